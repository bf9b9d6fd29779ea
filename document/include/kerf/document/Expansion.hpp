#pragma once
// How much a feature tree expands to once arrays and mirrors repeat their
// child: the work every evaluation, compilation and cut list does grows with
// these counts, not with the number of nodes. Arithmetic saturates at
// UINT64_MAX instead of wrapping, so a count like [4, 2^62, 1] can never come
// out small.

#include "kerf/document/Node.hpp"

#include <cstdint>

namespace kerf {

struct Expansion {
    std::uint64_t primitiveCopies = 0;    // primitive instances after arrays and mirrors
    std::uint64_t profilePointCopies = 0; // extrude profile points over every instance
};

/// The node's expansion; hidden nodes count when `includeHidden`, else they
/// (and everything below them) count as nothing.
Expansion expansionOf(const Node& node, bool includeHidden);

/// a * b and a + b, saturating at UINT64_MAX.
std::uint64_t saturatingMultiply(std::uint64_t a, std::uint64_t b);
std::uint64_t saturatingAdd(std::uint64_t a, std::uint64_t b);

/// The number of copies an array makes: the product of its counts, saturating.
std::uint64_t arrayCopies(const ArrayParams& p);

} // namespace kerf

#include "kerf/document/Expansion.hpp"
#include "kerf/document/NodeTypes.hpp"

#include <algorithm>
#include <limits>

namespace kerf {

std::uint64_t saturatingMultiply(std::uint64_t a, std::uint64_t b)
{
    std::uint64_t r = 0;
    if (__builtin_mul_overflow(a, b, &r)) return std::numeric_limits<std::uint64_t>::max();
    return r;
}

std::uint64_t saturatingAdd(std::uint64_t a, std::uint64_t b)
{
    std::uint64_t r = 0;
    if (__builtin_add_overflow(a, b, &r)) return std::numeric_limits<std::uint64_t>::max();
    return r;
}

std::uint64_t arrayCopies(const ArrayParams& p)
{
    std::uint64_t copies = 1;
    for (const std::int64_t c : p.count) copies = saturatingMultiply(copies, std::uint64_t(std::max<std::int64_t>(c, 1)));
    return copies;
}

// Recursion depth: the tree's depth, which the loader bounds (limits::kMaxNestingDepth).
Expansion expansionOf(const Node& node, bool includeHidden)
{
    if (!node.visible && !includeHidden) return {};
    if (isPrimitive(node.type)) {
        std::uint64_t points = 0;
        for (const FieldSpec& f : nodeTypeSpec(node.type).fields)
            if (f.shape == FieldShape::Points) points += f.pointsIn(node).size();
        return {1, points};
    }
    Expansion sum;
    for (const auto& c : node.children) {
        const Expansion e = expansionOf(c, includeHidden);
        sum.primitiveCopies = saturatingAdd(sum.primitiveCopies, e.primitiveCopies);
        sum.profilePointCopies = saturatingAdd(sum.profilePointCopies, e.profilePointCopies);
    }
    std::uint64_t factor = 1;
    if (node.type == NodeType::Mirror) factor = 2;
    if (node.type == NodeType::Array) factor = arrayCopies(node.as<ArrayParams>());
    return {saturatingMultiply(sum.primitiveCopies, factor), saturatingMultiply(sum.profilePointCopies, factor)};
}

} // namespace kerf

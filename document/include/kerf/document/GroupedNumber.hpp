#pragma once
// Counts as people read them in messages: the document's refusals and the
// commands' reports write them the same way.

#include <cstdint>
#include <string>

namespace kerf {

/// Thousands separated by commas: grouped(1234567) = "1,234,567".
std::string grouped(std::uint64_t n);

} // namespace kerf

#pragma once
// Parses a document's JSON text in one pass and in time linear in its size,
// refusing, while it parses, what later code could not take safely:
//  - nesting deeper than limits::kMaxJsonDepth, and feature-tree nodes nested
//    deeper than limits::kMaxNestingDepth (everything that walks the tree
//    afterwards may recurse that deep and no deeper);
//  - a key repeated in one object (readers disagree on which one counts);
//  - numbers too large for a double, marked so that the reader can refuse
//    them naming the node and the field (MarkedNumbers).
// The parser itself (nlohmann's SAX parser) keeps its own explicit stack and
// never recurses. Objects are built by appending, never by a lookup per key,
// so an object with a million keys costs a million steps, not 10^12.

#include "kerf/document/Node.hpp" // Json

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace kerf::detail {

/// Why the text was refused: `nodeId` and `field` as close as the parser can
/// tell (the innermost enclosing node whose id it has seen).
struct JsonRefusal {
    std::string nodeId;
    std::string field;
    std::string reason;
};

/// The text of a number token that overflows a double ("1e999") is replaced
/// by a string that starts with this marker and ends with the token.
inline constexpr std::string_view kNonFiniteMarker = "\x01kerf-non-finite-number:";

/// Parses `text`. Returns the value, or sets `refusal` and returns nothing.
/// `markedNumbers` tells whether any number was replaced by a marker.
std::optional<Json> parseBoundedJson(std::string_view text, JsonRefusal& refusal, bool& markedNumbers);

} // namespace kerf::detail

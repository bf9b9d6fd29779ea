#pragma once
// Paths to a number inside a node as the expressions and the messages spell
// them: a key ("radius"), keys joined by '.' ("transform.translate"), then
// indices ("size[0]", "profile[2][1]", "transform.translate[2]").

#include "kerf/document/Node.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace kerf::detail {

struct FieldPath {
    std::vector<std::string> keys;
    std::vector<std::size_t> indices;
};

/// Splits a path; nothing when it is malformed.
std::optional<FieldPath> parseFieldPath(std::string_view path);

/// The number at `path` in a node as it is in memory, or nothing when the
/// node has no such number.
std::optional<double> numberAt(const Node& n, std::string_view path);

/// The JSON value at `path` inside the node object `node`, or null.
const Json* jsonAt(const Json& node, const FieldPath& path);
Json* jsonAt(Json& node, const FieldPath& path);

} // namespace kerf::detail

#pragma once
// The numbers of a document's features that an expression can refer to, as
// it spells them ("panel.size[2]", "hole.radius",
// "hole.transform.translate[0]"): what the property fields offer while a
// reference is typed, so that a feature's id need not be known by heart.

#include "kerf/document/Document.hpp"

#include <string>
#include <vector>

namespace kerf {

/// One feature's single numbers and vector components, then its position's
/// coordinates (never empty); each resolves in an expression.
std::vector<std::string> referableNumbers(const Node& node);

/// Every feature's, in the tree's order.
std::vector<std::string> referableNumbers(const Document& doc);

} // namespace kerf

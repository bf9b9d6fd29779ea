#pragma once
// Where a node sits in the world and what it does to the part: the frames
// and facts the viewport's direct manipulation needs (a move gizmo placed on
// the feature, a drag turned into the feature's own translate, the ghost of
// a tool body that a difference takes away).
//
// "First instance": a node under an array or a mirror stands for several
// copies; these functions use the first (the array's copy at offset zero,
// the mirror's original). Moving it moves every copy alike.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Affine.hpp"
#include "kerf/document/Document.hpp"

#include <glm/vec3.hpp>

#include <string_view>
#include <vector>

namespace kerf::edit {

/// The nodes from the root down to `id` (the root first, the node last);
/// empty when there is no such node.
std::vector<const Node*> pathTo(const Document& doc, std::string_view id);

/// World from the node's parent frame (the product of its ancestors'
/// transforms). Throws std::invalid_argument for an unknown id.
Affine parentFrame(const Document& doc, std::string_view id);

/// World bounds of the node's first instance (empty for a hidden node).
Aabb firstInstanceBounds(const Document& doc, std::string_view id);

/// Moves the node by `worldDelta` (mm, world axes): its translate changes by
/// the same displacement expressed in its parent's frame, so the feature
/// moves exactly as dragged whatever its ancestors' rotations; a coordinate
/// the move changes loses its expression (it is the dragged number now).
/// Throws std::invalid_argument for an unknown id.
void moveNodeInWorld(Document& doc, std::string_view id, const glm::dvec3& worldDelta);

/// The part of `worldDelta` (mm, world axes) that moves the node without
/// touching a coordinate of its translate set by an expression: those stay
/// (the expression is the design's intent: a drag must not replace it
/// without a word). `held`, when given, receives the local axes held
/// (0 = x, 1 = y, 2 = z) that the move would have changed.
/// Throws std::invalid_argument for an unknown id.
glm::dvec3 moveKeepingExpressions(const Document& doc, std::string_view id, const glm::dvec3& worldDelta,
                                  std::vector<int>* held = nullptr);

/// Whether the node's material is taken away from the part: it lies under a
/// difference's tools (children after the first visible one) an odd number
/// of times on the way up (a hole; a plug inside a hole is material again).
bool isSubtracted(const Document& doc, std::string_view id);

/// The document with only this node's own shape: every ancestor becomes a
/// union of the one child on the path (its transform kept; arrays and
/// mirrors stay, so every copy is there), the node and its path visible.
/// For drawing a tool body that the part itself does not show.
Document documentOfNodeAlone(const Document& doc, std::string_view id);

/// What an export of documentOfNodeAlone holds, said to the person:
/// "Side L alone", "Side L alone, with every copy of the mirror above it",
/// "Pin hole alone, as a solid: it is a cutter (the part has its shape cut
/// away)". For the export's report.
std::string describeFeatureAlone(const Document& doc, std::string_view id);

/// The id of the feature a person names: its id, else its name when one
/// feature has it. Throws std::invalid_argument saying why not (no such
/// feature; a name several features share, with their ids).
std::string featureNamed(const Document& doc, std::string_view idOrName);

} // namespace kerf::edit

#pragma once
// Where a feature added from the toolbar, the Add menu or the tree's context
// menu goes, and what it starts with: the editing rule the desktop
// application applies, Qt-free and tested on its own (DocumentEditsTest).
//
// - A new primitive rests on the ground grid (its lowest point at z = 0 of
//   its parent's frame), centred on the Z axis; one added to a difference
//   after its body (a tool: a hole, a groove) is centred on the body's top
//   face instead, half above it, so that it cuts where the board is.
// - A primitive goes into the selected boolean, into the selected offset,
//   shell, array or mirror when it has room, and otherwise right after the
//   selected feature; with nothing selected, at the end of the root (a root
//   that takes no more children, or would not take it as material, an
//   intersection or a difference, is first wrapped under a union).
// - A primitive added to an offset, shell, array or mirror whose only child
//   is still the box it was given as a placeholder replaces that box.
// - An operation added while one feature (not the root) is selected puts
//   that feature under it: select a leg, press Array, get an array of legs.
//   Otherwise it goes where a primitive would, with a box to act on (the
//   placeholder), so the part stays valid.

#include "kerf/document/Document.hpp"

#include <optional>
#include <string>
#include <vector>

namespace kerf::edit {

/// Adds a feature of `type` by the rules above, `selection` being the ids
/// selected in the editor; returns the new feature's id. Throws
/// std::invalid_argument (a sentence) when the tree has no place for it; the
/// document is then unchanged.
std::string addFeature(Document& doc, NodeType type, const std::vector<std::string>& selection);

/// The placeholder box of an offset, shell, array or mirror: its only child
/// when that is still the box addFeature gave it (its id, the operation's id
/// with "-box", and default parameters); empty when there is none.
std::string placeholderOf(const Document& doc, const std::string& operationId);

/// A primitive that rests on the grid (its lowest point at z = 0 of its
/// parent's frame, unrotated) keeps resting on it when an edit of its own
/// parameters changes its height: a board laid on the bench and made
/// thinner stays on the bench. Adjusts `after`'s translate z; leaves it
/// alone when the edit moved the node itself, or it did not rest there.
/// So does an edit of its rotation alone (a leg turned to lie along the
/// bench lies on it), by its bounds in the parent's frame.
/// A height set by an expression (a box's Size Z "=thickness", a cylinder's
/// Height) places the resting primitive by one too: translate z becomes
/// "thickness/2", which follows the parameter; an expression this rule
/// wrote is rewritten as the height's changes, and goes when the height
/// becomes a number.
void keepResting(const Node& before, Node& after);

/// The expression for translate z that keeps `n` (unrotated) resting on the
/// grid as its height's expression changes: "thickness/2" for a box whose
/// Size Z is "thickness", "(a + b)/2", a sphere's radius as it is; nothing
/// where the height is a number or the primitive has no such field.
std::optional<std::string> restingExpression(const Node& n);

} // namespace kerf::edit

#pragma once
// Conservative bounding boxes of feature-tree nodes, propagated through
// transforms and every operation (blend, offset, shell, array, mirror).
//
// The bound is for the sublevel set {p : f(p) < margin} of the node's field,
// not just for its solid (margin 0): the smooth union of fields a and b is
// below c only where min(a, b) < c + k/4, so blends reach margin + k/4 into
// their children, and offsets reach margin + distance. Editors use margins
// to find the region an edit can change.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Affine.hpp"
#include "kerf/document/Document.hpp"

#include <string>
#include <unordered_map>
#include <vector>

namespace kerf {

/// Bounds of {f < margin} for a node in its parent's frame (its own transform
/// applied). Hidden nodes and operations with no visible child are empty.
Aabb nodeBounds(const Node& node, double margin = 0.0);

/// World-frame bounds of every visible node, over all of its instances (array
/// copies, mirror images). Keys are node ids.
std::unordered_map<std::string, Aabb> worldBoundsOfNodes(const Document& doc, double margin = 0.0);

/// The part's bounds: the root's bounds clipped by settings.bounds.
Aabb partBounds(const Document& doc);

/// The tools of differences that cut nothing: their bounds (every copy)
/// clear of the bounds of what they are cut from, so that they remove
/// nothing from it, for certain. A dowel hole moved off its board is one;
/// the part and its file are then missing the hole without a word.
/// Blended differences (whose tools round what is near) and hidden tools
/// are left out. Ids, in tree order.
std::vector<std::string> toolsCuttingNothing(const Document& doc);
/// Those tools in a sentence for people ("the cylinder 'hole2' cuts nothing:
/// it lies clear of Side panel"), the first three named; "" when none.
std::string describeToolsCuttingNothing(const Document& doc);

} // namespace kerf

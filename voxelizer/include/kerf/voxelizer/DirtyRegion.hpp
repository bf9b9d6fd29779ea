#pragma once
// Where an edit can change the voxels: for every node that changed between
// two versions of a document, its old and new world bounds of {f < margin}
// (blends of its ancestors widen them, see NodeBounds.hpp). A populated
// voxel's corners lie within a voxel diagonal of the surface, so a margin of
// a diagonal covers every stored sample the edit can reach.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/voxelizer/GridLayout.hpp"

#include <vector>

namespace kerf {

struct DirtyRegion {
    bool everything = false;   // settings or the root's frame changed: rebuild all
    bool geometryChanged = false;
    std::vector<Aabb> boxes;
};

DirtyRegion dirtyRegion(const Document& before, const Document& after, double margin);

/// The tiles of `layout` that the region's boxes reach, in increasing order
/// (every tile when it says everything).
std::vector<long> tilesReached(const DirtyRegion& region, const GridLayout& layout);

/// The tiles whose voxels at the layout's full depth an edit from `before`
/// to `after` can change (a margin of two voxel diagonals: a stored distance
/// saturates at two voxel edges).
std::vector<long> tilesAnEditReaches(const Document& before, const Document& after, const GridLayout& layout);

} // namespace kerf

#pragma once
// Assembles the tiles' shares into one mesh: global vertex numbers in tile
// order (so the result does not depend on threads), foreign vertex
// references resolved through their owners' edge tables, then a copy that
// frees each tile's share as it goes. Empties `shares`.

#include "TileShares.hpp"

#include "kerf/mesher/Mesh.hpp"
#include "kerf/mesher/MeshPart.hpp"

#include <tbb/task_arena.h>

namespace kerf::mesher {

/// Throws std::logic_error if a foreign vertex has no owner (a broken flood
/// fill: never expected), std::runtime_error past 2^32 vertices. Adds the
/// tiles' counters to `stats`. `normals` receives each vertex's unit normal
/// (0 for feature vertices).
Mesh mergeTiles(TileShares& shares, tbb::task_arena& arena, MeshStats& stats, std::vector<glm::dvec3>& normals);

} // namespace kerf::mesher

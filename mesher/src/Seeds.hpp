#pragma once
// Reads the populated voxels of a tile's contree (docs/voxel-format.md): the
// mesher's candidate cells. Walks the node masks only; corner samples are not
// decoded (VoxelQuery's forEachVoxel would decode eight normals per voxel).

#include "kerf/voxelizer/TileData.hpp"

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

namespace kerf::mesher {

/// Calls `visit` with the tile-local integer coordinates (0 .. 4^levels - 1)
/// of every populated voxel of a surface tile.
void forEachSeed(const TileData& tile, const std::function<void(const glm::ivec3&)>& visit);

} // namespace kerf::mesher

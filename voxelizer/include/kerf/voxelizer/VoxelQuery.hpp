#pragma once
// Random access into a tile's contree: the populated voxel at integer voxel
// coordinates, with its eight corner samples decoded. Used by the reference
// tracer, the mesher and the tests.

#include "kerf/voxelizer/TileData.hpp"

#include <glm/vec3.hpp>

#include <functional>
#include <optional>

namespace kerf {

struct VoxelCorners {
    float distance[8]; // mm, corner q = x + 2y + 4z
    glm::vec3 normal[8];
    std::uint32_t feature[8];
};

/// The populated voxel at `voxel` (0 <= x, y, z < 4^tile.levels) of a tile,
/// or nothing. `voxelSize` in mm decodes distances.
std::optional<VoxelCorners> findVoxel(const TileData& tile, const glm::ivec3& voxel, float voxelSize);

/// Depth (in levels) of the deepest existing node on the path to `voxel`:
/// tile.levels when the voxel is populated, less when an ancestor cell is
/// empty. Lets traversals skip the whole empty cell at once.
int populatedDepth(const TileData& tile, const glm::ivec3& voxel);

/// Calls `visit` for every populated voxel of a tile, with its integer voxel
/// coordinates (0 .. 4^levels - 1) and decoded corners.
void forEachVoxel(const TileData& tile, float voxelSize,
                  const std::function<void(const glm::ivec3& voxel, const VoxelCorners& corners)>& visit);

} // namespace kerf

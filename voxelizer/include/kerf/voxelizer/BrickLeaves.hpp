#pragma once
// Brick leaves: the voxels of a tile grid re-encoded as small dense bricks
// of distance samples, for a renderer that lets the texture unit
// interpolate them (../shared/seeds/hierarchical-evaluator-and-brick-renderer.md).
//
// A brick covers kBrickCells^3 voxels (two leaves of the contree along each
// axis; fewer in a tile shallower than two levels) and holds its
// kBrickSamples^3 lattice points: the cells' corners, the brick's faces
// included (the one-sample apron the seam needs: trilinear filtering inside
// a brick then never reads a neighbour's samples). The tile grid and the
// interval pruning above the leaves are the contree's, unchanged: a brick
// exists where the contree has a populated voxel.
//
// Every corner of a populated voxel carries the contree vertex's very code
// (distance snorm16 in units of kDistanceRange voxel edges, normal, feature),
// so hardware trilinear filtering in a populated voxel interpolates what
// the reference tracer does. The other samples (corners of cells with no
// sign change only) are not stored in the contree: they take the sign of a
// neighbour across such a cell, at the end of the range, with no normal
// and the neighbour's feature.
// Such a cell has no crossing either way, so the surface is the contree's.
//
// Built from FlatVoxelBuffers, so from either voxelizer (CPU or GPU layout).

#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace kerf {

inline constexpr int kBrickCells = 8;
inline constexpr int kBrickSamples = kBrickCells + 1;
inline constexpr int kBrickSampleCount = kBrickSamples * kBrickSamples * kBrickSamples;

struct Brick {
    glm::dvec3 min{0.0};      // world mm: the brick's minimum corner
    double voxelMm = 0.0;     // edge of its voxels
    int cells = kBrickCells;  // voxels along each edge (samples: cells + 1)
    std::uint32_t tile = 0;   // its tile's index in the grid
};

struct BrickLeaves {
    std::vector<Brick> bricks;
    /// Per brick kBrickSampleCount samples, x fastest, then y, then z:
    /// sample (x, y, z) of brick b at b * kBrickSampleCount + x + 9 (y + 9 z).
    std::vector<std::int16_t> distance;    // snorm16, units of voxel::kDistanceRange voxel edges
    std::vector<std::uint32_t> normal;     // RGBA8 snorm: x, y, z, 0 (zero where unknown)
    std::vector<std::uint16_t> feature;    // the contree vertex's feature (a neighbour's where unknown)

    std::size_t bytes() const
    {
        return bricks.size() * sizeof(Brick) + distance.size() * sizeof(std::int16_t) +
               normal.size() * sizeof(std::uint32_t) + feature.size() * sizeof(std::uint16_t);
    }
    /// The bytes a GPU holds: the three samples of each brick and a 32-byte
    /// instance record.
    std::size_t deviceBytes() const { return bricks.size() * (std::size_t(kBrickSampleCount) * 8 + 32); }
    static std::size_t sampleIndex(std::size_t brick, int x, int y, int z)
    {
        return brick * kBrickSampleCount + std::size_t(x + kBrickSamples * (y + kBrickSamples * z));
    }

    static BrickLeaves fromVoxels(const FlatVoxelBuffers& voxels);
};

} // namespace kerf

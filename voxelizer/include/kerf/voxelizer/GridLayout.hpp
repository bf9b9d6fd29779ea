#pragma once
// The tile grid over a part's bounding box: cubic tiles of edge
// voxelSize * 4^levels, each holding a contree `levels` deep, so that the
// finest voxels have exactly the requested feature size (the grid is rounded
// up to whole tiles, the feature size is never rounded).

#include "kerf/document/Aabb.hpp"

#include <glm/vec3.hpp>

#include <string>

namespace kerf {

struct GridLimits {
    /// Most tiles the grid may have: past this, deeper contrees are used.
    long maxTiles = 32 * 32 * 32;
    /// Deepest contree (voxel::kMaxLevels at most).
    int maxLevels = 10;
    /// Shallowest contree: a level-1 tile holds only 64 voxels, so the
    /// per-tile cost (an interval test of the whole tape) would dominate,
    /// and a coarse pass needs a level to drop.
    int minLevels = 2;
};

/// The feature size the program uses when a document sets none: about a
/// thousandth of the part's largest extent, rounded down to 1, 2 or 5 times a
/// power of ten (0.5 mm for a chair). 1 mm for an empty or unbounded box.
double defaultFeatureSize(const Aabb& partBounds);

struct GridLayout {
    glm::dvec3 origin{0.0};  // world position of the grid's minimum corner
    glm::ivec3 dims{0};      // tiles along x, y, z
    double tileSize = 0.0;   // mm
    int levels = 0;          // contree levels below a tile: voxel = tileSize / 4^levels
    double voxelSize = 0.0;  // mm, the finest voxel
    /// Set when the requested feature size needed more levels than allowed:
    /// voxels are then larger than asked, and this says so.
    std::string note;

    long tileCount() const { return long(dims.x) * dims.y * dims.z; }
    bool empty() const { return tileCount() == 0; }
    long tileIndex(const glm::ivec3& t) const { return t.x + long(dims.x) * (t.y + long(dims.y) * t.z); }
    glm::ivec3 tileCoord(long index) const
    {
        return {int(index % dims.x), int((index / dims.x) % dims.y), int(index / (long(dims.x) * dims.y))};
    }
    Aabb tileBox(const glm::ivec3& t) const
    {
        const glm::dvec3 lo = origin + glm::dvec3(t) * tileSize;
        return {lo, lo + glm::dvec3(tileSize)};
    }
    /// The grid's box; empty for a grid of no tiles (an empty part), not a
    /// point at its origin (the viewport sized the ground grid to 4 mm by it).
    Aabb bounds() const { return empty() ? Aabb::empty() : Aabb{origin, origin + glm::dvec3(dims) * tileSize}; }
    /// Voxel edge at a contree depth of `lv` levels.
    double voxelSizeAt(int lv) const;

    bool operator==(const GridLayout& o) const
    {
        return origin == o.origin && dims == o.dims && tileSize == o.tileSize && levels == o.levels;
    }

    /// Chooses the grid for a part: the fewest contree levels such that the
    /// tile count stays within the limits. An empty box gives an empty grid.
    static GridLayout choose(const Aabb& partBounds, double featureSize, const GridLimits& limits = {});
};

} // namespace kerf

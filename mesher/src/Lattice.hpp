#pragma once
// The export lattice: cell corners at origin + h * (i, j, k) for integer
// (i, j, k) ("global lattice coordinates"), cut into mesher tiles of n^3
// cells (the voxelizer's tiles, or cubes of 64 cells inside larger ones) and
// tape blocks of b^3 cells inside them. Keys pack tile-local coordinates
// into 64-bit integers for the hash tables.
//
// Why mesher tiles are at most 64 cells across: a tile's tables (edges,
// examined cells, corner values) are looked up in scattered order; a
// voxelizer tile 256 cells across has tables of tens of megabytes and every
// lookup misses the cache (measured: per-cell cost doubles from 0.5 mm to
// 0.25 mm on the chair when tiles go from 64 to 256 cells).

#include "FlatHash.hpp"

#include "kerf/voxelizer/GridLayout.hpp"

#include <glm/ext/vector_int3_sized.hpp>
#include <glm/vec3.hpp>

#include <cstdint>

namespace kerf::mesher {

using I3 = glm::i64vec3;

/// floor(a / b) for b > 0.
inline std::int64_t floorDiv(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
inline I3 floorDiv(const I3& a, std::int64_t b) { return {floorDiv(a.x, b), floorDiv(a.y, b), floorDiv(a.z, b)}; }

/// Tile-local coordinates take 20 bits (a tile is at most 64 cells across;
/// the room is spare).
inline constexpr int kLocalBits = 20;
inline constexpr std::int64_t kMaxTileCells = 64;

struct Lattice {
    glm::dvec3 origin{0.0}; // world position of lattice point (0, 0, 0): the grid's corner
    double h = 0.0;         // cell edge, mm
    std::int64_t n = 0;     // cells along a mesher tile's edge (divides the voxelizer's)
    std::int64_t b = 0;     // cells along a tape block's edge (divides n)
    I3 dims{0};             // mesher tiles along x, y, z covering the voxelizer's grid

    static Lattice fromLayout(const GridLayout& g)
    {
        Lattice l;
        l.origin = g.origin;
        l.h = g.voxelSize;
        const std::int64_t voxelizerTile = std::int64_t(1) << (2 * g.levels);
        l.n = voxelizerTile < kMaxTileCells ? voxelizerTile : kMaxTileCells;
        l.b = l.n < 16 ? l.n : 16;
        l.dims = I3(g.dims) * (voxelizerTile / l.n);
        return l;
    }

    /// World position of a lattice point. The one formula used everywhere, so
    /// that a point's coordinates never depend on who computes them.
    glm::dvec3 position(const I3& p) const
    {
        return {origin.x + h * double(p.x), origin.y + h * double(p.y), origin.z + h * double(p.z)};
    }
    /// A point on the edge from p along `axis`, at parameter t in [0, 1].
    glm::dvec3 position(const I3& p, int axis, double t) const
    {
        glm::dvec3 q = position(p);
        q[axis] = origin[axis] + h * (double(p[axis]) + t);
        return q;
    }
    /// The closed box of the cells [lo, lo + size)^3 (lattice coordinates).
    Aabb box(const I3& lo, std::int64_t size) const { return {position(lo), position(lo + I3(size))}; }

    I3 tileOf(const I3& cellOrPoint) const { return floorDiv(cellOrPoint, n); }
    I3 blockOf(const I3& point) const { return floorDiv(point, b); }
    bool inGrid(const I3& tile) const
    {
        return tile.x >= 0 && tile.y >= 0 && tile.z >= 0 && tile.x < dims.x && tile.y < dims.y && tile.z < dims.z;
    }
};

/// Tile-local coordinates (each in [0, 2^20)) packed into 60 bits.
inline std::uint64_t localKey(const I3& local)
{
    return std::uint64_t(local.x) | std::uint64_t(local.y) << kLocalBits | std::uint64_t(local.z) << (2 * kLocalBits);
}
inline I3 fromLocalKey(std::uint64_t key)
{
    const std::uint64_t m = (std::uint64_t(1) << kLocalBits) - 1;
    return {std::int64_t(key & m), std::int64_t(key >> kLocalBits & m), std::int64_t(key >> (2 * kLocalBits) & m)};
}
/// A lattice edge: its lower end's tile-local coordinates and its axis.
inline std::uint64_t edgeKey(const I3& localLower, int axis)
{
    return localKey(localLower) | std::uint64_t(axis) << (3 * kLocalBits);
}

/// Hash for edge keys that keeps the edges of a 2 x 2 x 2 group of lattice
/// points (all three axes) in 32 consecutive table slots: cells are meshed in
/// contree order, so consecutive lookups share cache lines instead of
/// missing on each (a large tile's edge table is tens of megabytes).
struct EdgeHash {
    std::uint64_t operator()(std::uint64_t key) const
    {
        constexpr std::uint64_t kFineBits = 1 | std::uint64_t(1) << kLocalBits | std::uint64_t(1) << (2 * kLocalBits) |
                                            std::uint64_t(3) << (3 * kLocalBits);
        const std::uint64_t fine = (key & 1) | (key >> kLocalBits & 1) << 1 | (key >> (2 * kLocalBits) & 1) << 2 |
                                   (key >> (3 * kLocalBits)) << 3;
        return (mixKey(key & ~kFineBits) << 5) + fine;
    }
};

/// Tiles (global tile coordinates within +-2^20) packed into 63 bits; the
/// order of keys is the order of GridLayout::tileIndex for tiles in the grid.
inline std::uint64_t tileKey(const I3& t)
{
    const std::int64_t o = std::int64_t(1) << 20;
    return std::uint64_t(t.x + o) | std::uint64_t(t.y + o) << 21 | std::uint64_t(t.z + o) << 42;
}

} // namespace kerf::mesher

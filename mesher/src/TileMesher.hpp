#pragma once
// One tile's share of the export mesh: the cells it examined, the vertices it
// owns, the triangles of its cells, and the flood-fill requests it sends to
// other tiles. Built by TileMesher::process, once per flood-fill round in
// which the tile has cells to examine; merged by MeshPart.
//
// Ownership. Cell c belongs to tile floor(c / N). A lattice edge belongs to
// the tile of its lower end, and only that tile computes its vertex; the
// cell whose lower corner is that end is in the same tile and uses the edge,
// so the owner always meshes it (the flood fill meshes all four cells around
// a sign-changing edge once any is). Other tiles' cells refer to it as a
// foreign vertex, resolved at the merge: no duplicates, no cracks. A cell
// polygon that cannot be triangulated under Triangulate.hpp's face rule gets
// a vertex of its own inside the cell (owned by the cell's tile, never
// shared), and a fan around it.
//
// Memory per surface cell: its vertex and triangles (about 24 + 2 x 12
// bytes, in chunks that never copy), an edge-table slot (12 bytes at 35 to
// 70% load) and a bit in the examined-cell bricks. Corner values live only
// for the round.

#include "CellSet.hpp"
#include "ChunkedVector.hpp"
#include "FlatHash.hpp"
#include "Lattice.hpp"
#include "LatticeTapes.hpp"

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/mesher/EdgeRoots.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"

#include <array>
#include <functional>
#include <vector>

namespace kerf::mesher {

/// A vertex reference inside a tile: an owned vertex index, or kForeign | i
/// for the tile's i-th foreign vertex.
inline constexpr std::uint32_t kForeign = 0x80000000u;
/// Marks a cell key that came from the voxelizer (statistics only).
inline constexpr std::uint64_t kSeedFlag = std::uint64_t(1) << 63;

struct ForeignVertex {
    std::uint8_t ownerStep = 0;     // bit a set: the owner is the next tile up along axis a
    std::uint64_t ownerEdgeKey = 0; // the edge's key in the owner tile
    glm::dvec3 position{0.0};       // computed here as well, for triangulation choices only
};

struct TileCounters {
    std::uint64_t seeds = 0, seedsNotMeshed = 0, cellsMeshed = 0, cellsFromFloodFill = 0, crossTileRequests = 0;
    std::uint64_t pointEvaluations = 0, rootEvaluations = 0, centreVertices = 0;
};

using Triangle = std::array<std::uint32_t, 3>;

struct TileShare {
    explicit TileShare(const I3& t) : tile(t) {}
    I3 tile;
    CellSet processed;                      // cells already examined
    FlatMap<std::uint32_t, EdgeHash> edges; // edge key (tile-local lower end, axis) -> vertex reference
    ChunkedVector<glm::dvec3> vertices;
    std::vector<ForeignVertex> foreign;
    ChunkedVector<Triangle> triangles;        // vertex references
    std::vector<I3> outbox;                   // global cells of other tiles to examine (this round)
    std::vector<std::uint64_t> inbox;         // tile-local keys other tiles asked for (next round)
    std::vector<std::uint32_t> foreignGlobal; // at the merge: foreign vertex -> global index
    TileCounters counters;
};

/// Per-thread scratch memory, reused across tiles.
struct TileScratch {
    TileScratch(const Tape& tape, const Lattice& lattice) : tapes(tape, lattice) {}
    struct Pending {
        std::uint64_t block; // tile-relative block key
        std::uint64_t point; // tile-local point key
        std::uint32_t index; // into pointValue
    };
    LatticeTapes tapes;
    PointEvaluator<double> points;
    EdgeRootFinder roots;
    TileBuildScratch build;
    // Corner values of this round; pointIndex maps a point key to its index
    // in pointValue within one slice of a wave.
    FlatMap<std::uint32_t> pointIndex;
    std::vector<double> pointValue;
    std::vector<Pending> pending;
    std::vector<std::uint64_t> wave, next, meshed;
    std::vector<std::uint32_t> waveCorners, meshedCorners; // 8 pointValue indices per cell
    std::vector<double> x, y, z, f;
    std::vector<EdgeRootJob> jobs;
    std::vector<std::uint32_t> jobTarget;                          // vertex reference of each job
    std::vector<std::pair<std::uint64_t, std::uint32_t>> jobOrder; // (block key, job)
    std::vector<EdgeRootJob> groupJobs;
    std::vector<double> groupRoots;
    std::vector<std::uint32_t> polygonRefs;
    std::vector<std::uint8_t> polygonMasks, polygonSizes;
    std::vector<std::uint32_t> polygonCells; // index into meshed
};

class TileMesher {
public:
    TileMesher(const Tape& tape, const Lattice& lattice) : tape_(tape), lattice_(lattice) {}

    /// Examines `cells` (tile-local keys, kSeedFlag allowed) that the tile has
    /// not examined yet, floods through faces with a sign change (within the
    /// tile; requests for other tiles go to state.outbox) and meshes every
    /// cell found. Returns false when cancelled; the state is then unusable.
    bool process(TileShare& state, const std::vector<std::uint64_t>& cells, TileScratch& scratch,
                 const std::function<bool()>& cancelled) const;

private:
    void evaluateCorners(TileShare& state, TileScratch& s) const;
    void evaluatePending(TileShare& state, TileScratch& s) const;
    std::uint32_t vertexRef(TileShare& state, const I3& cell, int edge, const double* values, TileScratch& s) const;
    void meshCells(TileShare& state, TileScratch& s) const;
    void solveRoots(TileShare& state, TileScratch& s) const;
    std::uint32_t centreVertex(TileShare& state, const I3& cell, const double* values, const glm::dvec3* points,
                               int size, TileScratch& s) const;

    const Tape& tape_;
    Lattice lattice_;
};

} // namespace kerf::mesher

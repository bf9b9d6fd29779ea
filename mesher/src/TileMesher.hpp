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

#include "kerf/document/Progress.hpp"
#include "CellSet.hpp"
#include "ChunkedVector.hpp"
#include "FlatHash.hpp"
#include "HiddenDetail.hpp"
#include "Lattice.hpp"
#include "LatticeTapes.hpp"
#include "RegionTapes.hpp"

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/mesher/EdgeRoots.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"

#include <array>
#include <functional>
#include <optional>
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
    glm::dvec3 normal{0.0};         // likewise, for feature detection
};

/// How cells are meshed, beyond the lattice.
struct CellMeshing {
    /// Least distance of a vertex from a lattice point, as a fraction of the
    /// cell edge (EdgeRootFinder::setMargin).
    double edgeMargin = kEdgeMargin;
    /// A lattice value within this many mm of 0 is "on the surface": its
    /// side is taken from the field a little further along a fixed generic
    /// direction (see TileMesher::evaluatePending), so that exact (or
    /// rounding-level) zeros never decide a side. Set by the mesher from the
    /// cell size and the coordinates' magnitude.
    double zeroBand = 0.0;
    /// How far (mm) that direction is followed.
    double nudge = 0.0;
    /// Sharp features: a cell polygon whose vertex normals diverge gets a
    /// vertex where their tangent planes meet (FeaturePoint.hpp) when that
    /// point is inside the cell and within this many mm of the surface; 0
    /// disables feature vertices.
    double featureTolerance = 0.0;
    /// Search the voxelizer's seed cells without a sign change at their
    /// corners for detail thinner than a cell (HiddenDetail.hpp).
    bool findHiddenDetail = true;
};

struct TileCounters {
    std::uint64_t seeds = 0, seedsNotMeshed = 0, cellsMeshed = 0, cellsFromFloodFill = 0, crossTileRequests = 0;
    std::uint64_t pointEvaluations = 0, rootEvaluations = 0, centreVertices = 0, featureVertices = 0;
    std::uint64_t zeroCorners = 0; // lattice values that were (about) 0, given a side by the nudge
    std::uint64_t hiddenDetailSearches = 0, hiddenDetailCells = 0; // seed cells hiding material or a gap thinner than a cell (HiddenDetail.hpp)
    std::optional<HiddenDetailFound> thinnestHidden;
};

using Triangle = std::array<std::uint32_t, 3>;

/// A cell whose corners the voxelizer found on one side, near the surface
/// (QuietVoxel in TileBuilder.hpp): tile-local key and that side.
struct QuietCell {
    std::uint64_t key;
    bool inside;
};

struct TileShare {
    explicit TileShare(const I3& t) : tile(t) {}
    I3 tile;
    CellSet processed;                      // cells already examined
    FlatMap<std::uint32_t, EdgeHash> edges; // edge key (tile-local lower end, axis) -> vertex reference
    ChunkedVector<glm::dvec3> vertices;
    ChunkedVector<glm::dvec3> normals; // unit normal of each vertex; 0 for a feature vertex (a crease or corner)
    std::vector<ForeignVertex> foreign;
    ChunkedVector<Triangle> triangles;        // vertex references
    std::vector<I3> outbox;                   // global cells of other tiles to examine (this round)
    std::vector<std::uint64_t> inbox;         // tile-local keys other tiles asked for (next round)
    std::vector<std::uint32_t> foreignGlobal; // at the merge: foreign vertex -> global index
    TileCounters counters;
};

/// Per-thread scratch memory, reused across tiles.
struct TileScratch {
    TileScratch(const Tape& tape, const Lattice& lattice) : tapes(tape, lattice), near(tape, 4.0 * lattice.h) {}
    struct Pending {
        std::uint64_t block; // tile-relative block key
        std::uint64_t point; // tile-local point key
        std::uint32_t index; // into pointValue
    };
    LatticeTapes tapes;
    RegionTapes near; // around feature vertices (TileMesher::featureVertex)
    PointEvaluator<double> points;
    GradientEvaluator<double> gradients;
    EdgeRootFinder roots;
    TileBuildScratch build;
    HiddenDetailScratch hidden;
    std::vector<QuietVoxel> quietVoxels; // of the voxelizer tile being read
    // Corner values of this round; pointIndex maps a point key to its index
    // in pointValue within one slice of a wave.
    FlatMap<std::uint32_t> pointIndex;
    std::vector<double> pointValue;
    std::vector<Pending> pending;
    std::vector<std::uint64_t> wave, next, meshed;
    std::vector<std::uint32_t> waveCorners, meshedCorners; // 8 pointValue indices per cell
    std::vector<double> x, y, z, f, gx, gy, gz;
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
    TileMesher(const Tape& tape, const Lattice& lattice, const CellMeshing& meshing = {})
        : tape_(tape), lattice_(lattice), meshing_(meshing)
    {
    }

    /// Examines `cells` (tile-local keys, kSeedFlag allowed) that the tile has
    /// not examined yet, floods through faces with a sign change (within the
    /// tile; requests for other tiles go to state.outbox) and meshes every
    /// cell found. Returns false when cancelled; the state is then unusable.
    bool process(TileShare& state, const std::vector<std::uint64_t>& cells, TileScratch& scratch,
                 const Progress& work) const;

    /// Looks for detail thinner than a cell (HiddenDetail.hpp) in the quiet
    /// cells that the tile has not examined (a cell examined was meshed, or
    /// looked at by process as a seed without a sign change).
    void lookForHiddenDetail(TileShare& state, const std::vector<QuietCell>& cells, TileScratch& scratch) const;

private:
    void evaluateCorners(TileShare& state, TileScratch& s) const;
    void evaluatePending(TileShare& state, TileScratch& s) const;
    std::uint32_t vertexRef(TileShare& state, const I3& cell, int edge, const double* values, TileScratch& s) const;
    void meshCells(TileShare& state, TileScratch& s) const;
    void solveRoots(TileShare& state, TileScratch& s) const;
    std::uint32_t centreVertex(TileShare& state, const I3& cell, const double* values, const glm::dvec3* points,
                               int size, TileScratch& s) const;
    std::optional<std::uint32_t> featureVertex(TileShare& state, const I3& cell, const glm::dvec3* points,
                                               const glm::dvec3* normals, int size, TileScratch& s) const;
    void lookForHiddenDetail(TileShare& state, const I3& localCell, bool cornersInside, TileScratch& s) const;
    double sideOfZero(const Tape& tape, const glm::dvec3& relative, TileScratch& s) const;
    glm::dvec3 unitNormal(const Tape& tape, const glm::dvec3& world, TileScratch& s) const;

    const Tape& tape_;
    Lattice lattice_;
    CellMeshing meshing_;
};

} // namespace kerf::mesher

#pragma once
// Meshes a part for export: marching cubes on the exact field, closed and
// consistently oriented by construction.
//
// How (each step has its own file):
// 1. The part is voxelized tile by tile at the export feature size
//    (GridLayout::choose over the tape's bounds). The populated voxels of the
//    float contrees are only SEEDS: candidate cells (Seeds.hpp).
// 2. Every cell corner is recomputed in double from the exact evaluator
//    (LatticeTapes.hpp says how each lattice point gets one value, whoever
//    asks). A cell is meshed iff its corner signs differ (value < 0 is
//    inside; exactly 0 counts as outside, everywhere).
// 3. Flood fill: a meshed cell with a sign change on one of its faces has its
//    neighbour across that face meshed too, so float/double disagreements in
//    the seeds can never open a hole. Requests that cross into another tile
//    are exchanged between rounds until none is left.
// 4. Each meshed cell becomes closed polygons from its faces' segments
//    (CellPolygons.hpp: asymptotic decider on ambiguous faces, computed from
//    the face's four values only, so both cells of a face agree), with one
//    vertex per sign-changing lattice edge (EdgeRoots.hpp: root finding on the
//    exact field), shared through a global edge key, then triangulated
//    (Triangulate.hpp); the rare polygon that no diagonal may split gets a
//    vertex on the surface inside its cell and a fan around it.
// 5. Cells without a sign change but near the surface (the voxelizer's
//    quiet voxels) are searched for material or a gap thinner than a cell
//    lying between their corners (HiddenDetail.hpp); what is found is
//    reported with the feature size that resolves it (MeshStats).
// 6. With a tolerance: flat blocks become fans (PlanarFans.hpp), the mesh is
//    simplified to the tolerance (SimplifyToTolerance.hpp) and refined where
//    its triangles' samples stray further (ToleranceRefiner.hpp); last, the
//    lattice's own points of the part are measured against the mesh, and
//    where one lies beyond the tolerance the mesh is split there
//    (SurfaceCoverage.hpp), so that the tolerance holds both ways.
//
// Threading: the work runs in a oneTBB arena (options.threads); tiles are
// independent within a round, and the result does not depend on the number
// of threads (tiles are merged in a fixed order).
// Memory: proportional to the surface: per meshed cell, its vertices and
// triangles plus hash tables over surface cells and edges; nothing per volume
// cell. A tile's float contree lives only while its seeds are read.

#include "kerf/document/Progress.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/evaluator/Tape.hpp"
#include "kerf/mesher/Mesh.hpp"
#include "kerf/voxelizer/GridLayout.hpp"

#include <glm/ext/vector_int3_sized.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace kerf {

/// The tolerance of an export nobody set one for (kerf export, the export
/// dialog), in mm: half of the tenth of a millimetre that a router, a
/// printer or a hand plane reproduces, so the file never holds back the
/// workshop; and the plain marching-cubes mesh it replaces is hundreds of
/// megabytes at a part's own feature size (the side chair at 0.5 mm: 9.5 M
/// triangles, 474 MB; within 0.05 mm: 15 k triangles, 0.75 MB;
/// docs/benchmarks.md).
inline constexpr double kDefaultExportTolerance = 0.05;

/// The most mesher tiles (of up to 64 cells) the lattice has along an axis.
inline constexpr std::int64_t kMaxLatticeCellsPerAxis = std::int64_t(1) << 20;

/// Why the part cannot be meshed at `featureSize` at all, or nothing when it
/// can: more than kMaxLatticeCellsPerAxis mesher tiles along an axis. Says
/// the feature size that fits.
std::optional<std::string> partTooLongToMesh(const Aabb& partBounds, double featureSize);

/// How the simplification keeps the mesh from crossing itself: no triangle
/// may cross another or come within the file's rounding of one.
enum class CrossingGuard {
    /// Each cube of the parallel passes, and the last pass over the whole,
    /// is simplified unguarded and its result checked; where the check finds
    /// a pair, that cube (or pass) is simplified again guarded.
    Afterwards,
    /// Every collapse is guarded (about twice the simplification's time on
    /// the side chair; for comparison).
    EveryCollapse,
};

struct MeshOptions {
    /// Cell edge in mm: the smallest feature resolved. 0: the document's
    /// settings.feature_size (meshPart), which must then be set. The grid may
    /// coarsen it (MeshStats::note).
    double featureSize = 0.0;
    /// The largest distance (mm) allowed between the mesh and the exact
    /// surface: the marching-cubes mesh is simplified down to it (flat faces
    /// become a few large triangles) and refined where a triangle strays
    /// further (curved faces get the triangles they need). 0: the
    /// marching-cubes mesh as it is, every cell's triangles.
    double tolerance = 0.0;
    int threads = 0; // 0: every core
    /// Look for detail thinner than a cell between the cells' corners
    /// (MeshStats::hiddenDetailCells). Off only to measure what it costs.
    bool findHiddenDetail = true;
    /// Where the lattice sits, in cells: its planes are moved by this
    /// fraction of a cell from where the grid centred on the part would put
    /// them. A part drawn in round millimetres has its faces and edges on
    /// the planes and lines of a centred lattice of round cells, where the
    /// field is exactly zero at cell corners: the mesh stays closed there
    /// (EdgeRoots.hpp) but its sharp edges come out cut off by up to 0.29 of
    /// a cell and the simplified mesh left up to 0.22 mm over a 0.01 mm
    /// tolerance (a board 18 x 100 x 100 at 1 mm cells). The default is
    /// irrational in every axis, so that no round coordinate lies on a
    /// plane; 0 keeps the centred lattice (tests of the zero corners).
    /// With a tolerance: split the mesh where the part's own points lie
    /// further than the tolerance from it (SurfaceCoverage.hpp; the
    /// refinement's last step). Off only to measure what it costs; the
    /// part's side is measured and reported either way.
    bool coverPartPoints = true;
    glm::dvec3 latticeShift{0.20710678118654752, 0.36602540378443865, 0.11803398874989485};
    /// Where the file's coordinates start (MeshFile.hpp, fileOffsetFor: 3MF
    /// writes a part far from the origin next to its middle). The mesher
    /// keeps vertices apart, and its triangles a height, by float32's spacing
    /// at the coordinates as written, not as they lie in the world: 100 m
    /// away that spacing is 7.8 um, and kept from the world's origin it held
    /// vertices 0.06 mm off the lattice's points in a 3MF whose coordinates
    /// step by 2 nm, which left triangles over a 0.01 mm tolerance.
    glm::dvec3 fileOffset{0.0};
    CrossingGuard crossingGuard = CrossingGuard::Afterwards;
    /// With a tolerance: blocks of this many cells a side whose lattice
    /// triangles are one flat disk become a fan before the simplification,
    /// and the eighths of those that are not, down to blocks of
    /// planarFanSmallestCells (PlanarFans.hpp); 0: none. (The side chair at
    /// 0.5 mm: 4.3 of its 9.5 M lattice triangles, the export 22 -> 17 s on
    /// two cores; docs/benchmarks.md.)
    int planarFanCells = 16;
    int planarFanSmallestCells = 4;
    GridLimits limits;
    /// Testing only: keeps a voxelizer seed (global cell coordinates) when it
    /// returns true. Dropping seeds must not change the mesh of a connected
    /// surface: the flood fill finds the rest.
    std::function<bool(const glm::i64vec3& cell)> keepSeed;
};

/// What the mesher did, for reports and benchmarks.
struct MeshStats {
    double featureSize = 0.0; // mm, as requested
    double cellSize = 0.0;    // mm, as used (larger only when the grid had to coarsen)
    glm::dvec3 latticeOrigin{0.0}; // a lattice point (world mm): the others are at latticeOrigin + i * cellSize
    std::string note;         // why cellSize differs, if it does
    glm::ivec3 tiles{0};
    int levels = 0;
    std::uint64_t surfaceTiles = 0;   // tiles with seeds or meshed cells
    std::uint64_t seeds = 0;          // populated float voxels
    std::uint64_t seedsNotMeshed = 0; // seeds whose double corners agree in sign
    std::uint64_t cellsMeshed = 0;
    std::uint64_t cellsFromFloodFill = 0; // meshed cells that were not seeds
    std::uint64_t crossTileRequests = 0;  // flood-fill requests sent to another tile
    int rounds = 0;                       // flood-fill rounds (1 when no request crossed tiles)
    std::uint64_t pointEvaluations = 0;   // corner values
    std::uint64_t rootEvaluations = 0;    // evaluations spent placing vertices
    std::uint64_t centreVertices = 0;     // vertices inside cells (polygons the face rule cannot split)
    std::uint64_t featureVertices = 0;    // vertices on sharp edges and corners inside cells
    std::uint64_t featureFlips = 0;       // edges flipped to join feature vertices along sharp edges
    std::uint64_t zeroCorners = 0;        // lattice points on the surface, given a side by the nudge
    double edgeMargin = 0.0;              // mm: least distance of a vertex from a lattice point
    /// Detail thinner than a cell that no cell corner sees (a wall, a pin or
    /// a gap between two lattice points): it is missing from the mesh or in
    /// fragments. Cells where it was found, and the thinnest found.
    std::uint64_t hiddenDetailSearches = 0; // cells searched (near the surface, no sign change at the corners)
    std::uint64_t hiddenDetailCells = 0;
    double hiddenDetailThickness = 0.0;   // mm, across the thinnest (0 when none)
    glm::dvec3 hiddenDetailAt{0.0};       // where it is (world mm)
    bool hiddenDetailIsMaterial = true;   // material (else a gap)
    std::size_t latticeTriangles = 0;     // the marching-cubes mesh's triangles, before simplification
    std::uint64_t planarFans = 0;         // flat blocks of the lattice replaced by a fan (PlanarFans.hpp)
    std::uint64_t planarFanRemoved = 0;   // lattice triangles fewer by them
    std::uint64_t collapses = 0;          // edge collapses of the simplification
    std::uint64_t splits = 0;             // edges split to reach the tolerance
    std::uint64_t creaseSplits = 0;       // of which on sharp edges of the part
    double worstSample = 0.0;             // mm: the final mesh's largest sample distance (|f| / |grad f|)
    std::uint64_t trianglesOverTolerance = 0; // triangles the refinement could not bring within the tolerance
    double areaOverTolerance = 0.0;           // mm^2: their area (a woodworker judges a few square mm, not a count)
    glm::dvec3 worstSampleAt{0.0};        // world mm: the centroid of the triangle with the worst sample
    /// The part's side (SurfaceCoverage.hpp): points of the exact surface
    /// the lattice found (its vertices, and its feature vertices on sharp
    /// edges and corners), how many lie further than the tolerance from the
    /// mesh, the furthest's distance (0 when none does) and where it is.
    std::uint64_t partSamples = 0;
    std::uint64_t partSamplesBeyond = 0;
    std::uint64_t partPointSplits = 0; // splits the refinement made for points beyond the tolerance
    double worstPartSample = 0.0;
    glm::dvec3 worstPartSampleAt{0.0};
    std::uint64_t unfolds = 0;            // flips that turned a folded triangle the surface's way
    std::uint64_t retriangulations = 0;   // disks round a stuck triangle triangulated anew (ToleranceRefiner.hpp)
    /// Triangles left facing into the part at their centroid (a fold no
    /// flip undid; the mesh is closed and uncrossed all the same).
    std::uint64_t foldedTriangles = 0;
    /// CrossingGuard::Afterwards: cubes (and last passes) simplified
    /// unguarded and checked, and of those redone guarded.
    std::uint64_t crossingChecks = 0;
    std::uint64_t crossingRedos = 0;
    double simplifySeconds = 0.0;
    double refineSeconds = 0.0;
    double coverageSeconds = 0.0; // measuring the part's side
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    double seedSeconds = 0.0; // CPU seconds in the voxelizer, summed over threads
    double cellSeconds = 0.0; // CPU seconds meshing cells, summed over threads
    double mergeSeconds = 0.0;
    double seconds = 0.0; // wall clock, all of it
};

/// The feature size that resolves what the cells missed, or 0 when nothing
/// was missed. Hidden detail (stats.hiddenDetailCells): a feature size at
/// most half its thickness, rounded down to 1, 2 or 5 times a power of ten,
/// puts lattice points inside it along its whole length. Triangles beyond
/// the tolerance (stats.trianglesOverTolerance): a gap, a groove or a rounded
/// edge smaller than a cell, or a sharp edge whose crease a cell's triangles
/// cut across and no split could reach; half the cell, which resolves more
/// of a miss a woodworker would see (coarse cells on pin holes), though not
/// of the last few triangles over a fine tolerance (describeTrianglesOverTolerance).
double finerFeatureSize(const MeshStats& stats);

/// The one feature size the export's sentences advise (the hidden detail,
/// the triangles over the tolerance, the file that misses the part), so
/// that a report does not name two: the part's own (`ownFeatureSize`, the
/// document's; 0 when unknown) where coarser cells were asked for and it is
/// no coarser than the hidden detail is thin (a gap as wide as a cell has a
/// lattice plane inside it: the door frame's 0.5 mm gap at its own 0.5 mm),
/// else finerFeatureSize. 0 when there is nothing to advise.
double advisedFeatureSize(const MeshStats& stats, double ownFeatureSize);

/// The hidden detail (stats.hiddenDetailCells) in one sentence for people:
/// what, how thin, where, what it does to the mesh and the feature size that
/// resolves it (advisedFeatureSize); empty when there is none. For `kerf
/// export` and the export dialog alike.
std::string describeHiddenDetail(const MeshStats& stats, double ownFeatureSize = 0.0);

/// A mesh that came out empty at stats.cellSize, in one sentence for people:
/// "the part is empty at a feature size of X mm (thinner than a cell
/// everywhere: <the hidden detail and the feature size that resolves it>)";
/// where no hidden detail was found (detail under about a sixteenth of the
/// cell is not searched), a quarter of the smallest extent of `bounds` (the
/// part's), rounded down to 1, 2 or 5 times a power of ten, to try. For
/// `kerf export` and the export dialog alike.
std::string describeEmptyPart(const MeshStats& stats, const Aabb& bounds);

/// The triangles left beyond the tolerance (stats.trianglesOverTolerance)
/// in one sentence for people: how many, how far, where the worst is, why
/// and what to try. With hidden detail: the detail finer than the cells.
/// Without: thin triangles across a sharp or rounded edge, or where two
/// faces meet at a tangent, that no split can mend without folding a
/// neighbour; no feature size is advised (half the cells left as many or
/// more on the bundled examples at 0.01 mm, docs/benchmarks.md: a visible
/// miss gets its advice from describeVisibleMiss). Empty when none. For
/// `kerf export` and the export dialog. With hidden detail, the feature
/// size to try: advisedFeatureSize.
std::string describeTrianglesOverTolerance(const MeshStats& stats, double tolerance, double ownFeatureSize = 0.0);

/// How far a mesh may miss the exact surface before a woodworker would see
/// it in the workshop (more than a router or a printer hides, mm).
inline constexpr double kVisibleMiss = 0.1;

/// Where the written mesh misses the part by more than kVisibleMiss and
/// twice the tolerance (stats.worstSample, with triangles left over the
/// tolerance): one sentence that the file does not match the part, how far
/// off it is, what that does, and the feature size to export at
/// (advisedFeatureSize); empty when the miss is within that. A newcomer
/// exported a shelf side at 10 mm cells: 12 mm pin holes came out through
/// its show face, 3.4 mm off, and the result called it "a closed solid all
/// the same".
std::string describeVisibleMiss(const MeshStats& stats, double tolerance, double ownFeatureSize);

/// Whether the mesh misses the part as describeVisibleMiss says (a
/// triangle over the tolerance by more than kVisibleMiss and twice it).
bool missesVisibly(const MeshStats& stats, double tolerance);

/// The part's side of the tolerance (stats.partSamples, SurfaceCoverage):
/// how far the part's surface lies from the mesh, in one sentence for
/// people, for `kerf export` and the export dialog: "all N points of the
/// part's surface that the cells found lie within T mm of the mesh", or
/// how many lie beyond, the furthest and where. The triangles' samples measure
/// the other way; where a triangle cuts a sharp edge off, or a rounded face
/// bows out between its samples, only this one sees it. Empty when no
/// points were measured (no tolerance).
std::string describePartSide(const MeshStats& stats, double tolerance);

/// A tolerance so coarse that the part's features may lose their shape:
/// above the feature size (stats.cellSize, the smallest feature resolved)
/// and above kVisibleMiss. One sentence, or empty. (A tolerance of 5 mm
/// turned 5 mm pin holes into blobs without a word.)
std::string describeCoarseTolerance(const MeshStats& stats, double tolerance);

/// Meshes the document's part. An empty part gives an empty mesh. `work`
/// hears the fraction done; once it is cancelled the meshing stops soon
/// (within one contree node or one batch of cells) and returns nothing
/// (never half a mesh). Throws std::invalid_argument
/// when no feature size is given or set, std::runtime_error when the part is
/// too large for its feature size.
std::optional<Mesh> meshPart(const Document& doc, const MeshOptions& options = {}, const Progress& work = {},
                             MeshStats* stats = nullptr);

/// `options` with the document's feature size where they give none (what
/// meshPart meshes with). Throws std::invalid_argument where neither does.
MeshOptions withDocumentFeatureSize(const Document& doc, MeshOptions options);

/// The same for a compiled tape (world coordinates; evaluated where it is,
/// never rebased); options.featureSize must be positive.
std::optional<Mesh> meshTape(const Tape& tape, const MeshOptions& options, const Progress& work = {},
                             MeshStats* stats = nullptr);

} // namespace kerf

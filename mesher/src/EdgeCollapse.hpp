#pragma once
// Simplification by edge collapse under the error quadrics of the exact
// surface's tangent planes (Quadric.hpp).
//
// A collapse of edge (a, b) removes a and leaves b either where it is (a
// half-edge collapse) or at the point where the planes both stand for meet
// best (the quadric's minimizer: on a sharp edge of the part where they
// are planes of its two sides, at a corner for three). A moved vertex must
// land on the exact surface (|f| within limits.placement, checked on the
// field), so every vertex stays on the part; this is how sharp edges and
// corners come out square from a marching-cubes mesh that cut them off.
// The cost is the larger of the mean squared distances of the new position
// to the planes a stands for and to those b stands for; a collapse above the
// limit is never made, and one whose new triangles stray further than the
// tolerance from the exact surface (sampled) neither: simplification never
// takes the mesh out of tolerance. A moved vertex whose planes disagree by more than 30
// degrees is a feature vertex from then on (no normal).
//
// Topology is kept: a collapse is refused unless the edge's two triangles
// are the only ones its ends share (the link condition), and where it would
// leave a vertex of valence below 3. So a closed, oriented 2-manifold stays
// one, with its genus and its components. Geometry: no triangle may turn by
// more than the limit, lean away from the surface's normals at its
// vertices, or lose its area.
//
// Passes: each pass proposes, for every vertex, its four cheapest collapses
// within the limit (so that a refused one has a second); sorts
// the proposals; makes them in order, skipping any that touches a vertex an
// earlier collapse of the pass changed (its neighbourhood is then stale);
// and repeats until a pass finds (almost) nothing. No priority queue, no
// re-evaluation of neighbours: about a microsecond per collapse.
//
// Parallel: collapsePartitioned cuts space into cubes and simplifies each on
// its own thread; a vertex with triangles in two cubes is held still. Two
// calls with cubes shifted by half a cube, then one over the whole, reach
// what one call over the whole would, at a fraction of the time.
//
// Crossing: no triangle may cross another or come within limits.clearance
// of one (TriangleClearance.hpp). Either every collapse is checked against
// the triangles around it (the guard), or a whole cube's result is checked
// and, where the check finds a pair, the cube simplified again guarded
// (collapseEdgesCheckedAfter, CollapseLimits::checkAfterwards): the guard
// refuses almost nothing and costs half of the time.

#include "kerf/document/Progress.hpp"
#include "Quadric.hpp"
#include "SurfaceQueries.hpp"

#include <tbb/task_arena.h>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace kerf::mesher {

using Triangle = std::array<std::uint32_t, 3>;

/// Marks a removed triangle (in its first slot).
inline constexpr std::uint32_t kRemoved = 0xFFFFFFFFu;
inline constexpr std::uint32_t kObstacleVertex = 0xC0000000u;

struct CollapseMesh {
    std::vector<glm::dvec3> positions; // mm, relative to a nearby origin (Quadric.hpp)
    std::vector<Quadric> quadrics;
    std::vector<glm::dvec3> normals;   // the surface's unit normal at each vertex; 0 where it has none (a crease)
    std::vector<std::uint8_t> held;    // 1: never removed, never collapsed into
    std::vector<std::uint8_t> removed; // 1: collapsed away
    std::vector<Triangle> triangles;   // outward orientation; kRemoved in [0] once removed
    /// Triangles of the surrounding mesh that this part must not cross
    /// (the neighbouring cubes' of the partitioned collapse), read-only:
    /// their vertex indices are this part's where they share a vertex with
    /// it, else values no vertex of it has (kObstacleVertex and up).
    std::vector<Triangle> obstacles;
    std::vector<std::array<glm::dvec3, 3>> obstacleCorners;

    std::size_t liveTriangles() const;
    /// Drops removed triangles and the vertices no live triangle uses,
    /// keeping the order of those that stay (so that a collapser, which
    /// breaks ties by index, does what it would have done); the obstacles
    /// must be empty.
    void dropRemoved();
};

struct CollapseLimits {
    double maxMeanSquaredError = 0.0; // mm^2
    /// A vertex moved to a quadric's minimizer must lie this close (mm) to
    /// the surface; 0: half-edge collapses only.
    double placement = 0.0;
    /// Every triangle a collapse makes is sampled on the exact field
    /// (TriangleSamples.hpp) and must lie within this distance (mm); 0: no
    /// check. A collapse inside a plane (every vertex involved with the same
    /// normal, every new triangle in that plane) needs none: its triangles
    /// cover what the old ones did.
    double tolerance = 0.0;
    /// Only edges shorter than this (mm) collapse; 0: any.
    double maxEdgeLength = 0.0;
    /// No collapse makes an edge longer than this (mm); 0: any length. The
    /// partitioned collapse sets it to a quarter of its cube, so that every
    /// triangle that could meet a cube's lies in the cube or its 26
    /// neighbours (its obstacles).
    double maxEdgeAfter = 0.0;
    /// Off: topology only (link condition, valence). For edges so short
    /// that moving a vertex along one changes the surface by nothing that
    /// matters, but may turn a sliver over on the way: the clusters of
    /// vertices that marching cubes leaves around lattice points the
    /// surface passes next to (EdgeRoots.hpp's margin), whose slivers only
    /// vanish together.
    bool checkGeometry = true;
    /// Off: no collapse is checked for crossing or coming close to a
    /// triangle around it (TriangleClearance.hpp; with checkGeometry on,
    /// the shape, normal and tolerance checks stay).
    bool guardCrossings = true;
    /// collapsePartitioned's cubes by collapseEdgesCheckedAfter: unguarded,
    /// then checked whole (and redone guarded where that finds a pair).
    bool checkAfterwards = false;
    /// A triangle's normal may turn by at most this (cosine) in one collapse.
    double minNormalCosine = 0.2;
    /// A triangle's normal stays within this angle (cosine) of the surface's
    /// normal at each of its vertices: no triangle stands across the surface
    /// it approximates (which no quadric sees: its vertices are on it).
    double minSurfaceCosine = 0.8;
    /// No collapse makes a triangle lower than this (mm; the height over its
    /// longest edge): a triangle must stay a triangle in the file's
    /// coordinates (FilePrecision.hpp).
    double minHeight = 0.0;
    /// mm: a new triangle keeps this distance from every triangle it shares
    /// no vertex with (TriangleClearance.hpp), so that rounding to the
    /// file's coordinates cannot make them touch or cross.
    double clearance = 0.0;
};

/// Simplifies `mesh` on the calling thread. Returns the number of collapses;
/// stops early (with a valid mesh) once `work` is cancelled.
std::size_t collapseEdges(CollapseMesh& mesh, const CollapseLimits& limits, SurfaceQueries& surface,
                          const Progress& work = {});

/// How often collapseEdgesCheckedAfter's check found a pair.
struct CrossingChecks {
    std::size_t checked = 0; // meshes (or cubes) simplified unguarded and checked
    std::size_t redone = 0;  // of which redone guarded
};

/// collapseEdges with the crossing guard (limits.guardCrossings) applied to
/// the result instead of to every collapse: the collapses are made
/// unguarded on a copy, and the copy is kept when no live triangle of it
/// crosses or comes within limits.clearance of another or of an obstacle;
/// else they are made again from `mesh` as it was, guarded at every
/// collapse. The result keeps the same rule either way. Why: the guard
/// refuses hardly any collapse (none in 549 k on the side chair at 0.5 mm)
/// and cost half of the simplification's time; the check of a result is a
/// small part of that. Only with limits.checkGeometry and
/// limits.guardCrossings on; else it is collapseEdges.
std::size_t collapseEdgesCheckedAfter(CollapseMesh& mesh, const CollapseLimits& limits, SurfaceQueries& surface,
                                      const Progress& work = {}, CrossingChecks* checks = nullptr);

/// The same in parallel over cubes of edge `cube` mm whose corners lie at
/// `shift` + cube * (i, j, k) (in the mesh's coordinates), in `arena`; each
/// cube asks `surface.region()` of its vertices' box. With `beforehand`,
/// each cube is first simplified under those limits (the micro collapses:
/// one partition of the mesh serves both).
std::size_t collapsePartitioned(CollapseMesh& mesh, const CollapseLimits& limits, double cube,
                                const glm::dvec3& shift, tbb::task_arena& arena, SurfaceQueries& surface,
                                const Progress& work = {}, CrossingChecks* checks = nullptr,
                                const CollapseLimits* beforehand = nullptr);

} // namespace kerf::mesher

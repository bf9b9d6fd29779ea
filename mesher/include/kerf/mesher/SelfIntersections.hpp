#pragma once
// Whether a closed mesh crosses itself: pairs of triangles that intersect
// other than along what they share (an edge, or a vertex). A mesh that is a
// closed 2-manifold by its connectivity but crosses itself does not bound a
// solid: a slicer fills it wrongly.
//
// Method: a bounding volume hierarchy over the triangles' boxes (in the
// Morton order of their centres), walked against itself so that every pair
// of boxes that meet is met once, and for each such pair exact-sign tests
// in double: an edge of one crossing the other (triangles sharing a vertex:
// only the edges away from it), or, for triangles in one plane, overlap in
// that plane. Threads: oneTBB (the caller's arena), in the building and
// the walk; the count does not depend on them.

#include "kerf/document/Progress.hpp"
#include "kerf/mesher/Mesh.hpp"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace kerf {

struct SelfIntersections {
    std::size_t pairs = 0;                               // intersecting triangle pairs
    std::vector<std::array<std::uint32_t, 2>> examples; // the lowest few (triangle indices), sorted
    bool stopped = false;                                // cancelled before the end
};

/// `work`, asked now and then from the worker threads, stops the
/// search early (the count is then incomplete and `stopped` is set); it
/// hears the part of the triangles searched, from those threads too.
SelfIntersections findSelfIntersections(const Mesh& mesh, std::size_t examples = 8,
                                        const Progress& work = {});

/// The pairs of triangles that cross or come within `clearance` (mm) of
/// each other other than at what they share: the rule the simplifier's and
/// the refiner's crossing guard keep every change to (a clearance of a few
/// float32 spacings survives the rounding of the written coordinates;
/// mesher/src/TriangleClearance.hpp). Found the same way as crossings.
SelfIntersections findTrianglesCloserThan(const Mesh& mesh, double clearance, std::size_t examples = 8,
                                          const Progress& work = {});

/// Whether triangles A and B (vertex indices, and their positions a[3], b[3])
/// intersect other than along the vertices or the edge they share by index.
/// Quick rejections first: the corners of one that the other does not share
/// beyond the other's plane on one side, or (in one plane) an edge's line
/// with the other triangle beyond it.
bool trianglesCross(const std::array<std::uint32_t, 3>& A, const glm::dvec3* a, const std::array<std::uint32_t, 3>& B,
                    const glm::dvec3* b);

/// The same test without the quick rejections: every edge against the
/// other triangle (in one plane, every pair of edges and every corner). The
/// reference the tests hold trianglesCross to.
bool trianglesCrossExhaustively(const std::array<std::uint32_t, 3>& A, const glm::dvec3* a,
                                const std::array<std::uint32_t, 3>& B, const glm::dvec3* b);

} // namespace kerf

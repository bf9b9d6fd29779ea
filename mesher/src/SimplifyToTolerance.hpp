#pragma once
// The marching-cubes mesh made small: edge collapses under the quadrics of
// the exact surface's tangent planes (EdgeCollapse.hpp), in parallel over
// cubes of space, then over the whole. Flat faces become a few large
// triangles; sharp edges keep their feature vertices (a feature vertex
// stands for the planes of both sides, so moving it off the crease costs);
// curved faces keep what the limit asks.
//
// The limit is a mean squared distance to the tangent planes a vertex
// stands for, not a bound on the distance of the triangles to the surface:
// ToleranceRefiner.hpp then checks every triangle on the exact field and
// puts back what was taken too far.

#include "kerf/document/Progress.hpp"
#include "kerf/evaluator/Tape.hpp"
#include "kerf/mesher/Mesh.hpp"
#include "EdgeCollapse.hpp"

#include <tbb/task_arena.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace kerf::mesher {

struct SimplifySettings {
    double rmsDistance = 0.0; // mm: the limit on a vertex's root mean squared distance to its planes
    double minHeight = 0.0;   // mm: no triangle becomes lower than this (EdgeCollapse.hpp)
    double cube = 0.0;        // mm: edge of the cubes simplified in parallel
    double regionSize = 0.0;  // mm: queries evaluate tapes simplified for cubes this big around them (RegionTapes.hpp)
    double placement = 0.0;   // mm: a vertex moved onto a sharp edge must lie this close to the surface
    double clearance = 0.0;   // mm: new triangles keep this far from others (TriangleClearance.hpp)
    double tolerance = 0.0;   // mm: every new triangle's samples lie this close to the surface (0: unchecked)
    /// mm: edges shorter than this collapse first, on topology alone
    /// (CollapseLimits::checkGeometry); 0: none.
    double microLength = 0.0;
    /// The crossing guard on every collapse; off (the default), on each
    /// cube's result and on the last pass's (collapseEdgesCheckedAfter).
    bool guardEveryCollapse = false;
};

/// Simplifies `mesh` (world coordinates), the surface of `tape`, whose vertex
/// i has unit normal normals[i] (0 for a feature vertex; kept in step with
/// the vertices). Returns the number of collapses; when cancelled, 0 and
/// `mesh` and `normals` emptied (their memory is given up as soon as the
/// work has its own copy).
std::uint64_t simplifyToTolerance(Mesh& mesh, std::vector<glm::dvec3>& normals, const Tape& tape,
                                  const SimplifySettings& settings, tbb::task_arena& arena,
                                  const Progress& work = {}, CrossingChecks* checks = nullptr);

} // namespace kerf::mesher

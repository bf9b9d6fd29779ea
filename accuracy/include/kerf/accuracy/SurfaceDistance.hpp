#pragma once
// How far a triangle mesh lies from the exact surface of a part (the zero set
// of its field), for `kerf bench` and the mesher's accuracy tests.
//
// Why not |f| at the vertices: the mesher root-finds its vertices on the
// exact field, so |f| there is about zero whatever the cell size; the error
// is in the triangles' interiors, which cut chords across curved surfaces
// and corners off sharp edges. And |f| is only a lower bound of the distance
// for CSG fields (they are 1-Lipschitz bounds, exact distances only
// piecewise).
//
// Method, per sample point p:
//  - lower bound: |f(p)| (the field is 1-Lipschitz, so no surface point is
//    nearer than that);
//  - upper bound (the figure reported): walk from p towards the surface,
//    each step of length |f(q)| along the unit gradient at q (downhill
//    outside, uphill inside), until |f(q)| <= 1e-8 mm; then require a sign
//    change between q -+ 1e-6 mm along the normal (along the three axes
//    where the dual numbers give no gradient, as at some points where f is
//    exactly 0), which puts a surface point within 1e-6 mm of q: the
//    distance is at most |p - q| + 1e-6 mm.
//    No step crosses the surface (the ball of radius |f(q)| around q holds
//    none, the field being 1-Lipschitz); re-aiming at every step turns the
//    corner of a CSG edge, where a straight march along the first gradient
//    could miss the part. Where the field is an exact distance (away from
//    CSG edges), the first step lands on the nearest surface point and the
//    two bounds agree; near a crease where |f| is only a bound (inside a
//    union, outside an intersection), the walk ends on a surface point near
//    the nearest one (about 10% farther in the tests). Where the walk gets
//    stuck (the field a bound that steps back and forth between two
//    surfaces, as in the mouth of a hole that pierces a face) or finds no
//    sign change, straight sphere-tracing marches along 26 directions
//    settle it: the nearest crossing bounds the distance.
// Sample points: every vertex, and on every triangle its three edge
// midpoints and its centroid. With the vertices these are the points of the
// 7-point triangle quadrature rule of degree 3 (weights 1/20 at vertices,
// 2/15 at edge midpoints, 9/20 at the centroid), which gives the
// area-weighted mean; the maximum is over the samples, so it can miss a
// slightly larger deviation between them.
//
// Speed: samples are processed in chunks of consecutive triangles (the
// mesher emits them tile by tile, so a chunk is compact); each chunk uses
// the tape simplified for its bounding box (grown by a margin), which equals
// the full tape there; a walk that leaves the box is redone with the full
// tape. Threads: oneTBB; the result does not depend on the thread count.

#include "kerf/document/Progress.hpp"
#include "kerf/evaluator/Tape.hpp"
#include "kerf/mesher/Mesh.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace kerf {

/// Bounds on one point's distance to the zero set of a field, in mm.
struct PointDistance {
    double lower = 0.0;    // |f(p)|
    double upper = 0.0;    // a surface point lies at most this far (valid when resolved)
    bool resolved = false; // false when the walk found no sign change (no surface reached)
};

/// Distance bounds for each of `points` (world coordinates) to the surface
/// of `tape`, with the full tape, on the calling thread.
std::vector<PointDistance> distancesToSurface(const Tape& tape, const std::vector<glm::dvec3>& points);

struct SurfaceDistance {
    std::uint64_t samples = 0;    // points measured
    std::uint64_t unresolved = 0; // samples from which no surface was reached (left out of the figures)
    double max = 0.0;             // mm: the largest sample distance (upper bounds)
    glm::dvec3 maxAt{0.0};        // world mm: the sample where it is (the first, in chunk order)
    double mean = 0.0;            // mm: area-weighted mean distance over the mesh (upper bounds)
    double maxLowerBound = 0.0;   // mm: the largest |f| at a sample; the true maximum lies in [this, max]
    double vertexMax = 0.0;       // mm: the largest distance of a vertex (about 0: vertices are root-found)
    double area = 0.0;            // mm^2 of the triangles measured
    bool complete = true;         // false: cancelled part way, the figures cover part of the mesh
};

/// Measures `mesh` against the surface of `tape` (world coordinates), on
/// `threads` threads (0: every core). `work` hears the fraction of samples
/// measured; cancelled, it stops between chunks and the result is not complete.
SurfaceDistance measureSurfaceDistance(const Mesh& mesh, const Tape& tape, int threads = 0, const Progress& work = {});

} // namespace kerf

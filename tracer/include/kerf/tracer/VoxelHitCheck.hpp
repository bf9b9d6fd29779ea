#pragma once
// Which rays the hybrid refinement has to trace (TraceQuality::Exact).
//
// Refining every ray (TraceQuality::ExactEverywhere) costs the GPU 5 to 10
// times the voxel trace: each ray that reaches a surface spends about 11
// exact tape evaluations in a loop whose length differs from lane to lane.
// Most of them change nothing that the voxels did not nearly have: on a
// smooth face the trilinear hit lies a small fraction of a voxel from the
// exact surface. So the voxel trace runs first, and its hit is checked on
// the exact field with two evaluations: the field at the hit, one Newton
// step along the ray (the voxels' normal standing in for the gradient),
// the field and its gradient where that step lands, a second Newton step
// with the exact slope. The hit is confirmed when
//  - the ray came no closer than KERF_EDGE_CHECK_CLEARANCE voxel edges to
//    the trilinear surface of any populated voxel it crossed before the
//    one it hit (the refinement searches the exact field around every
//    populated voxel the ray meets: a surface the voxels rounded away, an
//    edge just beside the ray, can only be found there); less where that
//    voxel's corner normals turn through a smaller angle (a smooth surface
//    of that curvature is interpolated that closely: ExactRefinement.h).
//    The voxel right before the hit's does not count when it is no sharp
//    edge and its field still fell as the ray left it: the ray was closing
//    in on the surface it hits, and the Newton steps below look there;
//  - the surface faces the ray (a grazing ray is refined);
//  - the first step stays within KERF_EDGE_CHECK_SHIFT voxel edges and
//    inside the tile (whose tape is exact only there), and the second
//    within KERF_EDGE_CHECK_RESIDUAL;
//  - the exact normal where the first step lands lies within
//    KERF_EDGE_CHECK_SMOOTH_ANGLE of the voxels' (else an edge lies
//    between them).
// A confirmed hit takes the two steps' depth, the exact gradient's normal
// and the deciding feature: what the refinement would have found, within
// its own tolerance. At a sharp edge, in a crease, at a silhouette or on a
// grazing face the check fails and the ray is traced again with the
// refinement (ExactEverywhere's algorithm). Where two planes meet, the
// check cannot confirm the wrong one: on a convex edge the first crossing
// is the later plane, and a step onto the earlier one lands outside the
// other; on a concave one the step onto the later plane lands inside the
// earlier; either way the second step is long, or the normal turns.
//
// A rule of one ray: the CPU reference (traceRay) and the GPU (the judge
// pass of shaders/trace.comp) apply it pixel by pixel, in the same order.

#include "kerf/tracer/ReferenceTracer.hpp"

namespace kerf {

enum class VoxelHitVerdict {
    Keep,    // the voxels' answer stands (a miss that met no populated voxel, a cap, a tile without a tape)
    Confirm, // the exact field confirms the hit: `refined` holds it
    Refine,  // the ray must be traced with the refinement
};

/// Checks `voxelHit`, the voxel trace of the ray origin + t * dir (grid
/// local, `plane` as for traceRay), as described above. On Confirm,
/// `refined` is the hit with its exact depth, normal and feature. Adds the
/// tape evaluations to refined.evaluations.
VoxelHitVerdict checkVoxelHit(const FlatVoxelBuffers& buffers, const glm::vec3& origin, const glm::vec3& dir,
                              const glm::vec4& plane, const RayHit& voxelHit, RayHit& refined);

} // namespace kerf

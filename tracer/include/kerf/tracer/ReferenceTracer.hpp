#pragma once
// The CPU reference of the viewport's voxel ray tracer: the same algorithm,
// written so that the GLSL compute shader can follow it line by line (float
// arithmetic, tile-local coordinates, plain loops with fixed bounds, no
// recursion, no containers in the per-ray code).
//
// Per ray:
//  1. Slab test against the grid's box; rays that miss it are done.
//  2. Amanatides & Woo 3D DDA over the tiles, front to back.
//  3. In a surface tile, the entry point is taken into tile-local
//     coordinates ([0, 1]^3 across the tile). A loop then descends the
//     contree from the root to the deepest existing node containing the
//     current cell (integer coordinates at the tile's finest level); an empty
//     cell, at whatever level, is skipped whole by moving to its face
//     neighbour across the face the ray leaves it by. The integer cell
//     coordinates step by at least one every iteration, so the loop always
//     ends, whatever rounding does to the float ray parameter.
//  4. In a populated voxel, the trilinear interpolation of its 8 corner
//     distances is a cubic along the ray; the roots of its derivative split
//     the segment into monotone pieces, and the first piece that reaches
//     f <= 0 is bisected. Inside is f < 0, as for the voxelizer, so a voxel
//     entered with f <= 0 counts as hit at its entry: a face lying exactly on
//     a plane of voxel corners (stored distance exactly 0, common for
//     axis-aligned boxes) is hit where it is, and a crossing lost to
//     rounding, or a ray starting inside the solid, still stops there.
//  5. The normal is the normalised trilinear interpolation of the corner
//     normals at the hit; the feature is the nearest corner's.
//  6. With a section plane, the ray is clipped to the side kept (ending at
//     the plane, or starting there); a ray starting on the plane meets a
//     cap when its first populated voxel (or a full tile) is entered with
//     f <= 0: no surface was crossed since the plane, so the plane point was
//     inside. A cap has the plane's normal and the feature kSectionCap.
//  7. With the hybrid refinement (TraceQuality::ExactEverywhere, and
//     TraceQuality::Exact where VoxelHitCheck.hpp says so) and a tile that
//     carries its exact tape (TileTape.hpp), every populated voxel the ray
//     meets is searched on the exact field, over its segment grown by
//     KERF_EXACT_MARGIN voxel edges both ways (within the tile, and not
//     again where an earlier voxel's search found the field positive):
//     sphere tracing from the window's start (which never passes a
//     crossing), bisection when a bracket is known (the trilinear crossing
//     where the exact field is inside there, or the window's end) and the
//     steps run out, a walk back when the window starts inside (the surface
//     crossed where no voxel is populated: an edge sharper than the
//     voxels). A crossing found is the hit, with the exact field's normal
//     (its gradient by forward differentiation, in tile-relative
//     millimetres) and deciding feature. TraceQuality::Exact's refinement
//     of the rays the check sends back searches the same windows eight
//     points at a time instead (one GPU lane each: exactCrossingLanes in
//     ReferenceTracer.cpp), spans certified empty by the field's values,
//     the first one that is not narrowed down. Where the window holds no
//     exact crossing, the trilinear one stands (the voxels never show a hole that the hybrid would open);
//     where neither exists, the ray moves on. ExactRefinement.h has the
//     constants. Tiles without a tape are traced on their voxels.
//  A kFullTile tile (entirely inside) is reported hit at its entry face,
//  with that face's normal; with consistent voxel data a ray always meets a
//  populated voxel before, so this is only a safety net.
//
// Precision: tile-local float coordinates resolve 2^-24 of a tile, so the
// hit is exact to about 4^levels * 6e-8 voxel edges inside a tile (far below
// a voxel for the depths GridLayout::choose makes), plus the ray origin's
// float error relative to the grid origin (distance * 6e-8).

#include "kerf/document/Progress.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/ExactRefinement.h"
#include "kerf/tracer/Image.hpp"
#include "kerf/tracer/Section.hpp"
#include "kerf/tracer/TraceQuality.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <limits>

namespace kerf {

/// What one ray found.
struct RayHit {
    float depth = std::numeric_limits<float>::infinity(); // mm along the ray from its origin; +inf: nothing hit
    glm::vec3 normal{0.0f};                               // unit, grid (= world) frame
    std::uint32_t feature = kNoFeature;
    std::uint32_t steps = 0;       // tiles and contree cells visited (a cost measure)
    std::uint32_t evaluations = 0; // exact tape evaluations (the hybrid refinement's cost)
    std::uint32_t rounds = 0;      // Exact's refinement: rounds of KERF_EDGE_REFINE_LANES evaluations
    /// The evaluations one after another, each of Exact's rounds counted
    /// once (its lanes evaluate together): what a GPU's ray waits for.
    std::uint32_t evaluationsInARow = 0;
    /// Of the populated voxels the ray crossed without meeting their
    /// trilinear surface, the least value of that surface's field along the
    /// ray, in units of the clearance VoxelHitCheck.hpp asks of that voxel
    /// (+inf: none; below 1: the hit needs the refinement); without the
    /// smooth voxel right before the hit's whose field fell to its exit.
    float passedClearance = std::numeric_limits<float>::infinity();
    /// The stretch of the ray (mm from its origin) that TraceQuality::Exact's
    /// refinement would search, from the voxel trace: the windows of the
    /// voxel hit and of the voxels passed within the clearance (empty:
    /// nearFrom > nearTo).
    float nearFrom = std::numeric_limits<float>::infinity();
    float nearTo = -std::numeric_limits<float>::infinity();
    bool refined = false;          // traced with the hybrid refinement (TraceQuality::Exact: the check failed)
    bool exactHit = false;         // the refinement's crossing of the exact field (else the voxels')

    bool hit() const { return depth < std::numeric_limits<float>::infinity(); }
};

/// Traces one ray through `buffers`. `origin` is relative to the grid's
/// origin (buffers.layout.origin), in mm; `direction` is of unit length.
/// `plane`: a section plane in the same coordinates (xyz unit normal, w
/// offset), or zero for none. Pure function of its arguments; safe from any
/// thread. `quality` ExactEverywhere turns the hybrid refinement on (step
/// 7); Exact traces the voxels, and refines only where the exact field does
/// not confirm their hit (VoxelHitCheck.hpp), with `refineLanes` points a
/// round (ExactRefinement.h: the GPU's lanes a ray, ComputeTracer::refineLanes).
RayHit traceRay(const FlatVoxelBuffers& buffers, const glm::vec3& origin, const glm::vec3& direction,
                const glm::vec4& plane = glm::vec4(0.0f), TraceQuality quality = TraceQuality::Voxels,
                int refineLanes = KERF_EDGE_REFINE_LANES);

/// A world-space section as traceRay's grid-local plane (zero when disabled).
glm::vec4 localPlane(const GridLayout& layout, const Section& section);

/// As above for a world-space ray (the subtraction of the grid origin is
/// done in double, as the GPU path does on the CPU before uploading).
RayHit traceRay(const FlatVoxelBuffers& buffers, const Ray& ray, const Section& section = {},
                TraceQuality quality = TraceQuality::Voxels, int refineLanes = KERF_EDGE_REFINE_LANES);

/// Traces every pixel of `camera`'s image, rows in parallel with oneTBB on
/// `threads` threads (0: every core). The buffers must not change meanwhile.
/// `work` hears the fraction of rows traced; cancelled, the tracing stops
/// between rows and the image is not complete.
TraceImage traceVoxels(const FlatVoxelBuffers& buffers, const Camera& camera, int threads = 0,
                       const Section& section = {}, TraceQuality quality = TraceQuality::Voxels,
                       const Progress& work = {}, int refineLanes = KERF_EDGE_REFINE_LANES);

} // namespace kerf

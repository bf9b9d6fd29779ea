// Tuning of the hybrid refinement (TraceQuality::Exact), shared by the CPU
// reference tracer (tracer/src/ReferenceTracer.cpp) and the GPU one
// (shaders/trace.comp) so that the two cannot drift. Preprocessor
// definitions only: C++ and GLSL both read it. Lengths are in voxel edges
// of the voxel being searched; docs/benchmarks.md has what they cost.
#ifndef KERF_EXACT_REFINEMENT_H
#define KERF_EXACT_REFINEMENT_H

// How far beyond a populated voxel's segment, both ways, the exact field is
// searched: the exact surface departs from the trilinear one by a fraction
// of a voxel (sharp edges rounded off, creases filled in).
#define KERF_EXACT_MARGIN 1.0
// Sphere-tracing steps per populated voxel before the window's end is tried
// as a bracket; and with a bracket already known (the trilinear crossing
// inside the exact surface), before regula falsi takes over.
#define KERF_EXACT_STEPS 8
#define KERF_EXACT_BRACKETED_STEPS 2
// Regula falsi (Illinois) steps on a bracketed crossing.
#define KERF_EXACT_REFINEMENTS 8
// The ray hits where the exact field drops below this.
#define KERF_EXACT_EPSILON 0.001

// A crossing the search found is tested a little further along the ray:
// just past where a sheet would be (twice the field's value there, plus
// NEAR) and at FAR (voxel edges). Where the field rises at both at half
// their distance or more, the ray only touched a sheet of no thickness (a
// blind hole's mouth cut flush with the face: 0 across it) and searches
// on. A ray through a sharp edge's corner for less than about NEAR is
// taken for such a touch too.
#define KERF_EXACT_TOUCH_NEAR 0.004
#define KERF_EXACT_TOUCH_FAR 0.1

// The check of a voxel hit (VoxelHitCheck.hpp), in voxel edges of the
// tile's finest level: how far the first Newton step may move the hit, and
// the second. A first step that long is a voxel's rounding of a face; a
// face that bends so much that the second is longer is for the refinement.
#define KERF_EDGE_CHECK_SHIFT 0.5
#define KERF_EDGE_CHECK_RESIDUAL 0.05
// And the field where the second step lands within this of zero: on the
// surface, a few times the refinement's own KERF_EXACT_EPSILON (float
// rounding of a depth thousands of voxels long is about that).
#define KERF_EDGE_CHECK_ON_SURFACE 0.005
// The surface must face the ray: the cosine between the ray and the
// gradient at least this (a grazing ray is refined).
#define KERF_EDGE_CHECK_FACING 0.1
// A populated voxel the ray crossed before its hit, without meeting its
// trilinear surface, is searched by the refinement when the ray came
// closer to that surface than the exact one may stand out from it there
// (voxel edges): CLEARANCE_PER_RADIAN times the angle the voxel's corner
// normals turn through (twice the trilinear error of a smooth distance
// field of that curvature), at least SMOOTH_CLEARANCE, at most CLEARANCE
// (a sharp edge rounds off by up to half a voxel).
#define KERF_EDGE_CHECK_CLEARANCE 0.5
#define KERF_EDGE_CHECK_SMOOTH_CLEARANCE 0.05
#define KERF_EDGE_CHECK_CLEARANCE_PER_RADIAN 0.43
// The exact normal where the first step lands must lie within this of the
// voxels' (degrees): else an edge lies between them.
#define KERF_EDGE_CHECK_SMOOTH_ANGLE 10.0
// TraceQuality::Exact's refinement of the rays the check sent back searches
// LANES points of the ray at a time (one GPU lane each, so that a round
// costs one evaluation's latency; ReferenceTracer.cpp, exactCrossingLanes):
// at most WINDOW_ROUNDS rounds in one populated voxel's window, and no new
// window once the ray has spent ROUNDS; beyond, the voxels it meets answer
// alone. A few rays that skim along an edge for many voxels would otherwise
// take hundreds, and on a GPU the frame waits for its slowest ray. The GPU
// takes as many lanes a ray as its subgroup holds, up to MAX_LANES (32 on
// NVIDIA, 8 on lavapipe: ComputeTracer::refineLanes); the CPU reference
// takes LANES unless told (each round costs it every lane's evaluation).
#define KERF_EDGE_REFINE_LANES 8
#define KERF_EDGE_REFINE_MAX_LANES 32
// A stretch shorter than this (voxel edges) between two points outside the
// surface counts as empty: a ray passing nearer than that to the surface
// without meeting it between two points is left to the voxels.
#define KERF_EDGE_REFINE_GAP 0.02
// The first segment that reaches the surface (its far end within
// KERF_EXACT_EPSILON of it, or inside) is narrowed until the crossing is
// known to within this (voxel edges); the line through its ends' values
// then places the hit.
#define KERF_EDGE_REFINE_FINISH 0.01
// The two budgets, measured in docs/benchmarks.md ("Exact edges in rounds of
// lanes"): tighter ones lose the edges' normals on the sharp part.
#define KERF_EDGE_REFINE_WINDOW_ROUNDS 20
#define KERF_EDGE_REFINE_ROUNDS 12u
// The GPU starts the refinement of rays whose stretch (where the voxels met
// the surface or came near it) is longer than this (finest voxel edges)
// before the others: they search the most windows (trace.comp, checkPixel).
// Measured against 0 (the order listed), 2 and 8 in docs/benchmarks.md
// ("The voxel trace out of local memory, long rays refined first").
#define KERF_EDGE_REFINE_LONG 4.0

#endif

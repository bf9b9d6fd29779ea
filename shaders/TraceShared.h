// Shared by C++ and GLSL: the parameters of one trace dispatch, so that the
// two sides cannot drift. Everything the shader reads is reached by buffer
// device address (no binding range limit: lavapipe caps bindings at 128 MiB).
// std430 layout: 64-bit addresses first, then 16-byte vectors.
#ifndef KERF_TRACE_SHARED_H
#define KERF_TRACE_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace kerf::gpu {
using uint64_t_ = std::uint64_t;
struct vec4_ {
    float x, y, z, w;
};
struct ivec4_ {
    std::int32_t x, y, z, w;
};
struct uvec4_ {
    std::uint32_t x, y, z, w;
};
#define KERF_U64 uint64_t_
#define KERF_VEC4 vec4_
#define KERF_IVEC4 ivec4_
#define KERF_UVEC4 uvec4_
#else
#define KERF_U64 uint64_t
#define KERF_VEC4 vec4
#define KERF_IVEC4 ivec4
#define KERF_UVEC4 uvec4
#endif

#define KERF_TRACE_LOCAL_SIZE 8

struct TraceParams {
    // Voxel buffers (FlatVoxelBuffers), as 32-bit words.
    KERF_U64 tiles;
    KERF_U64 entries;          // TileEntry: 8 words
    KERF_U64 nodes;            // Node: 3 words
    KERF_U64 leafIndirections; // 2 words
    KERF_U64 leafData;         // 2 words (8 bytes)
    KERF_U64 vertices;         // 2 words
    // Outputs, one element per pixel (x + width * y).
    KERF_U64 outDepth;   // float, +inf where nothing is hit
    KERF_U64 outNormal;  // vec4 (xyz unit normal, w unused)
    KERF_U64 outFeature; // uint, 0xFFFFFFFF where nothing is hit
    KERF_U64 tapes;      // the tiles' exact tapes (TileTapeFormat.h), as 32-bit words
    // TraceQuality::Exact's passes (trace.comp, kPass): what the voxel pass
    // tells the others about a pixel it lists (vec4: RayHit's
    // passedClearance, nearFrom, nearTo), the pixels sent to the refinement
    // (uint, x + width * y), the indirect dispatches and the lists' counts
    // (trace.comp, RefineArgs), and the voxel hits the check is to look at
    // (uint, x + width * y).
    KERF_U64 outVoxelPass;
    KERF_U64 refineList;
    KERF_U64 refineArgs;
    KERF_U64 checkList;
    KERF_VEC4 eye;       // xyz: camera eye relative to the grid origin (mm); w: tile size (mm)
    KERF_VEC4 forward;   // xyz: unit view direction; w: 1 for orthographic, 0 for perspective
    KERF_VEC4 right;     // xyz: unit image right; w: tan(fovY/2) or half the ortho height (mm)
    KERF_VEC4 up;        // xyz: unit image up; w: the grid's finest voxel edge (mm)
    KERF_IVEC4 dims;     // xyz: tiles along each axis
    KERF_UVEC4 image;    // x: width, y: height (pixels)
    KERF_VEC4 section;   // xyz: unit normal of the section plane, w: its offset from the grid origin; zero: none
    KERF_UVEC4 options;  // x: 1 where the hybrid refinement may run (the tapes are there), else 0
};

#ifdef __cplusplus
static_assert(sizeof(TraceParams) == 112 + 8 * 16);
} // namespace kerf::gpu
#endif

#undef KERF_U64
#undef KERF_VEC4
#undef KERF_IVEC4
#undef KERF_UVEC4
#endif

// Shared by C++ and GLSL: the brick renderer's instances and push
// constants (viewport/include/kerf/viewport/BrickRenderer.hpp).
#ifndef KERF_BRICK_SHARED_H
#define KERF_BRICK_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace kerf::gpu {
struct BVec4 {
    float x, y, z, w;
};
struct BUVec4 {
    std::uint32_t x, y, z, w;
};
struct BMat4 {
    float m[16]; // column-major
};
#define KERF_U64 std::uint64_t
#define KERF_VEC4 BVec4
#define KERF_UVEC4 BUVec4
#define KERF_MAT4 BMat4
#else
#define KERF_U64 uint64_t
#define KERF_VEC4 vec4
#define KERF_UVEC4 uvec4
#define KERF_MAT4 mat4
#endif

/// One brick drawn: a cube of `cells` voxels along each edge.
struct BrickInstance {
    KERF_VEC4 minEdge; // xyz: minimum corner relative to the eye (mm); w: voxel edge (mm)
    KERF_UVEC4 slot;   // xyz: the atlas texel of its sample (0, 0, 0); w: cells
};

struct BrickPush {
    KERF_MAT4 clipFromEye; // world relative to the eye -> clip
    KERF_VEC4 forward;     // xyz: unit view direction; w: 1 orthographic, 0 perspective
    KERF_VEC4 atlasScale;  // xyz: 1 / the atlas's size in texels
    KERF_U64 instances;    // address of the BrickInstance array
    KERF_U64 pad;
    // The section plane relative to the eye: xyz its unit normal, w its
    // offset (the kept side is dot(xyz, p) <= w for p relative to the eye);
    // a zero normal: no section.
    KERF_VEC4 section;
};

#ifdef __cplusplus
static_assert(sizeof(BrickInstance) == 32);
static_assert(sizeof(BrickPush) == 128); // the smallest push-constant space a device may have
} // namespace kerf::gpu
#endif

#undef KERF_U64
#undef KERF_VEC4
#undef KERF_UVEC4
#undef KERF_MAT4
#endif

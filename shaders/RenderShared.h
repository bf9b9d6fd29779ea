// Shared by C++ and GLSL: parameters of the passes that turn traced depth,
// normal and feature into a picture, and of the mesh pass that mixes
// ordinary meshes in by depth.
#ifndef KERF_RENDER_SHARED_H
#define KERF_RENDER_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace kerf::gpu {
struct RVec4 {
    float x, y, z, w;
};
struct RMat4 {
    float m[16]; // column-major
};
#define KERF_U64 std::uint64_t
#define KERF_UINT std::uint32_t
#define KERF_VEC4 RVec4
#define KERF_MAT4 RMat4
#else
#define KERF_U64 uint64_t
#define KERF_UINT uint
#define KERF_VEC4 vec4
#define KERF_MAT4 mat4
#endif

#define KERF_SHADE_ORTHO 1u
#define KERF_SHADE_EDGES 2u

// Per-feature flags, in the w of a featureColors entry (as a float).
#define KERF_FEATURE_HAS_COLOR 1u
#define KERF_FEATURE_SELECTED 2u

// The feature id of a section's cap: KERF_SECTION_CAP_FEATURE.
#include "kerf/tracer/SectionCap.h"

struct ShadeParams {
    KERF_U64 depth;         // float per pixel, +inf = nothing hit
    KERF_U64 normal;        // vec4 per pixel
    KERF_U64 feature;       // uint per pixel
    KERF_U64 featureColors; // vec4 per feature: rgb linear, a = 1 when the feature has a colour
    KERF_UINT featureCount;
    KERF_UINT width;
    KERF_UINT height;
    KERF_UINT flags;
    KERF_VEC4 forward;      // xyz view direction; w: near (mm)
    KERF_VEC4 right;        // xyz; w: far (mm)
    KERF_VEC4 up;           // xyz; w: tan(fovY/2) or half the ortho height
    KERF_VEC4 light;        // xyz towards the key light; w: key strength
    KERF_VEC4 view;         // xyz towards the viewer; w: headlight strength
    KERF_VEC4 sky;          // rgb; w: specular strength
    KERF_VEC4 ground;       // rgb; w: specular exponent
    KERF_VEC4 backgroundTop;
    KERF_VEC4 backgroundBottom;
    KERF_VEC4 defaultColor; // rgb: parts without a colour; w: edge darkening (0..1)
    KERF_VEC4 highlight;    // rgb: selection colour (linear); w: how much it tints the selection (0..1)
    KERF_VEC4 eye;          // xyz: eye in world mm (the grid pass); w: unused
    KERF_VEC4 grid;         // x: minor spacing (mm), y: major spacing (mm), z: fade distance (mm), w: 1 to draw
    KERF_VEC4 section;      // xyz: unit normal of the section plane (world); w: its offset (mm)
    KERF_VEC4 capColor;     // rgb: colour of the section's cut faces (linear); w: hatch spacing (pixels)
};

/// Push constants of the mesh pass.
struct MeshPush {
    KERF_MAT4 clipFromWorld; // world relative to the render origin
    KERF_VEC4 color;         // rgb linear; w: opacity (ghosts blend, the rest are opaque)
    KERF_U64 shade;          // address of the ShadeParams (lights)
    KERF_U64 pad;
};

/// Push constants of the gizmo pass.
struct GizmoPush {
    KERF_U64 shade;  // address of the ShadeParams (the view frame)
    KERF_U64 pad;
    KERF_VEC4 rect;  // x, y: top-left corner (pixels); z: size (pixels)
};

#ifdef __cplusplus
static_assert(sizeof(GizmoPush) == 32);
static_assert(sizeof(ShadeParams) == 48 + 15 * 16);
static_assert(sizeof(MeshPush) == 96);
} // namespace kerf::gpu
#endif

#undef KERF_U64
#undef KERF_UINT
#undef KERF_VEC4
#undef KERF_MAT4
#endif

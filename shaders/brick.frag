#version 460
// Marches one brick's samples along the pixel's ray with hardware trilinear
// filtering, and writes what the compute tracer writes (depth along the
// ray, unit normal, feature) where it meets the surface. The fragment is
// one of the cube's far faces (BrickRenderer.cpp) and writes no depth of its
// own: the depth test keeps the brick whose far face is nearest, which is
// the first brick along the ray that found the surface (bricks are
// disjoint boxes, so a ray leaves them in the order it enters them), and the
// early depth test drops the bricks behind it before their march.
//
// A section plane (BrickPush::section) clips the march to the kept side. A
// ray that starts on the plane inside the solid reports the cap there: in
// the brick the plane passes through when its samples are inside at the
// plane, else in the first brick it enters beyond, when they are inside
// where it enters (the field changes sign only in populated voxels, which
// bricks cover, so the cells it crossed between were inside too); the
// compute tracer's rule (trace.comp, capInsideAtEntry).
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "BrickShared.h"
#include "kerf/tracer/SectionCap.h"
// kDistanceRange: distances are stored in units of that many voxel edges.
#include "voxel_format.glsl"

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Instances { BrickInstance b[]; };
layout(push_constant) uniform Push { BrickPush p; } pc;
layout(set = 0, binding = 0) uniform sampler3D distanceAtlas; // R16 snorm, linear
layout(set = 0, binding = 1) uniform sampler3D normalAtlas;   // RGBA8 snorm, linear
layout(set = 0, binding = 2) uniform usampler3D featureAtlas; // R16 uint, nearest
layout(location = 0) in vec3 eyeRelative;
layout(location = 1) flat in uint instance;
layout(location = 0) out float outDepth;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out uint outFeature;

const int kBisectionSteps = 10;
const uint kSectionCap = KERF_SECTION_CAP_FEATURE;

vec3 slotOrigin;
vec3 atlasScale;

// The trilinear field at q (voxel units inside the brick, [0, cells]^3).
float field(vec3 q) { return texture(distanceAtlas, (slotOrigin + 0.5 + q) * atlasScale).r; }

void main()
{
    const BrickInstance brick = Instances(pc.p.instances).b[instance];
    slotOrigin = vec3(brick.slot.xyz);
    atlasScale = pc.p.atlasScale.xyz;
    const float voxel = brick.minEdge.w;
    const float cells = float(brick.slot.w);
    const bool ortho = pc.p.forward.w > 0.5;
    const vec3 dir = ortho ? pc.p.forward.xyz : normalize(eyeRelative);
    // The ray's origin: the eye, or its plane's point for a parallel view.
    const vec3 origin = ortho ? eyeRelative - dot(eyeRelative, dir) * dir : vec3(0.0);

    // The ray in voxel units of the brick: q(t) = o + t d, t in mm.
    // A ray parallel to an axis that runs along the brick's face (a parallel
    // view along an axis, the pixel centre on the cube's edge) counts as
    // inside: the rasterizer gives the pixel to one of the two cubes that
    // share the face, whichever, and both hold the same samples there.
    vec3 o = (origin - brick.minEdge.xyz) / voxel;
    o = mix(o, clamp(o, vec3(0.0), vec3(cells - 1e-4)), equal(dir, vec3(0.0)));
    // A component that is exactly zero (a parallel view along an axis)
    // becomes a tiny positive one, so that the face the ray leaves by is
    // always the far one along that axis (never -inf * 0).
    const vec3 d = mix(dir / voxel, vec3(1e-20), equal(dir, vec3(0.0)));
    const vec3 inv = 1.0 / d;
    const vec3 t0 = (vec3(0.0) - o) * inv, t1 = (vec3(cells) - o) * inv;
    const vec3 tNear = min(t0, t1), tFar = max(t0, t1);
    float tEnter = max(max(max(tNear.x, tNear.y), tNear.z), 0.0);
    float tExit = min(min(tFar.x, tFar.y), tFar.z);

    // The section plane keeps dot(n, p) <= offset (trace.comp, traceRay).
    const vec3 planeNormal = pc.p.section.xyz;
    bool capPending = false;
    float tPlane = 0.0;
    if (planeNormal != vec3(0.0)) {
        const float denom = dot(planeNormal, dir);
        const float above = dot(planeNormal, origin) - pc.p.section.w;
        if (abs(denom) < 1e-12) {
            if (above > 0.0) discard;
        } else {
            tPlane = -above / denom;
            if (denom > 0.0) {
                tExit = min(tExit, tPlane);
            } else if (tPlane > 0.0) {
                // The ray starts on the plane: until it meets a surface, what
                // it passes through says whether the plane's point is inside.
                capPending = true;
                tEnter = max(tEnter, tPlane);
            }
        }
    }
    if (!(tExit > tEnter)) discard;
    // A plane on the brick's far face leaves it a stretch of no length,
    // which the rounding of tPlane can make a little longer: the brick
    // beyond, which holds the same samples on that face, decides the cap.
    if (capPending && !(tExit - tEnter > 1e-3 * voxel)) discard;

    // Cell by cell, sampling each cell's entry, middle and exit; the first
    // sign change is bisected.
    const ivec3 stepDir = ivec3(sign(d));
    ivec3 cell = clamp(ivec3(floor(o + tEnter * d)), ivec3(0), ivec3(int(cells) - 1));
    float ta = tEnter;
    float fa = field(o + ta * d);
    float hit = -1.0;
    if (capPending) {
        // On the plane in this brick: below zero, or at zero in a cell with
        // a corner below (a populated voxel: a plane lying on a face of the
        // part caps it; in a cell with no corner below, zero is outside).
        // Entered through a face after cells proven wholly inside or
        // outside: below by more than a thousandth of a voxel (a face of the
        // part on a lattice plane, met from outside, is no cap).
        // ReferenceTracer.cpp, CapState.
        const bool travelled = tEnter - tPlane > 1e-3 * voxel;
        bool inside = fa < 0.0;
        if (!travelled && fa == 0.0) {
            inside = false;
            for (int c = 0; c < 8; ++c)
                inside = inside ||
                         texelFetch(distanceAtlas, ivec3(slotOrigin) + cell + ivec3(c & 1, (c >> 1) & 1, c >> 2), 0).r < 0.0;
        }
        if (travelled ? fa < -1e-3 / kDistanceRange : inside) {
            outDepth = tPlane;
            outNormal = vec4(planeNormal, 0.0);
            outFeature = kSectionCap;
            return;
        }
    }
    // Inside is below zero, as the voxelizer counts a corner (ReferenceTracer.cpp, firstCrossing).
    if (fa < 0.0) hit = ta;
    for (int i = 0; i < 3 * int(cells) + 3 && hit < 0.0; ++i) {
        const vec3 bound = vec3(cell) + vec3(greaterThan(d, vec3(0.0)));
        const vec3 tb = (bound - o) * inv;
        const float tc = min(min(min(tb.x, tb.y), tb.z), tExit);
        const float tm = 0.5 * (ta + tc);
        const float fm = field(o + tm * d);
        const float fc = field(o + tc * d);
        float lo = -1.0, hi = -1.0;
        if (fm < 0.0) {
            lo = ta;
            hi = tm;
        } else if (fc < 0.0) {
            lo = tm;
            hi = tc;
        }
        if (hi >= 0.0) {
            for (int k = 0; k < kBisectionSteps; ++k) {
                const float mid = 0.5 * (lo + hi);
                if (field(o + mid * d) < 0.0)
                    hi = mid;
                else
                    lo = mid;
            }
            hit = hi;
            break;
        }
        if (tc >= tExit) break;
        ta = tc;
        fa = fc;
        // Into the neighbour across the face the ray leaves by.
        if (tb.x <= tc) cell.x += stepDir.x;
        else if (tb.y <= tc) cell.y += stepDir.y;
        else cell.z += stepDir.z;
        if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, ivec3(int(cells))))) break;
    }
    if (hit < 0.0) discard;

    const vec3 q = o + hit * d;
    vec3 n = texture(normalAtlas, (slotOrigin + 0.5 + q) * atlasScale).xyz;
    float len = length(n);
    if (!(len > 1e-6)) {
        // Corner normals that cancel out: the interpolated field's gradient.
        const float h = 0.25;
        n = vec3(field(q + vec3(h, 0, 0)) - field(q - vec3(h, 0, 0)), field(q + vec3(0, h, 0)) - field(q - vec3(0, h, 0)),
                 field(q + vec3(0, 0, h)) - field(q - vec3(0, 0, h)));
        len = length(n);
    }
    n = len > 0.0 ? n / len : -dir;
    // The nearest sample, a tie to the lower one (as the reference tracer's
    // first nearest corner).
    const ivec3 nearest = clamp(ivec3(ceil(q - 0.5)), ivec3(0), ivec3(int(cells)));
    outFeature = texelFetch(featureAtlas, ivec3(slotOrigin) + nearest, 0).r;
    outDepth = hit;
    outNormal = vec4(n, 0.0);
}

#version 460
// The depth prepass and shading of the traced part: writes the part's colour
// and its depth, so that meshes drawn afterwards are hidden where the part is
// in front and hide it where they are. Selected features are tinted and
// outlined; a section plane's cut faces are hatched.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "RenderShared.h"

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ShadeRef { ShadeParams s; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Floats { float f[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Vec4s { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Uints { uint u[]; };
layout(push_constant) uniform Push { uint64_t shade; } pc;

layout(location = 0) out vec4 outColor;

#include "lighting.glsl"

ShadeParams S;

float depthAt(ivec2 p)
{
    p = clamp(p, ivec2(0), ivec2(S.width - 1, S.height - 1));
    return Floats(S.depth).f[uint(p.x) + S.width * uint(p.y)];
}
uint featureAt(ivec2 p)
{
    p = clamp(p, ivec2(0), ivec2(S.width - 1, S.height - 1));
    return Uints(S.feature).u[uint(p.x) + S.width * uint(p.y)];
}
uint flagsOf(uint feature)
{
    return feature < S.featureCount ? uint(Vec4s(S.featureColors).v[feature].w + 0.5) : 0u;
}

void main()
{
    S = ShadeRef(pc.shade).s;
    const ivec2 p = ivec2(gl_FragCoord.xy);
    const uint i = uint(p.x) + S.width * uint(p.y);
    const float t = Floats(S.depth).f[i];
    const float v = gl_FragCoord.y / float(S.height);
    if (isinf(t)) {
        outColor = vec4(toSrgb(mix(S.backgroundTop.rgb, S.backgroundBottom.rgb, v)), 1.0);
        gl_FragDepth = 1.0;
        return;
    }
    const float aspect = float(S.width) / float(S.height);
    const float u = (2.0 * gl_FragCoord.x / float(S.width) - 1.0) * aspect;
    const float w = 1.0 - 2.0 * gl_FragCoord.y / float(S.height);
    const bool ortho = (S.flags & KERF_SHADE_ORTHO) != 0u;
    const vec3 dir = ortho ? S.forward.xyz
                           : normalize(S.forward.xyz + (u * S.up.w) * S.right.xyz + (w * S.up.w) * S.up.xyz);
    // Depth along the view axis, then the projection's depth (0 near, 1 far).
    const float z = t * dot(dir, S.forward.xyz);
    const float n = S.forward.w, f = S.right.w;
    gl_FragDepth = ortho ? (z - n) / (f - n) : f * (z - n) / (z * (f - n));

    const uint feature = Uints(S.feature).u[i];
    const uint flags = flagsOf(feature);
    vec3 albedo = S.defaultColor.rgb;
    if ((flags & KERF_FEATURE_HAS_COLOR) != 0u) albedo = Vec4s(S.featureColors).v[feature].rgb;
    vec3 nrm = Vec4s(S.normal).v[i].xyz;
    vec3 c;
    if (feature == KERF_SECTION_CAP_FEATURE) {
        // The cut face: flat colour with diagonal hatching in screen space,
        // as a drawing shows a section.
        const float hatch = mod(gl_FragCoord.x + gl_FragCoord.y, S.capColor.w);
        c = S.capColor.rgb * (hatch < 1.5 ? 0.55 : 1.0);
    } else {
        const bool selected = (flags & KERF_FEATURE_SELECTED) != 0u;
        if (selected) albedo = mix(albedo, S.highlight.rgb, S.highlight.w);
        c = lightSurface(S, albedo, nrm, -dir);
    }

    if ((S.flags & KERF_SHADE_EDGES) != 0u) {
        // Silhouette and crease lines: a neighbour that is background, much
        // farther or nearer, or another feature; the outline of a selection.
        float edge = 0.0;
        bool outline = false;
        const bool selected = (flags & KERF_FEATURE_SELECTED) != 0u;
        const ivec2 offs[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
        for (int k = 0; k < 4; ++k) {
            const float tn = depthAt(p + offs[k]);
            const uint fn = featureAt(p + offs[k]);
            if (isinf(tn) || abs(tn - t) > 0.02 * t) edge = 1.0;
            else if (fn != feature) edge = max(edge, 0.6);
            if (selected && (isinf(tn) || (flagsOf(fn) & KERF_FEATURE_SELECTED) == 0u)) outline = true;
        }
        c *= 1.0 - S.defaultColor.w * edge;
        if (outline) c = S.highlight.rgb;
    }
    outColor = vec4(toSrgb(c), 1.0);
}

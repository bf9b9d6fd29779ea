#version 460
// The axis gizmo in a corner of the viewport: the world's X (red), Y
// (green) and Z (blue) axes as the camera sees them, drawn analytically as
// antialiased segments from the centre, nearer axes over farther ones.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "RenderShared.h"

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ShadeRef { ShadeParams s; };
layout(push_constant) uniform Push { GizmoPush g; } pc;
layout(location = 0) out vec4 outColor;

float segment(vec2 p, vec2 a, vec2 b)
{
    const vec2 pa = p - a, ba = b - a;
    const float h = clamp(dot(pa, ba) / max(dot(ba, ba), 1e-6), 0.0, 1.0);
    return length(pa - ba * h);
}

void main()
{
    const ShadeParams S = ShadeRef(pc.g.shade).s;
    const float size = pc.g.rect.z;
    // Pixel position relative to the gizmo's centre, y up.
    const vec2 q = vec2(gl_FragCoord.x - pc.g.rect.x - 0.5 * size, pc.g.rect.y + 0.5 * size - gl_FragCoord.y);
    const vec3 axes[3] = vec3[3](vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1));
    const vec3 colors[3] = vec3[3](vec3(0.90, 0.25, 0.22), vec3(0.35, 0.80, 0.25), vec3(0.25, 0.45, 0.95));
    const float reach = 0.38 * size;
    vec4 result = vec4(0.0);
    float nearest = 1e9;
    for (int k = 0; k < 3; ++k) {
        const vec2 tip = reach * vec2(dot(axes[k], S.right.xyz), dot(axes[k], S.up.xyz));
        const float depth = dot(axes[k], S.forward.xyz); // towards the viewer is negative
        const float d = segment(q, vec2(0.0), tip);
        const float cover = clamp(2.0 - d, 0.0, 1.0);
        const float cap = clamp(4.0 - length(q - tip), 0.0, 1.0); // a dot at the tip
        const float a = max(cover, cap);
        if (a > 0.0 && depth < nearest) {
            nearest = depth;
            const vec3 c = colors[k] * (depth > 0.0 ? 0.6 : 1.0); // axes pointing away are dimmer
            result = vec4(c, a);
        }
    }
    if (result.a <= 0.003) discard;
    outColor = result;
}

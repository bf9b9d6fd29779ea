#version 460
// The ground grid: the plane z = 0 under the part, found per pixel by
// intersecting the pixel's ray with it, with minor and major lines
// antialiased by their screen-space width and faded with distance. Depth
// tested against the part and meshes (drawn before it) and blended over them.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "RenderShared.h"

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ShadeRef { ShadeParams s; };
layout(push_constant) uniform Push { uint64_t shade; } pc;
layout(location = 0) out vec4 outColor;

// Coverage of lines every `spacing` mm at plane coordinates q, about a
// pixel wide. Lines closer than about ten pixels apart on screen fade out
// before they would turn the plane into a grey moire.
float lines(vec2 q, float spacing)
{
    const vec2 g = q / spacing;
    const vec2 width = fwidth(g); // grid cells per pixel
    const vec2 d = abs(fract(g - 0.5) - 0.5) / max(width, vec2(1e-6));
    const float density = max(width.x, width.y);
    return (1.0 - min(min(d.x, d.y), 1.0)) * (1.0 - smoothstep(0.04, 0.1, density));
}

void main()
{
    const ShadeParams S = ShadeRef(pc.shade).s;
    const float aspect = float(S.width) / float(S.height);
    const float u = (2.0 * gl_FragCoord.x / float(S.width) - 1.0) * aspect;
    const float w = 1.0 - 2.0 * gl_FragCoord.y / float(S.height);
    const bool ortho = (S.flags & KERF_SHADE_ORTHO) != 0u;
    vec3 origin = S.eye.xyz;
    vec3 dir;
    if (ortho) {
        origin += (u * S.up.w) * S.right.xyz + (w * S.up.w) * S.up.xyz;
        dir = S.forward.xyz;
    } else {
        dir = normalize(S.forward.xyz + (u * S.up.w) * S.right.xyz + (w * S.up.w) * S.up.xyz);
    }
    if (abs(dir.z) < 1e-6) discard;
    const float t = -origin.z / dir.z;
    if (t <= 0.0) discard;
    const vec3 hit = origin + t * dir;
    const float z = t * dot(dir, S.forward.xyz);
    const float n = S.forward.w, f = S.right.w;
    if (z <= n || z >= f) discard;
    gl_FragDepth = ortho ? (z - n) / (f - n) : f * (z - n) / (z * (f - n));

    const float minor = lines(hit.xy, S.grid.x), major = lines(hit.xy, S.grid.y);
    // Fade with distance and at grazing angles, where lines would alias.
    const float fade = clamp(1.0 - length(hit.xy - S.eye.xy) / S.grid.z, 0.0, 1.0) * smoothstep(0.02, 0.2, abs(dir.z));
    // The X and Y axes in their colours.
    const vec2 axisWidth = fwidth(hit.xy);
    const float onX = 1.0 - min(abs(hit.y) / max(axisWidth.y, 1e-6), 1.0);
    const float onY = 1.0 - min(abs(hit.x) / max(axisWidth.x, 1e-6), 1.0);
    vec3 color = vec3(0.78);
    float alpha = max(minor * 0.18, major * 0.32);
    if (onX > 0.0) { color = vec3(0.85, 0.25, 0.22); alpha = max(alpha, onX * 0.9); }
    if (onY > 0.0) { color = vec3(0.35, 0.75, 0.25); alpha = max(alpha, onY * 0.9); }
    alpha *= fade;
    if (alpha <= 0.003) discard;
    outColor = vec4(color, alpha);
}

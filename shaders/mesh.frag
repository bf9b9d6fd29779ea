#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "RenderShared.h"

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ShadeRef { ShadeParams s; };
layout(push_constant) uniform Push { MeshPush m; } pc;
layout(location = 0) in vec3 worldNormal;
layout(location = 1) in vec3 worldPosition;
layout(location = 0) out vec4 outColor;

#include "lighting.glsl"

void main()
{
    const ShadeParams s = ShadeRef(pc.m.shade).s;
    vec3 n = normalize(worldNormal);
    // Meshes may be open or inconsistently wound: light the side we see.
    // The headlight direction stands in for the direction to the eye.
    const vec3 toViewer = -s.forward.xyz;
    if (dot(n, toViewer) < 0.0) n = -n;
    // Alpha is the mesh's opacity: 1 for meshes and markers (drawn unblended),
    // less for ghosts (blended).
    outColor = vec4(toSrgb(lightSurface(s, pc.m.color.rgb, n, toViewer)), pc.m.color.a);
}

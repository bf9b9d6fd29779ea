#version 460
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "RenderShared.h"

layout(location = 0) in vec3 position; // mm, relative to the render origin
layout(location = 1) in vec3 normal;
layout(push_constant) uniform Push { MeshPush m; } pc;
layout(location = 0) out vec3 worldNormal;
layout(location = 1) out vec3 worldPosition;

void main()
{
    worldNormal = normal;
    worldPosition = position;
    gl_Position = pc.m.clipFromWorld * vec4(position, 1.0);
}

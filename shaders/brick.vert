#version 460
// The brick renderer's cubes: one instance per brick, 36 vertices each
// (no vertex buffer). The fragment shader marches the brick's samples.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "BrickShared.h"

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Instances { BrickInstance b[]; };
layout(push_constant) uniform Push { BrickPush p; } pc;
layout(location = 0) out vec3 eyeRelative;   // the cube's point, relative to the eye (mm)
layout(location = 1) flat out uint instance;

// Two triangles per face, counter-clockwise seen from outside.
const uint kCorners[36] = uint[36](0, 2, 3, 0, 3, 1,   // z = 0
                                   4, 5, 7, 4, 7, 6,   // z = 1
                                   0, 1, 5, 0, 5, 4,   // y = 0
                                   2, 6, 7, 2, 7, 3,   // y = 1
                                   0, 4, 6, 0, 6, 2,   // x = 0
                                   1, 3, 7, 1, 7, 5);  // x = 1

void main()
{
    const BrickInstance brick = Instances(pc.p.instances).b[gl_InstanceIndex];
    const uint c = kCorners[gl_VertexIndex];
    const vec3 corner = vec3(float(c & 1u), float((c >> 1) & 1u), float(c >> 2));
    const float edge = brick.minEdge.w * float(brick.slot.w);
    eyeRelative = brick.minEdge.xyz + corner * edge;
    instance = uint(gl_InstanceIndex);
    gl_Position = pc.p.clipFromEye * vec4(eyeRelative, 1.0);
    // A brick wholly on the side a section plane takes away (BrickPush::section:
    // its corner nearest the kept side is beyond the plane) would discard
    // every fragment (brick.frag clips its march to the kept side): it gets
    // no fragments at all. A hundredth of a voxel of slack keeps a brick whose
    // face lies on the plane, which brick.frag decides as before.
    const vec3 n = pc.p.section.xyz;
    if (n != vec3(0.0)) {
        const vec3 nearest = brick.minEdge.xyz + vec3(lessThan(n, vec3(0.0))) * edge;
        if (dot(n, nearest) - pc.p.section.w > 0.01 * brick.minEdge.w) gl_Position = vec4(0.0, 0.0, 0.0, -1.0);
    }
}

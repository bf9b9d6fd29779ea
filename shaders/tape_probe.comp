#version 460
// Evaluates one encoded tile tape through the GLSL tape library (tape.glsl)
// at many points (values, gradients, features) or over many boxes
// (intervals): TapeProbe's kernel, for the test that holds the GLSL and C++
// tape evaluators to the same results.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64) in;

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Words { uint w[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Inputs { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer Results { vec4 r[]; };

layout(push_constant) uniform Push
{
    uint64_t tape;    // the encoded tape's words
    uint64_t inputs;  // points: one vec4 each (xyz: tile-relative mm); boxes: two (lo, then hi)
    uint64_t results; // two vec4 each: points (value, feature bits, 0, 0), then the dual (value, gradient);
                      // boxes (lo, hi, 0, 0), then zeros
    uint count;
    uint boxes;       // 1: the inputs are boxes
} pc;

uint tapeWord(uint t, uint i) { return Words(pc.tape).w[t + i]; }

#include "tape.glsl"

void main()
{
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    if (pc.boxes != 0u) {
        const vec3 lo = Inputs(pc.inputs).v[2u * i].xyz, hi = Inputs(pc.inputs).v[2u * i + 1u].xyz;
        Results(pc.results).r[2u * i] = vec4(evaluateTileTapeInterval(0u, lo, hi), 0.0, 0.0);
        Results(pc.results).r[2u * i + 1u] = vec4(0.0);
        return;
    }
    const vec3 p = Inputs(pc.inputs).v[i].xyz;
    uint feature;
    const vec4 dual = evaluateTileTapeGradient(0u, p, feature);
    Results(pc.results).r[2u * i] = vec4(evaluateTileTape(0u, p), uintBitsToFloat(feature), 0.0, 0.0);
    Results(pc.results).r[2u * i + 1u] = dual;
}

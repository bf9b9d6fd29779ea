// The GLSL tape library: a tile's encoded exact tape (TileTapeFormat.h)
// evaluated at a tile-relative point, as values and as values with
// gradients (forward differentiation: dual numbers as vec4, x the value,
// yzw the gradient). The primitives and the stack machine are written once,
// in tape_body.glsl, included here twice: with T = float and with T = vec4.
// Its C++ counterpart is voxelizer/src/TileTape.cpp over the sdf:: templates
// of evaluator/include/kerf/evaluator/Primitives.hpp; TapeLanguagesTest holds
// the two to the same values on every shape kind.
//
// The includer first defines where the tapes live:
//   uint tapeWord(uint t, uint i)   word i of the tape starting at word t
// and gets:
//   float evaluateTileTape(uint t, vec3 p)
//   vec4  evaluateTileTapeGradient(uint t, vec3 p, out uint feature)
// A shape kind this library does not know makes the result NaN (never a
// plane that hides the mistake).
#ifndef KERF_TAPE_GLSL
#define KERF_TAPE_GLSL

#include "kerf/voxelizer/TileTapeFormat.h"

float tapeFloat(uint t, uint i) { return uintBitsToFloat(tapeWord(t, i)); }
#define kTapeNaN uintBitsToFloat(0x7fc00000u)
#define kTapeFloatMax uintBitsToFloat(0x7f7fffffu) // std::numeric_limits<float>::max()
// Set by a shape of a kind this library does not know; the evaluators make
// their whole result NaN then (a min or max could pass over one NaN). Only
// that path writes it: the loop pays nothing per primitive.
bool tapeUnknownKind = false;

// The arithmetic that differs between values and duals; +, - and scaling
// by a float are the same for both (vec4 arithmetic is the dual's there).
float valT(float a) { return a; }
float valT(vec4 a) { return a.x; }
float mulT(float a, float b) { return a * b; }
vec4 mulT(vec4 a, vec4 b) { return vec4(a.x * b.x, a.yzw * b.x + a.x * b.yzw); }
float sqT(float a) { return a * a; }
vec4 sqT(vec4 a) { return mulT(a, a); }
float sqrtT(float a) { return sqrt(a); }
vec4 sqrtT(vec4 a)
{
    // Dual.hpp's rule: 0 where the root is 0 (only squared lengths are rooted).
    const float s = sqrt(a.x);
    return vec4(s, a.yzw * (s > 0.0 ? 0.5 / s : 0.0));
}
float absT(float a) { return abs(a); }
vec4 absT(vec4 a) { return a.x < 0.0 ? -a : a; }
// GLSL's min(x, y) is "y if y < x, else x": Dual.hpp's rule, in one instruction.
float minT(float a, float b) { return min(a, b); }
vec4 minT(vec4 a, vec4 b) { return b.x < a.x ? b : a; }
float maxT(float a, float b) { return max(a, b); }
vec4 maxT(vec4 a, vec4 b) { return a.x < b.x ? b : a; }

// Local coordinates of tile-relative p by the frame at word f; as duals,
// each carries its row of the frame as its gradient.
void localT(uint t, uint f, vec3 p, out float lx, out float ly, out float lz)
{
    lx = tapeFloat(t, f) * p.x + tapeFloat(t, f + 1u) * p.y + tapeFloat(t, f + 2u) * p.z + tapeFloat(t, f + 9u);
    ly = tapeFloat(t, f + 3u) * p.x + tapeFloat(t, f + 4u) * p.y + tapeFloat(t, f + 5u) * p.z + tapeFloat(t, f + 10u);
    lz = tapeFloat(t, f + 6u) * p.x + tapeFloat(t, f + 7u) * p.y + tapeFloat(t, f + 8u) * p.z + tapeFloat(t, f + 11u);
}
void localT(uint t, uint f, vec3 p, out vec4 lx, out vec4 ly, out vec4 lz)
{
    float x, y, z;
    localT(t, f, p, x, y, z);
    lx = vec4(x, tapeFloat(t, f), tapeFloat(t, f + 1u), tapeFloat(t, f + 2u));
    ly = vec4(y, tapeFloat(t, f + 3u), tapeFloat(t, f + 4u), tapeFloat(t, f + 5u));
    lz = vec4(z, tapeFloat(t, f + 6u), tapeFloat(t, f + 7u), tapeFloat(t, f + 8u));
}

#define T float
#define cT(c) float(c)
#define KERF_TAPE_EVALUATE evaluateTileTapeValue
#include "tape_body.glsl"
#undef T
#undef cT
#undef KERF_TAPE_EVALUATE

#define T vec4
#define cT(c) vec4(c, 0.0, 0.0, 0.0)
#define KERF_TAPE_EVALUATE evaluateTileTapeGradient
#define KERF_TAPE_FEATURES
#include "tape_body.glsl"
#undef T
#undef cT
#undef KERF_TAPE_EVALUATE
#undef KERF_TAPE_FEATURES

float evaluateTileTape(uint t, vec3 p)
{
    uint unused;
    return evaluateTileTapeValue(t, p, unused);
}

#endif

// The GLSL tape library: a tile's encoded exact tape (TileTapeFormat.h)
// evaluated at a tile-relative point as values and as values with gradients
// (forward differentiation: dual numbers as vec4, x the value, yzw the
// gradient), and over a tile-relative box as an interval (vec2: lo, hi)
// that encloses every value inside it. The primitives (tape_shapes.glsl)
// and the stack machine (tape_machine.glsl) are written once and included
// here three times: T = float, vec4 and vec2. Its C++ counterparts are
// voxelizer/src/TileTape.cpp over the sdf:: templates of
// evaluator/include/kerf/evaluator/Primitives.hpp (points, gradients) and
// evaluator/src/IntervalEvaluator.cpp (intervals); TapeLanguagesTest holds
// the two languages to the same results on every shape kind.
//
// The includer first defines where the tapes live:
//   uint tapeWord(uint t, uint i)   word i of the tape starting at word t
// and gets:
//   float evaluateTileTape(uint t, vec3 p)
//   vec4  evaluateTileTapeGradient(uint t, vec3 p, out uint feature)
//   vec2  evaluateTileTapeInterval(uint t, vec3 lo, vec3 hi)
// A shape kind this library does not know makes the result NaN (never a
// plane that hides the mistake).
#ifndef KERF_TAPE_GLSL
#define KERF_TAPE_GLSL

#include "kerf/voxelizer/TileTapeFormat.h"
#include "kerf/evaluator/FeatureTie.h"

float tapeFloat(uint t, uint i) { return uintBitsToFloat(tapeWord(t, i)); }
#define kTapeNaN uintBitsToFloat(0x7fc00000u)
#define kTapeInf uintBitsToFloat(0x7f800000u)
#define kTapeFloatMax uintBitsToFloat(0x7f7fffffu) // std::numeric_limits<float>::max()
#define kTapeFloatMinNormal uintBitsToFloat(0x00800000u)
// Set by a shape of a kind this library does not know; the evaluators make
// their whole result NaN then (a min or max could pass over one NaN). Only
// that path writes it: the loop pays nothing per primitive.
bool tapeUnknownKind = false;

#ifdef KERF_TAPE_PRUNING
// ---- Tapes pruned per box (the GPU voxelizer) ----
// The instructions of the tape that the evaluators pass over (bit i:
// instruction i; only tapes of at most 64 instructions have any): a min or
// max that one operand decides everywhere in a box leaves the other operand
// and itself out, the post-order stack then holding the deciding operand
// where the operation's result would be. Set by the includer before an
// evaluation; the interval evaluator adds to it what its box leaves out
// when tapePruning is on (KERF_TAPE_RECORD_PRUNING).
uvec2 tapeSkip = uvec2(0u);
bool tapePruning = false;
bool tapeSkipped(uint i) { return i < 64u && ((i < 32u ? tapeSkip.x >> i : tapeSkip.y >> (i - 32u)) & 1u) != 0u; }
// Instructions first..last (< 64) left out.
void tapeSkipRange(uint first, uint last)
{
    for (uint w = 0u; w < 2u; ++w) {
        const uint lo = max(first, 32u * w), hi = min(last, 32u * w + 31u);
        if (lo > hi) continue;
        const uint width = hi - lo + 1u;
        const uint bits = (width == 32u ? 0xFFFFFFFFu : (1u << width) - 1u) << (lo - 32u * w);
        if (w == 0u) tapeSkip.x |= bits;
        else tapeSkip.y |= bits;
    }
}
#endif

// ---- Values (float) and duals (vec4) ----
// Dual arithmetic is vec4 arithmetic for +, - and scaling by a float; the
// product, square root, abs, min and max follow Dual.hpp's rules.
float valT(float a) { return a; }
float valT(vec4 a) { return a.x; }
float addT(float a, float b) { return a + b; }
vec4 addT(vec4 a, vec4 b) { return a + b; }
float subT(float a, float b) { return a - b; }
vec4 subT(vec4 a, vec4 b) { return a - b; }
float negT(float a) { return -a; }
vec4 negT(vec4 a) { return -a; }
float scaleT(float a, float s) { return a * s; }
vec4 scaleT(vec4 a, float s) { return a * s; }
float divT(float a, float s) { return a / s; }
vec4 divT(vec4 a, float s) { return a / s; }
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

// ---- Intervals (vec2: lo, hi) ----
// Outward rounding as kerf::Interval does it: each result of +, - and * one
// float step wider on each side (Vulkan rounds them correctly); the square
// root, which Vulkan allows about three ulps off (it inherits the precision
// of 1 / inversesqrt), by four: a relative 2^-21. min, max,
// abs and negation are exact. There is no product of two intervals and no
// value to branch on (valT): a shape that needs them has no interval instance.
float stepUp(float v)
{
    if (!(v < kTapeInf)) return v; // +inf, NaN
    if (v == 0.0) return kTapeFloatMinNormal; // not a denormal: a device may flush those to 0
    const uint bits = floatBitsToUint(v);
    return uintBitsToFloat(v > 0.0 ? bits + 1u : bits - 1u);
}
float stepDown(float v) { return -stepUp(-v); }
vec2 widenI(float lo, float hi) { return vec2(stepDown(lo), stepUp(hi)); }
vec2 addT(vec2 a, vec2 b) { return widenI(a.x + b.x, a.y + b.y); }
vec2 subT(vec2 a, vec2 b) { return widenI(a.x - b.y, a.y - b.x); }
vec2 negT(vec2 a) { return -a.yx; }
vec2 scaleT(vec2 a, float s) { return s >= 0.0 ? widenI(a.x * s, a.y * s) : widenI(a.y * s, a.x * s); }
vec2 sqT(vec2 a)
{
    // x^2 over an interval that straddles 0 has its minimum 0 (a * a would go below).
    const float l2 = a.x * a.x, h2 = a.y * a.y;
    if (a.x >= 0.0) return widenI(l2, h2);
    if (a.y <= 0.0) return widenI(h2, l2);
    return vec2(0.0, stepUp(max(l2, h2)));
}
vec2 sqrtT(vec2 a)
{
    // Roots of sums of squares: a lower end below 0 is rounding, clamped.
    const float rel = 1.0 / 2097152.0;
    const float lo = a.x <= 0.0 ? 0.0 : max(sqrt(a.x) * (1.0 - rel), 0.0);
    const float hi = a.y <= 0.0 ? 0.0 : sqrt(a.y) * (1.0 + rel);
    return vec2(lo, hi);
}
vec2 absT(vec2 a)
{
    if (a.x >= 0.0) return a;
    if (a.y <= 0.0) return -a.yx;
    return vec2(0.0, max(-a.x, a.y));
}
vec2 minT(vec2 a, vec2 b) { return min(a, b); }
vec2 maxT(vec2 a, vec2 b) { return max(a, b); }

// ---- The three instances ----
#define T float
#define cT(c) float(c)
#include "tape_shapes.glsl"
#define KERF_TAPE_EVALUATE evaluateTileTapeValue
#include "tape_machine.glsl"
#undef T
#undef cT
#undef KERF_TAPE_EVALUATE

#define T vec4
#define cT(c) vec4(c, 0.0, 0.0, 0.0)
#define KERF_TAPE_DUALS
#include "tape_shapes.glsl"
#undef KERF_TAPE_DUALS
#define KERF_TAPE_EVALUATE evaluateTileTapeDual
#define KERF_TAPE_FEATURES
#include "tape_machine.glsl"
#undef T
#undef cT
#undef KERF_TAPE_EVALUATE
#undef KERF_TAPE_FEATURES

#define T vec2
#define cT(c) vec2(c)
#define KERF_TAPE_INTERVALS
#include "tape_shapes.glsl"

// The primitive at word s over the tape-relative box (px, py, pz), as
// shapeInterval (IntervalEvaluator.cpp): its value at the centre widened by
// the half diagonal (a distance field changes by at most the distance
// moved; frames are rigid), intersected with its enclosure. The centre's
// float evaluation is off by a few ulps of the magnitudes involved; the
// margin covers that many times over.
vec2 primitiveT(uint t, uint s, vec2 px, vec2 py, vec2 pz)
{
    const uint f = s + KERF_TAPE_SHAPE_FRAME;
    const vec3 c = 0.5 * vec3(px.x + px.y, py.x + py.y, pz.x + pz.y);
    const vec3 halfSize = 0.5 * vec3(px.y - px.x, py.y - py.x, pz.y - pz.x);
    float cx, cy, cz;
    localT(t, f, c.x, c.y, c.z, cx, cy, cz);
    const float fc = shapeT(t, s, cx, cy, cz);
    const uint a = s + KERF_TAPE_SHAPE_PARAMS;
    const uint kind = tapeWord(t, s);
    float scale = abs(cx) + abs(cy) + abs(cz) + abs(c.x) + abs(c.y) + abs(c.z) + abs(tapeFloat(t, a));
    if (kind == KERF_SHAPE_EXTRUDE || kind == KERF_SHAPE_REVOLVE) {
        vec2 lo, hi;
        polygonBounds(t, tapeWord(t, a + 1u), tapeWord(t, a + 2u), lo, hi);
        scale += max(max(abs(lo.x), abs(lo.y)), max(abs(hi.x), abs(hi.y)));
    } else {
        for (uint i = 1u; i < 6u; ++i) scale += abs(tapeFloat(t, a + i));
    }
    const float reach = length(halfSize) * (1.0 + 1.0 / 1048576.0) + (scale + 1.0) * (1.0 / 1048576.0);
    const vec2 lipschitz = widenI(fc - reach, fc + reach);
    vec2 x, y, z;
    localT(t, f, px, py, pz, x, y, z);
    const vec2 e = enclosureT(t, s, x, y, z);
    return vec2(max(lipschitz.x, e.x), min(lipschitz.y, e.y));
}

// Monotone in both operands (smooth min and max) or convex (the shell, with
// its minimum -thickness/2 at -thickness/2): their images are taken at the
// ends, widened by a relative margin over the few roundings inside.
vec2 widenBy(vec2 v, float k)
{
    const float m = 1.0 / 262144.0;
    return vec2(v.x - (abs(v.x) + k) * m, v.y + (abs(v.y) + k) * m);
}
vec2 smoothMinT(vec2 a, vec2 b, float k) { return widenBy(vec2(smoothMinT(a.x, b.x, k), smoothMinT(a.y, b.y, k)), k); }
vec2 smoothMaxT(vec2 a, vec2 b, float k) { return widenBy(vec2(smoothMaxT(a.x, b.x, k), smoothMaxT(a.y, b.y, k)), k); }
vec2 shellT(vec2 a, float thickness)
{
    const float dMin = clamp(-0.5 * thickness, a.x, a.y);
    return widenBy(vec2(shellT(dMin, thickness), max(shellT(a.x, thickness), shellT(a.y, thickness))), thickness);
}

#ifdef KERF_TAPE_PRUNING
// Which operand of binary operation `op` decides it everywhere in the box
// of the intervals a and b: 1 (a), 2 (b) or 0 (both can). A smooth one
// needs its operands k apart, where its blend term is exactly 0. The
// point evaluators must then compute exactly what the whole tape does (the
// voxels are compared bit for bit with the CPU's), so the operands must be
// apart by more than their float evaluation can err: a relative 2^-16 more
// (the intervals already hold the float values with a 2^-20 margin).
uint tapeDecidingOperand(uint op, vec2 a, vec2 b, float k)
{
    const float m = (1.0 + max(max(abs(a.x), abs(a.y)), max(abs(b.x), abs(b.y)))) * (1.0 / 65536.0);
    const float gap = op == KERF_TAPE_SMOOTH_MIN || op == KERF_TAPE_SMOOTH_MAX ? k + m : m;
    if (op == KERF_TAPE_MIN || op == KERF_TAPE_SMOOTH_MIN) {
        if (a.y + gap < b.x) return 1u;
        if (b.y + gap < a.x) return 2u;
    } else {
        if (a.x > b.y + gap) return 1u;
        if (b.x > a.y + gap) return 2u;
    }
    return 0u;
}
#define KERF_TAPE_RECORD_PRUNING
#endif
#define KERF_TAPE_EVALUATE evaluateTileTapeIntervalT
#include "tape_machine.glsl"
#undef KERF_TAPE_RECORD_PRUNING
#undef T
#undef cT
#undef KERF_TAPE_EVALUATE
#undef KERF_TAPE_INTERVALS

float evaluateTileTape(uint t, vec3 p)
{
    uint unused;
    return evaluateTileTapeValue(t, p.x, p.y, p.z, unused);
}

// Each coordinate's derivative seeds its axis of the gradient.
vec4 evaluateTileTapeGradient(uint t, vec3 p, out uint feature)
{
    return evaluateTileTapeDual(t, vec4(p.x, 1.0, 0.0, 0.0), vec4(p.y, 0.0, 1.0, 0.0), vec4(p.z, 0.0, 0.0, 1.0), feature);
}

vec2 evaluateTileTapeInterval(uint t, vec3 lo, vec3 hi)
{
    uint unused;
    return evaluateTileTapeIntervalT(t, vec2(lo.x, hi.x), vec2(lo.y, hi.y), vec2(lo.z, hi.z), unused);
}

#endif

#include "kerf/tracer/ReferenceTracer.hpp"

#include "kerf/tracer/ExactRefinement.h"
#include "kerf/tracer/VoxelHitCheck.hpp"
#include "kerf/voxelizer/TileTape.hpp"
#include "kerf/voxelizer/WorkerArena.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <tbb/task_arena.h>

#include <bit>
#include <cmath>

// Written to be ported to GLSL: glm types stand for GLSL's, std::popcount for
// bitCount, and every helper takes and returns plain values.

namespace kerf {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// Bisection steps of a monotone piece of a voxel's segment (at most sqrt(3)
// voxel edges long): 2^-16 of that is far below the float error of the entry.
constexpr int kBisectionSteps = 16;

bool hasChild(const voxel::Node& n, int c)
{
    return c < 32 ? ((n.maskLo >> c) & 1u) != 0u : ((n.maskHi >> (c - 32)) & 1u) != 0u;
}

// Position of child c among the node's populated children.
std::uint32_t childRank(const voxel::Node& n, int c)
{
    if (c < 32) return std::uint32_t(std::popcount(n.maskLo & ((1u << c) - 1u)));
    const std::uint32_t below = c == 32 ? 0u : n.maskHi & ((1u << (c - 32)) - 1u);
    return std::uint32_t(std::popcount(n.maskLo) + std::popcount(below));
}

// Trilinear interpolation in the monomial basis:
// f = k0 + k1 x + k2 y + k3 z + k4 xy + k5 yz + k6 xz + k7 xyz, (x, y, z) in [0, 1]^3.
struct Trilinear {
    float k[8];
};

Trilinear trilinear(const float d[8])
{
    Trilinear t;
    t.k[0] = d[0];
    t.k[1] = d[1] - d[0];
    t.k[2] = d[2] - d[0];
    t.k[3] = d[4] - d[0];
    t.k[4] = d[3] - d[2] - d[1] + d[0];
    t.k[5] = d[6] - d[4] - d[2] + d[0];
    t.k[6] = d[5] - d[4] - d[1] + d[0];
    t.k[7] = d[7] - d[6] - d[5] - d[3] + d[4] + d[2] + d[1] - d[0];
    return t;
}

glm::vec3 trilinearGradient(const Trilinear& t, const glm::vec3& u)
{
    return {t.k[1] + t.k[4] * u.y + t.k[6] * u.z + t.k[7] * u.y * u.z,
            t.k[2] + t.k[4] * u.x + t.k[5] * u.z + t.k[7] * u.x * u.z,
            t.k[3] + t.k[5] * u.y + t.k[6] * u.x + t.k[7] * u.x * u.y};
}

// The trilinear field along o + w d as a cubic a0 + a1 w + a2 w^2 + a3 w^3.
struct Cubic {
    float a0, a1, a2, a3;
};

Cubic alongRay(const Trilinear& t, const glm::vec3& o, const glm::vec3& d)
{
    const float* k = t.k;
    Cubic c;
    c.a0 = k[0] + k[1] * o.x + k[2] * o.y + k[3] * o.z + k[4] * o.x * o.y + k[5] * o.y * o.z + k[6] * o.x * o.z +
           k[7] * o.x * o.y * o.z;
    c.a1 = k[1] * d.x + k[2] * d.y + k[3] * d.z + k[4] * (o.x * d.y + o.y * d.x) + k[5] * (o.y * d.z + o.z * d.y) +
           k[6] * (o.x * d.z + o.z * d.x) + k[7] * (d.x * o.y * o.z + o.x * d.y * o.z + o.x * o.y * d.z);
    c.a2 = k[4] * d.x * d.y + k[5] * d.y * d.z + k[6] * d.x * d.z +
           k[7] * (d.x * d.y * o.z + d.x * o.y * d.z + o.x * d.y * d.z);
    c.a3 = k[7] * d.x * d.y * d.z;
    return c;
}

float evalCubic(const Cubic& c, float w) { return c.a0 + w * (c.a1 + w * (c.a2 + w * c.a3)); }

// First w in [0, wEnd] with f(w) <= 0, or -1 when the segment stays
// outside; then `least` is the field's minimum over the segment.
// What counts as zero in a voxel's cubic along a ray, relative to the sum
// of its coefficients' sizes (float rounding of the trilinear sum is a few
// times 1e-7 of it). shaders/trace.comp has the same.
constexpr float kCubicZero = 1e-5f;
float cubicZero(const Cubic& c) { return kCubicZero * (std::abs(c.a0) + std::abs(c.a1) + std::abs(c.a2) + std::abs(c.a3)); }

float firstCrossing(const Cubic& c, float wEnd, float& least)
{
    // The extrema of the cubic (roots of its derivative) split the segment
    // into at most three monotone pieces, each holding at most one root.
    float r1 = kInf, r2 = kInf;
    const float qa = 3.0f * c.a3, qb = 2.0f * c.a2, qc = c.a1;
    if (qa != 0.0f) {
        const float disc = qb * qb - 4.0f * qa * qc;
        if (disc >= 0.0f) {
            // The numerically stable pair of quadratic roots.
            const float q = -0.5f * (qb + std::copysign(std::sqrt(disc), qb));
            r1 = q / qa;
            r2 = q != 0.0f ? qc / q : r1;
        }
    } else if (qb != 0.0f) {
        r1 = -qc / qb;
    }
    if (r2 < r1) {
        const float tmp = r1;
        r1 = r2;
        r2 = tmp;
    }
    float breaks[4] = {0.0f, wEnd, wEnd, wEnd};
    int count = 1;
    if (r1 > 0.0f && r1 < wEnd) breaks[count++] = r1;
    if (r2 > 0.0f && r2 < wEnd && r2 != r1) breaks[count++] = r2;
    breaks[count++] = wEnd;

    // Inside is below zero, as the voxelizer counts a corner (0 counts as
    // outside), and a value within the cubic's rounding of zero is zero: a
    // voxel whose face lies on a face of the part that a tool cuts flush (a
    // blind hole's mouth) has 0 at every corner of that face, and taking
    // the cubic's -1e-8 there as a hit drew a film across the mouth.
    const float zero = cubicZero(c);
    float a = breaks[0];
    float fa = evalCubic(c, a);
    least = fa;
    if (fa < -zero) return a;
    for (int i = 1; i < count; ++i) {
        const float b = breaks[i];
        const float fb = evalCubic(c, b);
        least = glm::min(least, fb);
        if (fb < -zero) {
            // Monotone on [a, b] with f(a) >= -zero > f(b): bisect.
            float lo = a, hi = b;
            for (int k = 0; k < kBisectionSteps; ++k) {
                const float mid = 0.5f * (lo + hi);
                if (evalCubic(c, mid) < -zero)
                    hi = mid;
                else
                    lo = mid;
            }
            return hi;
        }
        a = b;
        fa = fb;
    }
    return -1.0f;
}

// The clearance the hit check asks of a ray passing this voxel without a
// hit (voxel edges): how far its exact surface may stand out from the
// trilinear one. Where the field is smooth that is about (sqrt(3)/8) h
// times the angle the corner normals turn through (the trilinear error of
// a distance field of curvature k is (3/8) h^2 k, and the normals turn by
// sqrt(3) h k across the voxel); twice that, between the smooth floor and
// the sharp-edge ceiling (an edge rounds off by up to half a voxel).
float cornerClearance(const FlatVoxelBuffers& b, std::uint32_t vertexBase, const voxel::LeafData& ld)
{
    const glm::vec3 first = voxel::decodeNormal(b.vertices[vertexBase + ld.corner[0]].normal);
    float least = 1.0f; // the least cosine between the first corner's normal and another's
    for (int q = 1; q < 8; ++q)
        least = glm::min(least, glm::dot(first, voxel::decodeNormal(b.vertices[vertexBase + ld.corner[q]].normal)));
    const float turn = std::acos(glm::clamp(least, -1.0f, 1.0f));
    return glm::clamp(float(KERF_EDGE_CHECK_CLEARANCE_PER_RADIAN) * turn, float(KERF_EDGE_CHECK_SMOOTH_CLEARANCE),
                      float(KERF_EDGE_CHECK_CLEARANCE));
}

// A component of a direction is never exactly zero, so that 1/d is finite
// and the slab and cell exits need no special case (1e-20 bends nothing).
float nonZero(float v) { return std::fabs(v) < 1e-20f ? (v < 0.0f ? -1e-20f : 1e-20f) : v; }

// The hybrid refinement (TraceQuality::Exact). The ray inside a tile is
// e + s * dir in tile units; the tile's exact tape takes tile-relative
// millimetres.

// The exact field at ray parameter s, in tile edges.
float exactAt(const std::uint32_t* tape, const glm::vec3& e, const glm::vec3& dir, float tileSize, float s,
              std::uint32_t& evaluations)
{
    ++evaluations;
    return voxel::evaluateTileTape(tape, (e + s * dir) * tileSize) / tileSize;
}

// Whether the exact field, having come within KERF_EXACT_EPSILON of zero at
// sHit, rises on beyond it at half its slope or more instead of going below
// zero: the ray met a sheet of no thickness, not a surface it enters. Where
// a tool is cut flush with a face (a blind hole's mouth), the face's field
// and the hole's are both 0 across the mouth, and the search stopped there,
// drawing a film across the hole with Exact Edges on.
bool onlyTouches(const std::uint32_t* tape, const glm::vec3& e, const glm::vec3& dir, float tileSize, float sHit,
                 float voxelEdge, std::uint32_t& evaluations)
{
    // Just past where the sheet would be (within KERF_EXACT_EPSILON ahead),
    // and further: three points the GPU's lanes evaluate in one round.
    const float f0 = exactAt(tape, e, dir, tileSize, sHit, evaluations);
    const float nearStep = float(2.0 * KERF_EXACT_EPSILON + KERF_EXACT_TOUCH_NEAR) * voxelEdge;
    const float farStep = float(KERF_EXACT_TOUCH_FAR) * voxelEdge;
    return exactAt(tape, e, dir, tileSize, sHit + nearStep, evaluations) > f0 + 0.5f * nearStep &&
           exactAt(tape, e, dir, tileSize, sHit + farStep, evaluations) > f0 + 0.5f * farStep;
}

// How a round of exactCrossingLanes spreads its points over [lo, end]: the
// first from lo itself to end; inside a segment whose end is known, strictly
// between the two; over the next span of the window, up to end.
struct RefineSpacing {
    int offset, divisions;
};
RefineSpacing refineSpacing(bool first, bool knownEnd, int lanes)
{
    if (first) return {0, lanes - 1};
    return {1, knownEnd ? lanes + 1 : lanes};
}
float refinePoint(float lo, float end, int j, RefineSpacing spacing)
{
    if (j + spacing.offset == spacing.divisions) return end; // exactly: the window's end is recognised by it
    return lo + (end - lo) * (float(j + spacing.offset) / float(spacing.divisions));
}

// No crossing between x0 (outside, f0 >= eps) and x1: x1 outside too and
// the two values too large for the surface to fit between them, or the two
// closer than `gap` (a near miss that close is left to the voxels: ruling
// it out takes rounds in proportion to how near it passes).
bool refineSegmentCertified(float x0, float f0, float x1, float f1, float eps, float gap)
{
    return !(f1 < eps) && (f0 + f1 >= x1 - x0 || x1 - x0 <= gap);
}

// The hit in the first segment that reaches the surface, from x0 (outside)
// to x1 (within eps of the surface, or inside), once the crossing is known
// to within KERF_EDGE_REFINE_FINISH: where the line through the two values
// crosses zero (the field is all but linear there), kept where the crossing
// can be (no nearer x0 than f0: the field is 1-Lipschitz; not beyond an
// inside x1, nor more than eps beyond an outside one); else x1.
float refineFinish(float x0, float f0, float x1, float f1, float eps)
{
    if (!(f1 < f0)) return x1;
    const float root = x1 - f1 * ((x1 - x0) / (f1 - f0));
    return glm::clamp(root, glm::min(x0 + f0, x1), f1 <= 0.0f ? x1 : x1 + eps);
}

// The ray's first crossing of the exact surface around a populated voxel
// whose segment is [s0, s1]: searched on [s0 - margin, s1 + margin] within
// the tile, and not before `searched` (up to where an earlier search found
// the field positive, moved on when this one finds nothing). `sTrilinear`
// is the trilinear crossing in the voxel (or -1): where the exact field is
// inside there, it brackets the crossing. Returns the crossing's parameter,
// or -1 when the window holds none.
//
// From the window's start the search either walks back (the start is
// inside: the surface was crossed where no voxel is populated, an edge
// sharper than the voxels; a step of |g| never passes the crossing, nor
// goes back before what is known outside) or sphere-traces forward, which
// never passes a crossing (the field is 1-Lipschitz) but closes in on one
// slowly unless the ray meets the surface head-on. So once a crossing is
// bracketed (the trilinear crossing is inside, a step landed inside, or the
// steps ran out and the window's end is inside) a few more steps tighten
// the bracket from the outside and the Illinois variant of regula falsi
// finishes it.
//
// Written as one loop with one evaluation per iteration, whose phase says
// what the value means and where the next one goes: the GPU compiler then
// inlines the tape interpreter once.
constexpr int kStart = 0, kBack = 1, kProbe = 2, kMarch = 3, kEnd = 4, kRefine = 5;
constexpr int kMaxEvaluations = 3 + KERF_EXACT_STEPS + KERF_EXACT_REFINEMENTS;

float exactCrossing(const std::uint32_t* tape, const glm::vec3& e, const glm::vec3& dir, float tileSize, float s0,
                    float s1, float sTileEnd, float voxelEdge, float sTrilinear, float& searched,
                    std::uint32_t& evaluations)
{
    const float margin = float(KERF_EXACT_MARGIN) * voxelEdge;
    const float eps = float(KERF_EXACT_EPSILON) * voxelEdge;
    const float a = glm::max(searched, s0 - margin);
    const float b = glm::min(s1 + margin, sTileEnd);
    if (!(a < b)) return -1.0f;
    int phase = kStart, count = 0;
    float at = a;                 // where the field is evaluated next
    float lo = a, gLo = 0.0f;     // outside: the march's point, or the bracket's outer end
    float hi = -1.0f, gHi = 0.0f; // inside, ahead: the bracket's inner end (hi < 0: none)
    int side = 0;                 // regula falsi: the end moved last (-1 lo, 1 hi)
    for (int k = 0; k < kMaxEvaluations; ++k) {
        const float g = exactAt(tape, e, dir, tileSize, at, evaluations);
        // What the value says.
        if (phase == kStart) {
            if (g <= 0.0f) {
                phase = kBack;
            } else {
                gLo = g;
                phase = sTrilinear > a && sTrilinear < b ? kProbe : kMarch;
                if (phase == kProbe) {
                    at = sTrilinear;
                    continue;
                }
            }
        } else if (phase == kProbe) {
            if (g <= 0.0f) {
                hi = sTrilinear;
                gHi = g;
            }
            phase = kMarch;
        } else if (phase == kMarch) {
            if (g <= 0.0f) {
                hi = at; // landed inside (a sliver of float): bracketed
                gHi = g;
                phase = kRefine;
                count = 0;
            } else {
                lo = at;
                gLo = g;
            }
        } else if (phase == kEnd) {
            if (g <= 0.0f) {
                hi = b;
                gHi = g;
            }
            if (hi < 0.0f) {
                searched = lo;
                return -1.0f;
            }
            phase = kRefine;
            count = 0;
        } else if (phase == kRefine) {
            if (glm::abs(g) < eps) return at;
            // Illinois: an end kept twice in a row has its value halved.
            if (g <= 0.0f) {
                hi = at;
                gHi = g;
                if (side == 1) gLo *= 0.5f;
                side = 1;
            } else {
                lo = at;
                gLo = g;
                if (side == -1) gHi *= 0.5f;
                side = -1;
            }
            ++count;
        }
        // Where the next one goes.
        if (phase == kBack) {
            if (count < KERF_EXACT_STEPS && g < -eps && at > searched) {
                at = glm::max(at + g, searched);
                ++count;
                continue;
            }
            return at;
        }
        if (phase == kMarch) {
            if (gLo < eps) return lo;
            if (lo + gLo >= b) {
                searched = b;
                return -1.0f;
            }
            if (count < (hi < 0.0f ? KERF_EXACT_STEPS : KERF_EXACT_BRACKETED_STEPS)) {
                at = lo + gLo;
                ++count;
                if (hi < 0.0f || at < hi) continue;
                phase = kRefine; // at or past the bracket's inner end: close in on it
                count = 0;
            } else if (hi < 0.0f) {
                phase = kEnd;
                at = b;
                continue;
            } else {
                phase = kRefine;
                count = 0;
            }
        }
        if (count < KERF_EXACT_REFINEMENTS) {
            at = hi - gHi * (hi - lo) / (gHi - gLo);
            if (!(at > lo && at < hi)) at = 0.5f * (lo + hi);
            continue;
        }
        return hi;
    }
    return hi; // not reached: every phase ends within its steps
}

// Exact's refinement of the rays the check sent back (Refinement::Budgeted):
// the same window as exactCrossing, searched KERF_EDGE_REFINE_LANES points
// at a time. On the GPU each point is one lane's evaluation, so that a round
// costs one evaluation's latency: the serial search spent up to 44 in a row
// on one ray, and a frame waits for its slowest ray (docs/benchmarks.md).
//
// Everything before `lo` is known to hold no crossing, and f(lo) >= eps. A
// round places its points evenly over [lo, end]: the first over the whole
// window from its start; later ones inside a segment whose far end's value
// is known (an open segment, a bracket), or over the next `span` of the
// window. Each segment between neighbouring points is then
//  - certified empty when both ends are outside and their values add up to
//    its length or more (the field is 1-Lipschitz: no crossing fits),
//  - reached when its far end is within eps of the surface or inside,
//  - open otherwise (a near miss the points are too far apart to rule out).
// The first segment that is not certified is looked into with points
// closer together. A reached one is narrowed until its crossing is pinned
// to KERF_EDGE_REFINE_FINISH (it lies no nearer the outside end x0 than
// f(x0)), and refineFinish places the hit in it. When every segment is
// certified the search moves past them, the span grown back. After
// KERF_EDGE_REFINE_WINDOW_ROUNDS rounds without reaching the surface the
// window is left (`searched` = lo: the next voxel's window goes on from
// there); having reached it, the hit is the reached end. A window whose
// start is inside walks back as exactCrossing does (kBack). The GPU
// (trace.comp, exactCrossingLanes) makes the same decisions point by point.
float exactCrossingLanes(const std::uint32_t* tape, const glm::vec3& e, const glm::vec3& dir, float tileSize,
                         float s0, float s1, float sTileEnd, float voxelEdge, int lanes, float& searched,
                         RayHit& hit)
{
    const float margin = float(KERF_EXACT_MARGIN) * voxelEdge;
    const float eps = float(KERF_EXACT_EPSILON) * voxelEdge;
    const float gap = float(KERF_EDGE_REFINE_GAP) * voxelEdge;
    const float finish = float(KERF_EDGE_REFINE_FINISH) * voxelEdge;
    const float a = glm::max(searched, s0 - margin);
    const float b = glm::min(s1 + margin, sTileEnd);
    if (!(a < b)) return -1.0f;
    float lo = a, fLo = kInf; // kInf: the window's start is certified against nothing
    float hi = b;             // the window's end, or a bracket's inner end
    float end = b, fEnd = 0.0f;
    bool known = false; // fEnd holds end's value (a round inside an open segment or a bracket)
    bool bracketed = false;
    float span = b - a;
    for (int round = 0; round < KERF_EDGE_REFINE_WINDOW_ROUNDS; ++round) {
        ++hit.rounds;
        if (round > 0 && !known) end = span < hi - lo ? lo + span : hi;
        const RefineSpacing spacing = refineSpacing(round == 0, known, lanes);
        float x[KERF_EDGE_REFINE_MAX_LANES + 1], f[KERF_EDGE_REFINE_MAX_LANES + 1];
        for (int j = 0; j < lanes; ++j) {
            x[j] = refinePoint(lo, end, j, spacing);
            f[j] = exactAt(tape, e, dir, tileSize, x[j], hit.evaluations);
        }
        int points = lanes;
        if (known) {
            x[lanes] = end;
            f[lanes] = fEnd;
            points = lanes + 1;
        }
        int k = 0;
        while (k < points && refineSegmentCertified(k == 0 ? lo : x[k - 1], k == 0 ? fLo : f[k - 1], x[k], f[k], eps, gap))
            ++k;
        if (k == points) {
            if (x[points - 1] == b) { // the whole window certified
                searched = b;
                return -1.0f;
            }
            span = (x[points - 1] - lo) * float(lanes + 1);
            lo = x[points - 1];
            fLo = f[points - 1];
            known = false;
            continue;
        }
        const float fPrev = k == 0 ? fLo : f[k - 1];
        const float xPrev = k == 0 ? lo : x[k - 1];
        if (f[k] < eps) {
            if (round == 0 && k == 0) { // the window's start reached
                if (f[0] > -eps) return x[0];
                // Inside: exactCrossing's walk back.
                float at = x[0], g = f[0];
                for (int count = 0; count < KERF_EXACT_STEPS && g < -eps && at > searched; ++count) {
                    at = glm::max(at + g, searched);
                    ++hit.rounds;
                    g = exactAt(tape, e, dir, tileSize, at, hit.evaluations);
                }
                return at;
            }
            // The first crossing lies in (xPrev, x[k]], no earlier than xPrev + fPrev.
            if (!(x[k] - (xPrev + fPrev) > finish)) return refineFinish(xPrev, fPrev, x[k], f[k], eps);
            bracketed = true;
            hi = x[k];
        }
        lo = xPrev;
        fLo = fPrev;
        end = x[k];
        fEnd = f[k];
        known = true;
    }
    if (bracketed) return hi;
    searched = glm::max(searched, lo);
    return -1.0f;
}

// A section's cap, pending while the ray, started on the section plane, has
// met no populated voxel and crossed no empty tile yet: until then no
// surface was crossed, so a full tile, or the first voxel's value at the
// ray's entry, says whether the plane point was inside the solid (a cap) or
// not, and an empty tile that it was not.
struct CapState {
    bool pending = false;
    float depth = 0.0f;
    glm::vec3 normal{0.0f};
    // Whether the plane's point was inside, from the field where the ray
    // enters its first populated voxel (`value`, mm). Where the ray starts in
    // that voxel, at or below zero: a plane lying on a face of the part caps
    // it (below by more than the rounding alone, CPU and GPU decided such
    // points differently). Where it first crossed unpopulated cells
    // (`travelled`), those were proven wholly inside or outside, corners
    // included, so inside, the face they share with the voxel is below zero
    // all over; a value within a thousandth of a voxel of zero there is a face
    // of the part on a lattice plane met from outside (a dado's wall seen in
    // perspective was hatched as cut). A thousandth, not the cubic's rounding:
    // after 50 voxels of travel the entry lies 1e-5 of a voxel off the face,
    // on either side as the CPU or the GPU rounds.
    static bool insideAtEntry(float value, float voxelMm, bool travelled)
    {
        return travelled ? value < -1e-3f * voxelMm : value <= 0.0f;
    }
    void hitAt(RayHit& hit)
    {
        hit.depth = depth;
        hit.normal = normal;
        hit.feature = kSectionCap;
        pending = false;
    }
};

// Traces inside one surface tile, from ray parameter tEnter (where the ray is
// in the tile) until it leaves the tile. Returns true with `hit` filled when
// it finds the surface (or a section's cap).
// Where a hit of the hybrid refinement lies: its tile's tape and the point,
// tile-relative (mm). Its normal and feature are the exact field's there,
// evaluated once the ray is done (outside the loops: on the GPU their state
// would otherwise stay live across the gradient's evaluation).
struct ExactPoint {
    const std::uint32_t* tape = nullptr;
    glm::vec3 point{0.0f};
};

// Which populated voxels the hybrid refinement searches on the exact field.
enum class Refinement {
    None,       // none: the voxels alone (TraceQuality::Voxels, and Exact's first look)
    EveryVoxel, // every one the ray meets (TraceQuality::ExactEverywhere)
    // Exact's rays that the check sent back: every one the ray meets (on the
    // stretch traceGrid is given), KERF_EDGE_REFINE_LANES points a round
    // (exactCrossingLanes), until the ray has spent KERF_EDGE_REFINE_ROUNDS.
    Budgeted,
};

// `tape`: the tile's exact tape when the hybrid refinement is on, else null.
bool traceTile(const FlatVoxelBuffers& b, const TileEntry& entry, const std::uint32_t* tape, const glm::ivec3& tile,
               const glm::vec3& origin, const glm::vec3& dir, const glm::vec3& invDir, float tileSize, float tEnter,
               Refinement refinement, int lanes, RayHit& hit, CapState& cap, ExactPoint& exact)
{
    const int levels = int(entry.levels);
    const int n = 1 << (2 * levels); // finest cells per tile edge
    const float fn = float(n);
    const float invN = 1.0f / fn;
    const float invTile = 1.0f / tileSize;

    // Entry point in tile units, [0, 1]^3 across the tile; the ray is
    // e + s * dir there, with s in tile edges.
    const glm::vec3 e = glm::clamp((origin - glm::vec3(tile) * tileSize + tEnter * dir) * invTile, 0.0f, 1.0f);
    glm::ivec3 cell = glm::clamp(glm::ivec3(glm::floor(e * fn)), glm::ivec3(0), glm::ivec3(n - 1));
    float s = 0.0f;
    // Hybrid refinement: where the ray leaves the tile, and up to where the
    // exact field is known to be outside.
    const glm::vec3 sFaces = (glm::vec3(glm::greaterThan(dir, glm::vec3(0.0f))) - e) * invDir;
    const float sTileEnd = glm::min(sFaces.x, glm::min(sFaces.y, sFaces.z));
    float searched = 0.0f;
    // The clearance of the voxel passed last, held back while the next cell
    // may be the hit (RayHit::passedClearance).
    float pending = kInf;
    bool pendingAdjacent = false;

    // Each iteration moves at least one cell coordinate one step along the
    // ray, so 3n iterations cross the whole tile.
    const int maxIterations = 3 * n + 3;
    for (int iteration = 0; iteration < maxIterations; ++iteration) {
        // Descend to the deepest existing node containing `cell`.
        std::uint32_t node = entry.node;
        int cellShift = 0;  // log2 of the cell's edge in finest cells
        bool voxel = false; // a populated voxel (else an empty cell)
        std::uint32_t leafIndirection = 0, voxelRank = 0;
        for (int depth = 0; depth < levels; ++depth) {
            const int shift = 2 * (levels - 1 - depth);
            const int c = voxel::childIndex((cell.x >> shift) & 3, (cell.y >> shift) & 3, (cell.z >> shift) & 3);
            const voxel::Node nd = b.nodes[node];
            cellShift = shift;
            ++hit.steps;
            if (!hasChild(nd, c)) break;
            if (nd.isLeaf()) {
                voxel = true;
                leafIndirection = entry.leafIndirection + nd.pointer();
                voxelRank = childRank(nd, c);
                break;
            }
            node = entry.node + nd.pointer() + childRank(nd, c);
        }

        // The cell's extent in finest cells, and where the ray leaves it.
        const glm::ivec3 lo = (cell >> cellShift) << cellShift;
        const glm::ivec3 hi = lo + (1 << cellShift);
        const glm::vec3 bound(dir.x > 0.0f ? float(hi.x) : float(lo.x), dir.y > 0.0f ? float(hi.y) : float(lo.y),
                              dir.z > 0.0f ? float(hi.z) : float(lo.z));
        const glm::vec3 sAxis = (bound * invN - e) * invDir;
        const float sExit = glm::min(sAxis.x, glm::min(sAxis.y, sAxis.z));

        if (voxel) {
            // The voxel is the cell [lo, hi): one finest cell when the leaf
            // sits at the tile's last level, as the voxelizer builds them.
            const float voxelScale = fn / float(1 << cellShift); // voxel edges per tile edge
            const float voxelMm = tileSize / voxelScale;
            const glm::vec3 voxelLo = glm::vec3(lo) * invN; // tile units
            const voxel::LeafIndirection li = b.leafIndirections[leafIndirection];
            const voxel::LeafData ld = b.leafData[entry.leafData + li.leafData + voxelRank];
            float d[8];
            for (int q = 0; q < 8; ++q)
                d[q] =
                    voxel::decodeDistance(b.vertices[entry.vertex + li.vertex + ld.corner[q]].distanceFeature, voxelMm);
            const Trilinear tri = trilinear(d);
            // Voxel-local coordinates ([0, 1]^3 across the voxel), w in voxel edges from the entry.
            const glm::vec3 o = glm::clamp((e + s * dir - voxelLo) * voxelScale, 0.0f, 1.0f);
            const float wEnd = glm::max(0.0f, (sExit - s) * voxelScale);
            const Cubic along = alongRay(tri, o, dir);
            if (cap.pending) {
                if (cap.insideAtEntry(evalCubic(along, 0.0f), voxelMm,
                                      tEnter + s * tileSize - cap.depth > 1e-3f * voxelMm)) {
                    cap.hitAt(hit);
                    return true;
                }
                cap.pending = false;
            }
            float least = 0.0f;
            const float w = firstCrossing(along, wEnd, least);
            // Crossed without a hit: how close the ray came to this voxel's
            // surface, in units of what the hit check allows there
            // (VoxelHitCheck.hpp; the corner normals only asked where they
            // decide). At 1 or more the voxel hides no exact surface from the ray.
            float clearance = kInf, allowed = float(KERF_EDGE_CHECK_CLEARANCE);
            if (w < 0.0f && least / voxelMm < float(KERF_EDGE_CHECK_CLEARANCE)) {
                allowed = cornerClearance(b, entry.vertex + li.vertex, ld);
                clearance = least / voxelMm / allowed;
            }
            const bool near = w >= 0.0f || clearance < 1.0f;
            if (near) {
                // The stretch of the ray Exact's refinement searches: this
                // voxel's window (RayHit::nearFrom).
                const float margin = float(KERF_EXACT_MARGIN) / voxelScale;
                hit.nearFrom = glm::min(hit.nearFrom, tEnter + (s - margin) * tileSize);
                hit.nearTo = glm::max(hit.nearTo, tEnter + (sExit + margin) * tileSize);
            }
            // Exact's refinement searches the stretch of the ray between
            // the first and the last of them (traceGrid's from, to), and
            // stops searching once it has spent its budget (the few rays
            // that skim along edges for many voxels keep their voxels'
            // answer there: on the GPU one such ray sets the frame time).
            if (tape && (refinement == Refinement::EveryVoxel || hit.rounds < KERF_EDGE_REFINE_ROUNDS)) {
                // Near the surface: the exact field decides, the trilinear
                // crossing only brackets it; where the exact field has no
                // crossing nearby, the voxels' stands (never a hole where
                // the voxels show surface).
                const float voxelEdge = 1.0f / voxelScale;
                const float sHit =
                    refinement == Refinement::Budgeted
                        ? exactCrossingLanes(tape, e, dir, tileSize, s, sExit, sTileEnd, voxelEdge, lanes, searched, hit)
                        : exactCrossing(tape, e, dir, tileSize, s, sExit, sTileEnd, voxelEdge,
                                        w >= 0.0f ? s + w / voxelScale : -1.0f, searched, hit.evaluations);
                if (sHit >= 0.0f && onlyTouches(tape, e, dir, tileSize, sHit, voxelEdge, hit.evaluations)) {
                    // A sheet of no thickness, not a surface: search on past it.
                    searched = glm::max(searched, sHit + float(KERF_EXACT_TOUCH_FAR) * voxelEdge);
                } else if (sHit >= 0.0f) {
                    // The normal is taken a hair in front of the hit: exactly
                    // on the surface some fields have no derivative (a
                    // cone's cap is a sqrt(0) there).
                    exact.tape = tape;
                    exact.point = (e + glm::max(sHit - float(KERF_EXACT_EPSILON) * voxelEdge, 0.0f) * dir) * tileSize;
                    hit.normal = -dir;
                    hit.feature = kNoFeature;
                    hit.depth = tEnter + sHit * tileSize;
                    return true;
                }
            }
            if (w >= 0.0f) {
                // The voxel passed just before, on a smooth sheet whose field
                // still fell as the ray left it: the ray closes in on this
                // surface, and the check's Newton steps from this hit look
                // there (they may step back into it).
                if (!pendingAdjacent) hit.passedClearance = glm::min(hit.passedClearance, pending);
                const glm::vec3 u = glm::clamp(o + w * dir, 0.0f, 1.0f);
                glm::vec3 nrm(0.0f);
                float nearest = kInf;
                std::uint32_t feature = kNoFeature;
                for (int q = 0; q < 8; ++q) {
                    const voxel::Vertex vx = b.vertices[entry.vertex + li.vertex + ld.corner[q]];
                    const glm::vec3 corner(float(q & 1), float((q >> 1) & 1), float(q >> 2));
                    const glm::vec3 weight3 = glm::mix(glm::vec3(1.0f) - u, u, corner);
                    nrm += (weight3.x * weight3.y * weight3.z) * voxel::decodeNormal(vx.normal);
                    const glm::vec3 toCorner = u - corner;
                    const float dist2 = glm::dot(toCorner, toCorner);
                    if (dist2 < nearest) {
                        nearest = dist2;
                        feature = voxel::decodeFeature(vx.distanceFeature);
                    }
                }
                float len = glm::length(nrm);
                if (!(len > 1e-6f)) {
                    // Corner normals that cancel out (a thin wall, a crease):
                    // the interpolated field's own gradient.
                    nrm = trilinearGradient(tri, u);
                    len = glm::length(nrm);
                }
                hit.normal = len > 0.0f ? nrm / len : -dir;
                hit.feature = feature;
                hit.depth = tEnter + (s + w / voxelScale) * tileSize;
                return true;
            }
            // Its clearance counts, unless the voxels from here on to the
            // hit all close in on a smooth sheet (above): a ray meeting a
            // face at a low angle passes near it for several voxels.
            if (clearance < 1.0f && allowed < float(KERF_EDGE_CHECK_CLEARANCE) && least >= evalCubic(along, wEnd)) {
                pending = pendingAdjacent ? glm::min(pending, clearance) : clearance;
                pendingAdjacent = true;
            } else {
                hit.passedClearance = glm::min(hit.passedClearance, glm::min(pending, clearance));
                pending = kInf;
                pendingAdjacent = false;
            }
        } else {
            hit.passedClearance = glm::min(hit.passedClearance, pending); // an empty cell in between
            pending = kInf;
            pendingAdjacent = false;
        }

        // Step into the face neighbour across the face the ray leaves by.
        s = glm::max(s, sExit);
        const glm::vec3 p = (e + s * dir) * fn;
        glm::ivec3 next = glm::clamp(glm::ivec3(glm::floor(p)), lo, hi - 1);
        if (sAxis.x <= sExit) next.x = dir.x > 0.0f ? hi.x : lo.x - 1;
        if (sAxis.y <= sExit) next.y = dir.y > 0.0f ? hi.y : lo.y - 1;
        if (sAxis.z <= sExit) next.z = dir.z > 0.0f ? hi.z : lo.z - 1;
        cell = next;
        if (cell.x < 0 || cell.y < 0 || cell.z < 0 || cell.x >= n || cell.y >= n || cell.z >= n) break;
    }
    hit.passedClearance = glm::min(hit.passedClearance, pending); // the tile ends
    return false;
}

// `from`, `to`: the stretch of the ray to trace (Exact's refined rays: the
// voxel trace's RayHit::nearFrom and nearTo), where no section plane is set.
RayHit traceGrid(const FlatVoxelBuffers& b, const glm::vec3& origin, const glm::vec3& direction, const glm::vec4& plane,
                 Refinement refinement, int lanes, ExactPoint& exact, float from = 0.0f, float to = kInf)
{
    RayHit hit;
    const GridLayout& layout = b.layout;
    if (layout.empty() || b.tiles.size() != std::size_t(layout.tileCount())) return hit;

    const glm::vec3 dir(nonZero(direction.x), nonZero(direction.y), nonZero(direction.z));
    const glm::vec3 invDir = 1.0f / dir;
    const float tileSize = float(layout.tileSize);
    const glm::ivec3 dims = layout.dims;

    // 1. Slab test against the grid's box.
    const glm::vec3 t0 = (glm::vec3(0.0f) - origin) * invDir;
    const glm::vec3 t1 = (glm::vec3(dims) * tileSize - origin) * invDir;
    const glm::vec3 tNear = glm::min(t0, t1), tFar = glm::max(t0, t1);
    float tEnter = glm::max(glm::max(tNear.x, tNear.y), glm::max(tNear.z, 0.0f));
    float tLeave = glm::min(tFar.x, glm::min(tFar.y, tFar.z));
    // The axis whose face the ray enters by (for a full tile's normal).
    int enterAxis = tNear.x >= tNear.y && tNear.x >= tNear.z ? 0 : (tNear.y >= tNear.z ? 1 : 2);

    // A section plane (a unit normal, w = offset; zero normal: none) keeps
    // dot(n, p) <= offset. A ray heading into the cut-away side ends at the
    // plane; one coming out of it starts there, where a cap may be.
    CapState cap;
    const glm::vec3 n(plane);
    if (n != glm::vec3(0.0f)) {
        const float denom = glm::dot(n, dir);
        const float above = glm::dot(n, origin) - plane.w; // > 0: the origin is cut away
        if (std::fabs(denom) < 1e-12f) {
            if (above > 0.0f) return hit;
        } else {
            const float tPlane = -above / denom;
            if (denom > 0.0f) {
                tLeave = glm::min(tLeave, tPlane);
            } else if (tPlane > tEnter) {
                tEnter = tPlane;
                cap.pending = true;
                cap.depth = tPlane;
                cap.normal = n;
            }
        }
    }
    if (n == glm::vec3(0.0f)) {
        tEnter = glm::max(tEnter, from);
        tLeave = glm::min(tLeave, to);
    }
    if (!(tEnter <= tLeave)) return hit;

    // 2. DDA over the tiles (Amanatides & Woo).
    const glm::vec3 p = (origin + tEnter * dir) / tileSize;
    glm::ivec3 tile = glm::clamp(glm::ivec3(glm::floor(p)), glm::ivec3(0), dims - 1);
    const glm::ivec3 step(dir.x > 0.0f ? 1 : -1, dir.y > 0.0f ? 1 : -1, dir.z > 0.0f ? 1 : -1);
    const glm::vec3 tDelta = glm::abs(invDir) * tileSize;
    glm::vec3 tNext =
        ((glm::vec3(tile) + glm::vec3(glm::greaterThan(dir, glm::vec3(0.0f)))) * tileSize - origin) * invDir;
    const int maxTileSteps = dims.x + dims.y + dims.z + 3;
    for (int i = 0; i < maxTileSteps; ++i) {
        const int axis = tNext.x <= tNext.y && tNext.x <= tNext.z ? 0 : (tNext.y <= tNext.z ? 1 : 2);
        const float tExitTile = tNext[axis];
        const std::uint32_t value = b.tiles[std::size_t(tile.x + dims.x * (tile.y + dims.y * tile.z))];
        ++hit.steps;
        if (value == voxel::kFullTile && cap.pending) {
            cap.hitAt(hit);
            return hit;
        }
        // Outside, with no surface crossed since the plane: so was the
        // plane's point, and nothing further on is its cap (a leg far behind
        // the plane was drawn hatched at the plane's depth). Only a tile the
        // ray crosses for a length: on a plane that lies on tile faces the
        // first tile may be the one behind it, by rounding.
        if (value == voxel::kEmptyTile && tExitTile - tEnter > 1e-3f * tileSize) cap.pending = false;
        if (value == voxel::kFullTile) {
            hit.depth = tEnter;
            hit.normal = glm::vec3(0.0f);
            hit.normal[enterAxis] = -float(step[enterAxis]);
            hit.feature = kNoFeature;
            return hit;
        }
        if (value != voxel::kEmptyTile &&
            traceTile(b, b.entries[value],
                      refinement != Refinement::None && b.entries[value].tape != voxel::kNoTape
                          ? b.tapes.data() + b.entries[value].tape
                          : nullptr,
                      tile, origin, dir, invDir, tileSize, tEnter, refinement, lanes, hit, cap, exact)) {
            // A hit past the section plane is in the part cut away.
            if (hit.depth > tLeave) {
                hit = RayHit{};
                exact.tape = nullptr;
            }
            return hit;
        }
        if (tExitTile >= tLeave) break;
        tEnter = glm::max(tEnter, tExitTile);
        tile[axis] += step[axis];
        tNext[axis] += tDelta[axis];
        enterAxis = axis;
        if (tile[axis] < 0 || tile[axis] >= dims[axis]) break;
    }
    return hit;
}

// traceGrid, then the exact normal and feature of a refined hit.
RayHit traceRefined(const FlatVoxelBuffers& b, const glm::vec3& origin, const glm::vec3& direction,
                    const glm::vec4& plane, Refinement refinement, int lanes = KERF_EDGE_REFINE_LANES,
                    float from = 0.0f, float to = kInf)
{
    ExactPoint exact;
    RayHit hit = traceGrid(b, origin, direction, plane, refinement, lanes, exact, from, to);
    hit.exactHit = exact.tape != nullptr;
    if (exact.tape) {
        // The exact field's gradient at the refined hit, by forward differentiation.
        std::uint32_t feature = kNoFeature;
        const glm::vec4 fg = voxel::evaluateTileTapeGradient(exact.tape, exact.point, feature);
        ++hit.evaluations;
        const glm::vec3 g(fg.y, fg.z, fg.w);
        const float len = glm::length(g);
        hit.normal = len > 0.0f ? g / len : hit.normal;
        hit.feature = feature;
    }
    return hit;
}

} // namespace

RayHit traceRay(const FlatVoxelBuffers& b, const glm::vec3& origin, const glm::vec3& direction, const glm::vec4& plane,
                TraceQuality quality, int refineLanes)
{
    refineLanes = glm::clamp(refineLanes, 2, KERF_EDGE_REFINE_MAX_LANES);
    // Without tapes (none built) the refinement has nothing to refine with: the voxels, as on the GPU.
    if (quality == TraceQuality::Voxels || b.tapes.empty())
        return traceRefined(b, origin, direction, plane, Refinement::None);
    if (quality == TraceQuality::ExactEverywhere) {
        RayHit hit = traceRefined(b, origin, direction, plane, Refinement::EveryVoxel);
        hit.evaluationsInARow = hit.evaluations;
        return hit;
    }
    // Exact: the voxels first; the refinement only where the exact field does not confirm their hit.
    const RayHit voxels = traceRefined(b, origin, direction, plane, Refinement::None);
    RayHit checked;
    const glm::vec3 dir(nonZero(direction.x), nonZero(direction.y), nonZero(direction.z));
    if (checkVoxelHit(b, origin, dir, plane, voxels, checked) != VoxelHitVerdict::Refine) {
        checked.evaluationsInARow = checked.evaluations;
        return checked;
    }
    // Only the stretch where the voxels met the surface or came near it:
    // nothing before or after it would be searched.
    RayHit hit =
        traceRefined(b, origin, direction, plane, Refinement::Budgeted, refineLanes, voxels.nearFrom, voxels.nearTo);
    // A round's evaluations run side by side (one lane each); then the gradient at the hit.
    std::uint32_t inARow = hit.rounds + (hit.exactHit ? 1u : 0u);
    if (hit.hit() && !hit.exactHit && hit.rounds >= KERF_EDGE_REFINE_ROUNDS) {
        // The budget ran out before the hit: it is a voxel hit, which the
        // check's two Newton steps put on the exact surface where they can.
        RayHit voxelHit = hit, onSurface;
        voxelHit.passedClearance = kInf;
        if (checkVoxelHit(b, origin, dir, plane, voxelHit, onSurface) == VoxelHitVerdict::Confirm) {
            inARow += onSurface.evaluations - voxelHit.evaluations;
            hit = onSurface;
        }
    }
    hit.evaluationsInARow = inARow + checked.evaluations;
    hit.evaluations += checked.evaluations;
    hit.steps += checked.steps;
    hit.refined = true;
    return hit;
}

glm::vec4 localPlane(const GridLayout& layout, const Section& section)
{
    if (!section.enabled) return glm::vec4(0.0f);
    // The offset relative to the grid origin, in double: float sees small numbers.
    return glm::vec4(glm::vec3(section.normal), float(section.offset - glm::dot(section.normal, layout.origin)));
}

RayHit traceRay(const FlatVoxelBuffers& buffers, const Ray& ray, const Section& section, TraceQuality quality,
                int refineLanes)
{
    return traceRay(buffers, glm::vec3(ray.origin - buffers.layout.origin), glm::vec3(ray.direction),
                    localPlane(buffers.layout, section), quality, refineLanes);
}

TraceImage traceVoxels(const FlatVoxelBuffers& buffers, const Camera& camera, int threads, const Section& section,
                       TraceQuality quality, const Progress& work, int refineLanes)
{
    TraceImage image(camera.width(), camera.height());
    tbb::task_arena arena = workerArena(threads);
    std::atomic<int> rowsDone{0};
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, image.height), [&](const tbb::blocked_range<int>& rows) {
            for (int y = rows.begin(); y != rows.end(); ++y) {
                if (work.cancelled()) return;
                for (int x = 0; x < image.width; ++x) {
                    const RayHit h = traceRay(buffers, camera.ray(x, y), section, quality, refineLanes);
                    const std::size_t i = image.index(x, y);
                    image.depth[i] = h.depth;
                    image.normal[i] = h.normal;
                    image.feature[i] = h.feature;
                }
                if (work.reporting()) work.report(double(++rowsDone) / double(image.height));
            }
        });
    });
    image.complete = !work.cancelled();
    return image;
}

} // namespace kerf

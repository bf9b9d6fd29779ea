#version 460
// The voxel tracer: one ray per pixel through the tile grid and its
// contrees, writing depth, normal and feature. A line-by-line port of
// tracer/src/ReferenceTracer.cpp (the CPU reference): keep the two in step.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_EXT_control_flow_attributes : require

#include "TraceShared.h"
#include "kerf/tracer/ExactRefinement.h"
#include "kerf/tracer/SectionCap.h"
#include "kerf/voxelizer/TileTapeFormat.h"
#include "voxel_format.glsl"

layout(local_size_x = KERF_TRACE_LOCAL_SIZE, local_size_y = KERF_TRACE_LOCAL_SIZE) in;

// Pipelines of this shader (ComputeTracer.cpp): without the hybrid
// refinement its code is compiled out, so that the voxel path keeps its
// registers and occupancy; with it, TraceParams.options.x still decides.
layout(constant_id = 0) const bool kHybrid = false;
// What a dispatch does. kTraceAll: trace every pixel (TraceQuality Voxels,
// or ExactEverywhere with kHybrid). TraceQuality::Exact takes four
// dispatches: kTraceVoxels traces every pixel on its voxels, records
// the ray's clearance (RayHit::passedClearance), lists for the refinement
// the rays that passed too close to a voxel's surface and for the check the
// other voxel hits; kCheckHits checks each listed voxel hit on the exact
// field (tracer/src/VoxelHitCheck.cpp) and lists for the refinement those
// it cannot confirm; kTraceListed (with kHybrid) traces those, and
// kFinishListed, one lane a listed pixel, takes the exact normal at each
// refined hit, or the check's Newton steps where the refinement's budget ran
// out before a voxel hit. Those evaluations of the gradient are a pass of
// their own so that the listed pass, whose rounds are the exact frame's
// slowest part, does not hold the dual numbers' registers.
const int kTraceAll = 0, kTraceVoxels = 1, kCheckHits = 2, kTraceListed = 3, kFinishListed = 4;
layout(constant_id = 1) const int kPass = kTraceAll;
// kTraceListed: the lanes that trace one listed ray together (a power of
// two up to KERF_EDGE_REFINE_MAX_LANES that divides the subgroup).
layout(constant_id = 2) const int kRefineLanes = KERF_EDGE_REFINE_LANES;

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Words { uint w[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer Floats { float f[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer Vec4s { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer Uints { uint u[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ParamsRef { TraceParams p; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer ReadFloats { float f[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ReadVec4s { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer RefineList { uint pixel[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer RefineArgs {
    uint groups, y, z; // the refinement's indirect dispatch
    uint count;        // pixels listed
    uint front, back;  // of which listed from the list's front (long stretches) and its back
    uint finishGroups, finishY, finishZ; // kFinishListed's indirect dispatch: one lane a listed pixel
    uint checkGroups, checkY, checkZ;    // kCheckHits' indirect dispatch: one lane a voxel hit to check
    uint checkCount;                     // voxel hits listed for the check
};
layout(buffer_reference, std430, buffer_reference_align = 4) buffer CheckList { uint pixel[]; };

layout(push_constant) uniform Push { uint64_t params; } pc;

const uint kNoFeature = 0xFFFFFFFFu;
const uint kSectionCap = KERF_SECTION_CAP_FEATURE;
const float kInf = 1.0 / 0.0;
const int kBisectionSteps = 16;

TraceParams P;

struct Hit {
    float depth;
    vec3 normal;
    uint feature;
    uint tape;  // a hit of the hybrid refinement: its tile's tape (else KERF_NO_TAPE) ...
    vec3 point; // ... and the point, tile-relative (mm), where main() takes the exact normal
    float clearance; // RayHit::passedClearance (kTraceVoxels only) ...
    float nearFrom, nearTo; // ... and RayHit::nearFrom, nearTo
};

// Rounds of the listed pass's refinement so far (KERF_EDGE_REFINE_ROUNDS).
uint refineRounds = 0u;
// The listed pass: this invocation's lane among the kRefineLanes
// that trace one listed ray together, and the subgroup invocation of its
// first lane.
uint refineLane = 0u, refineLaneBase = 0u;

// A section's cap, pending while the ray, started on the section plane, has
// met no populated voxel (ReferenceTracer.cpp, CapState).
bool capPending = false;
float capDepth = 0.0;
vec3 capNormal = vec3(0.0);

// Whether the plane's point was inside, from the field where the ray enters
// its first populated voxel (ReferenceTracer.cpp, CapState::insideAtEntry).
bool capInsideAtEntry(float value, float voxelMm, bool travelled)
{
    return travelled ? value < -1e-3 * voxelMm : value <= 0.0;
}

void hitCap(inout Hit hit)
{
    hit.depth = capDepth;
    hit.normal = capNormal;
    hit.feature = kSectionCap;
    capPending = false;
}

uint word(uint64_t base, uint index) { return Words(base).w[index]; }

// Trilinear field in the monomial basis and along a ray as a cubic.
void trilinear(const float d[8], out float k[8])
{
    k[0] = d[0];
    k[1] = d[1] - d[0];
    k[2] = d[2] - d[0];
    k[3] = d[4] - d[0];
    k[4] = d[3] - d[2] - d[1] + d[0];
    k[5] = d[6] - d[4] - d[2] + d[0];
    k[6] = d[5] - d[4] - d[1] + d[0];
    k[7] = d[7] - d[6] - d[5] - d[3] + d[4] + d[2] + d[1] - d[0];
}

vec3 trilinearGradient(const float k[8], vec3 u)
{
    return vec3(k[1] + k[4] * u.y + k[6] * u.z + k[7] * u.y * u.z,
                k[2] + k[4] * u.x + k[5] * u.z + k[7] * u.x * u.z,
                k[3] + k[5] * u.y + k[6] * u.x + k[7] * u.x * u.y);
}

vec4 alongRay(const float k[8], vec3 o, vec3 d)
{
    vec4 c;
    c.x = k[0] + k[1] * o.x + k[2] * o.y + k[3] * o.z + k[4] * o.x * o.y + k[5] * o.y * o.z + k[6] * o.x * o.z +
          k[7] * o.x * o.y * o.z;
    c.y = k[1] * d.x + k[2] * d.y + k[3] * d.z + k[4] * (o.x * d.y + o.y * d.x) + k[5] * (o.y * d.z + o.z * d.y) +
          k[6] * (o.x * d.z + o.z * d.x) + k[7] * (d.x * o.y * o.z + o.x * d.y * o.z + o.x * o.y * d.z);
    c.z = k[4] * d.x * d.y + k[5] * d.y * d.z + k[6] * d.x * d.z +
          k[7] * (d.x * d.y * o.z + d.x * o.y * d.z + o.x * d.y * d.z);
    c.w = k[7] * d.x * d.y * d.z;
    return c;
}

float evalCubic(vec4 c, float w) { return c.x + w * (c.y + w * (c.z + w * c.w)); }

// What counts as zero in a voxel's cubic along a ray (ReferenceTracer.cpp, kCubicZero).
float cubicZero(const vec4 c) { return 1e-5 * (abs(c.x) + abs(c.y) + abs(c.z) + abs(c.w)); }

float firstCrossing(vec4 c, float wEnd, out float least)
{
    float r1 = kInf, r2 = kInf;
    const float qa = 3.0 * c.w, qb = 2.0 * c.z, qc = c.y;
    if (qa != 0.0) {
        const float disc = qb * qb - 4.0 * qa * qc;
        if (disc >= 0.0) {
            const float q = -0.5 * (qb + (qb < 0.0 ? -sqrt(disc) : sqrt(disc)));
            r1 = q / qa;
            r2 = q != 0.0 ? qc / q : r1;
        }
    } else if (qb != 0.0) {
        r1 = -qc / qb;
    }
    if (r2 < r1) {
        const float tmp = r1;
        r1 = r2;
        r2 = tmp;
    }
    // The points 0, the extrema inside (0, wEnd) and wEnd, in order, as
    // ReferenceTracer.cpp's `breaks`; an extremum outside the span repeats
    // the point before it, a piece of no length that cannot hold the first
    // crossing, so the decisions are the reference's. Four names, not an
    // array indexed by a count: NVIDIA's compiler kept such an array in
    // local memory (kerf_gpu_bench --pipeline-statistics).
    const float b1 = r1 > 0.0 && r1 < wEnd ? r1 : 0.0;
    const float b2 = r2 > 0.0 && r2 < wEnd && r2 != r1 ? r2 : b1;

    // Inside is below zero, as the voxelizer counts a corner, and a value
    // within the cubic's rounding of zero is zero (ReferenceTracer.cpp says why).
    const float zero = cubicZero(c);
    const float f0 = evalCubic(c, 0.0), f1 = evalCubic(c, b1), f2 = evalCubic(c, b2), f3 = evalCubic(c, wEnd);
    float lo, hi;
    if (f0 < -zero) {
        least = f0;
        return 0.0;
    } else if (f1 < -zero) {
        least = min(f0, f1);
        lo = 0.0;
        hi = b1;
    } else if (f2 < -zero) {
        least = min(min(f0, f1), f2);
        lo = b1;
        hi = b2;
    } else if (f3 < -zero) {
        least = min(min(f0, f1), min(f2, f3));
        lo = b2;
        hi = wEnd;
    } else {
        least = min(min(f0, f1), min(f2, f3));
        return -1.0;
    }
    // Monotone on [lo, hi] with f(lo) >= -zero > f(hi): bisect.
    for (int k = 0; k < kBisectionSteps; ++k) {
        const float mid = 0.5 * (lo + hi);
        if (evalCubic(c, mid) < -zero) hi = mid;
        else lo = mid;
    }
    return hi;
}

float nonZero(float v) { return abs(v) < 1e-20 ? (v < 0.0 ? -1e-20 : 1e-20) : v; }
vec3 nonZero(vec3 v) { return vec3(nonZero(v.x), nonZero(v.y), nonZero(v.z)); }

// ---- A tile's exact tape: the GLSL tape library (tape.glsl) ----
// t is the tape's first word in P.tapes; indices are relative to it.

uint tapeWord(uint t, uint i) { return word(P.tapes, t + i); }

#include "tape.glsl"

// ---- The hybrid refinement (ReferenceTracer.cpp, exactCrossing) ----

float exactAt(uint tape, vec3 e, vec3 dir, float tileSize, float s)
{
    return evaluateTileTape(tape, (e + s * dir) * tileSize) / tileSize;
}

// ReferenceTracer.cpp, onlyTouches: the ray met a sheet of no thickness.
// In the listed pass the ray's first three lanes evaluate the three points
// in one round (every lane of the ray is here, with the same sHit).
bool onlyTouches(uint tape, vec3 e, vec3 dir, float tileSize, float sHit, float voxelEdge)
{
    const float nearStep = float(2.0 * KERF_EXACT_EPSILON + KERF_EXACT_TOUCH_NEAR) * voxelEdge;
    const float farStep = float(KERF_EXACT_TOUCH_FAR) * voxelEdge;
    float f0, fNear, fFar;
    if (kPass == kTraceListed) {
        const uint j = refineLane;
        const float f = exactAt(tape, e, dir, tileSize, sHit + (j == 1u ? nearStep : j == 2u ? farStep : 0.0));
        f0 = subgroupShuffle(f, refineLaneBase);
        fNear = subgroupShuffle(f, refineLaneBase + 1u);
        fFar = subgroupShuffle(f, refineLaneBase + 2u);
    } else {
        f0 = exactAt(tape, e, dir, tileSize, sHit);
        fNear = exactAt(tape, e, dir, tileSize, sHit + nearStep);
        fFar = exactAt(tape, e, dir, tileSize, sHit + farStep);
    }
    return fNear > f0 + 0.5 * nearStep && fFar > f0 + 0.5 * farStep;
}

const int kStart = 0, kBack = 1, kProbe = 2, kMarch = 3, kEnd = 4, kRefine = 5;
const int kMaxEvaluations = 3 + KERF_EXACT_STEPS + KERF_EXACT_REFINEMENTS;

float exactCrossing(uint tape, vec3 e, vec3 dir, float tileSize, float s0, float s1, float sTileEnd, float voxelEdge,
                    float sTrilinear, inout float searched)
{
    const float margin = float(KERF_EXACT_MARGIN) * voxelEdge;
    const float eps = float(KERF_EXACT_EPSILON) * voxelEdge;
    const float a = max(searched, s0 - margin);
    const float b = min(s1 + margin, sTileEnd);
    if (!(a < b)) return -1.0;
    int phase = kStart, count = 0;
    float at = a;
    float lo = a, gLo = 0.0;
    float hi = -1.0, gHi = 0.0;
    int side = 0;
    for (int k = 0; k < kMaxEvaluations; ++k) {
        const float g = exactAt(tape, e, dir, tileSize, at);
        if (phase == kStart) {
            if (g <= 0.0) {
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
            if (g <= 0.0) {
                hi = sTrilinear;
                gHi = g;
            }
            phase = kMarch;
        } else if (phase == kMarch) {
            if (g <= 0.0) {
                hi = at;
                gHi = g;
                phase = kRefine;
                count = 0;
            } else {
                lo = at;
                gLo = g;
            }
        } else if (phase == kEnd) {
            if (g <= 0.0) {
                hi = b;
                gHi = g;
            }
            if (hi < 0.0) {
                searched = lo;
                return -1.0;
            }
            phase = kRefine;
            count = 0;
        } else if (phase == kRefine) {
            if (abs(g) < eps) return at;
            if (g <= 0.0) {
                hi = at;
                gHi = g;
                if (side == 1) gLo *= 0.5;
                side = 1;
            } else {
                lo = at;
                gLo = g;
                if (side == -1) gHi *= 0.5;
                side = -1;
            }
            ++count;
        }
        if (phase == kBack) {
            if (count < KERF_EXACT_STEPS && g < -eps && at > searched) {
                at = max(at + g, searched);
                ++count;
                continue;
            }
            return at;
        }
        if (phase == kMarch) {
            if (gLo < eps) return lo;
            if (lo + gLo >= b) {
                searched = b;
                return -1.0;
            }
            if (count < (hi < 0.0 ? KERF_EXACT_STEPS : KERF_EXACT_BRACKETED_STEPS)) {
                at = lo + gLo;
                ++count;
                if (hi < 0.0 || at < hi) continue;
                phase = kRefine;
                count = 0;
            } else if (hi < 0.0) {
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
            if (!(at > lo && at < hi)) at = 0.5 * (lo + hi);
            continue;
        }
        return hi;
    }
    return hi;
}

// Exact's refinement of a listed ray: kRefineLanes lanes search
// the window together, one point each a round (ReferenceTracer.cpp,
// exactCrossingLanes, which says why and how). Every lane of the ray runs
// this with the same arguments and takes the same decisions; the values are
// exchanged by subgroup shuffles, the first segment not certified found by
// a ballot.
int refineSpacingOffset(bool first) { return first ? 0 : 1; }
int refineSpacingDivisions(bool first, bool knownEnd)
{
    return first ? kRefineLanes - 1 : (knownEnd ? kRefineLanes + 1 : kRefineLanes);
}
float refinePoint(float lo, float end, int j, int offset, int divisions)
{
    if (j + offset == divisions) return end;
    return lo + (end - lo) * (float(j + offset) / float(divisions));
}
bool refineSegmentCertified(float x0, float f0, float x1, float f1, float eps, float gap)
{
    return !(f1 < eps) && (f0 + f1 >= x1 - x0 || x1 - x0 <= gap);
}
float refineFinish(float x0, float f0, float x1, float f1, float eps)
{
    if (!(f1 < f0)) return x1;
    const float root = x1 - f1 * ((x1 - x0) / (f1 - f0));
    return clamp(root, min(x0 + f0, x1), f1 <= 0.0 ? x1 : x1 + eps);
}
// The value lane j of this ray holds.
float laneValue(float v, int j) { return subgroupShuffle(v, refineLaneBase + uint(j)); }

float exactCrossingLanes(uint tape, vec3 e, vec3 dir, float tileSize, float s0, float s1, float sTileEnd,
                         float voxelEdge, inout float searched)
{
    const int lanes = kRefineLanes;
    const float margin = float(KERF_EXACT_MARGIN) * voxelEdge;
    const float eps = float(KERF_EXACT_EPSILON) * voxelEdge;
    const float gap = float(KERF_EDGE_REFINE_GAP) * voxelEdge;
    const float finish = float(KERF_EDGE_REFINE_FINISH) * voxelEdge;
    const float a = max(searched, s0 - margin);
    const float b = min(s1 + margin, sTileEnd);
    if (!(a < b)) return -1.0;
    float lo = a, fLo = kInf;
    float hi = b;
    float end = b, fEnd = 0.0;
    bool known = false;
    bool bracketed = false;
    float span = b - a;
    const int j = int(refineLane);
    for (int round = 0; round < KERF_EDGE_REFINE_WINDOW_ROUNDS; ++round) {
        ++refineRounds;
        if (round > 0 && !known) end = span < hi - lo ? lo + span : hi;
        const int offset = refineSpacingOffset(round == 0), divisions = refineSpacingDivisions(round == 0, known);
        const float x = refinePoint(lo, end, j, offset, divisions);
        const float f = exactAt(tape, e, dir, tileSize, x);
        // This lane's segment: from the previous lane's point (lane 0: lo).
        const float fBefore = laneValue(f, max(j - 1, 0));
        const float xBefore = j == 0 ? lo : refinePoint(lo, end, j - 1, offset, divisions);
        const bool certified = refineSegmentCertified(xBefore, j == 0 ? fLo : fBefore, x, f, eps, gap);
        const uvec4 votes = subgroupBallot(!certified);
        // This ray's lanes' votes (all 32 of a word: a shift by 32 is undefined).
        const uint mine = lanes == 32 ? votes[refineLaneBase >> 5u]
                                      : (votes[refineLaneBase >> 5u] >> (refineLaneBase & 31u)) & ((1u << uint(lanes)) - 1u);
        int k = mine == 0u ? lanes : findLSB(mine);
        const float fLast = laneValue(f, lanes - 1);
        // The known end, one more point after the lanes'.
        if (k == lanes && known && !refineSegmentCertified(refinePoint(lo, end, lanes - 1, offset, divisions), fLast,
                                                             end, fEnd, eps, gap))
            k = lanes + 1; // not a lane: stands for the known end below
        if (k == lanes) {
            const float xLast = known ? end : refinePoint(lo, end, lanes - 1, offset, divisions);
            const float fAtLast = known ? fEnd : fLast;
            if (xLast == b) {
                searched = b;
                return -1.0;
            }
            span = (xLast - lo) * float(lanes + 1);
            lo = xLast;
            fLo = fAtLast;
            known = false;
            continue;
        }
        const bool atEnd = k == lanes + 1;
        const int kk = atEnd ? lanes : k;
        const float xk = atEnd ? end : refinePoint(lo, end, kk, offset, divisions);
        const float fk = atEnd ? fEnd : laneValue(f, kk);
        const float xPrev = kk == 0 ? lo : refinePoint(lo, end, kk - 1, offset, divisions);
        const float fPrev = kk == 0 ? fLo : laneValue(f, kk - 1);
        if (fk < eps) {
            if (round == 0 && kk == 0) {
                if (fk > -eps) return xk;
                float at = xk, g = fk;
                for (int count = 0; count < KERF_EXACT_STEPS && g < -eps && at > searched; ++count) {
                    at = max(at + g, searched);
                    ++refineRounds;
                    g = exactAt(tape, e, dir, tileSize, at);
                }
                return at;
            }
            if (!(xk - (xPrev + fPrev) > finish)) return refineFinish(xPrev, fPrev, xk, fk, eps);
            bracketed = true;
            hi = xk;
        }
        lo = xPrev;
        fLo = fPrev;
        end = xk;
        fEnd = fk;
        known = true;
    }
    if (bracketed) return hi;
    searched = max(searched, lo);
    return -1.0;
}

bool traceTile(uint entry, uint tape, ivec3 tile, vec3 origin, vec3 dir, vec3 invDir, float tileSize, float tEnter,
               inout Hit hit)
{
    const uint eNode = word(P.entries, entry * 8u + 0u);
    const uint eLeafInd = word(P.entries, entry * 8u + 1u);
    const uint eLeafData = word(P.entries, entry * 8u + 2u);
    const uint eVertex = word(P.entries, entry * 8u + 3u);
    const int levels = int(word(P.entries, entry * 8u + 4u));
    const int n = 1 << (2 * levels);
    const float fn = float(n);
    const float invN = 1.0 / fn;
    const float invTile = 1.0 / tileSize;

    const vec3 e = clamp((origin - vec3(tile) * tileSize + tEnter * dir) * invTile, 0.0, 1.0);
    ivec3 cell = clamp(ivec3(floor(e * fn)), ivec3(0), ivec3(n - 1));
    float s = 0.0;
    const vec3 sFaces = (vec3(greaterThan(dir, vec3(0.0))) - e) * invDir;
    const float sTileEnd = min(sFaces.x, min(sFaces.y, sFaces.z));
    float searched = 0.0;
    // ReferenceTracer.cpp: the clearance of the voxel passed last, held back while the next cell may be the hit.
    float pending = kInf;
    bool pendingAdjacent = false;

    const int maxIterations = 3 * n + 3;
    for (int iteration = 0; iteration < maxIterations; ++iteration) {
        uint node = eNode;
        int cellShift = 0;
        bool isVoxel = false;
        uint leafIndirection = 0u, voxelRank = 0u;
        int depth = 0;
        for (; depth < levels; ++depth) {
            const int shift = 2 * (levels - 1 - depth);
            const int c = childIndex((cell.x >> shift) & 3, (cell.y >> shift) & 3, (cell.z >> shift) & 3);
            const uint header = word(P.nodes, node * 3u);
            const uint maskLo = word(P.nodes, node * 3u + 1u);
            const uint maskHi = word(P.nodes, node * 3u + 2u);
            cellShift = shift;
            if (!hasChild(maskLo, maskHi, c)) break;
            if ((header & kLeafFlag) != 0u) {
                isVoxel = true;
                leafIndirection = eLeafInd + (header & ~kLeafFlag);
                voxelRank = childRank(maskLo, maskHi, c);
                break;
            }
            node = eNode + (header & ~kLeafFlag) + childRank(maskLo, maskHi, c);
        }

        const ivec3 lo = (cell >> cellShift) << cellShift;
        const ivec3 hi = lo + (1 << cellShift);
        const vec3 bound = vec3(dir.x > 0.0 ? float(hi.x) : float(lo.x), dir.y > 0.0 ? float(hi.y) : float(lo.y),
                                dir.z > 0.0 ? float(hi.z) : float(lo.z));
        const vec3 sAxis = (bound * invN - e) * invDir;
        const float sExit = min(sAxis.x, min(sAxis.y, sAxis.z));

        if (isVoxel) {
            const int voxelShift = 2 * (levels - 1 - depth);
            const float cellsPerVoxel = float(1 << voxelShift);
            const float voxelScale = fn / cellsPerVoxel;
            const float voxelMm = tileSize / voxelScale;
            const vec3 voxelLo = vec3(lo) * invN;
            const uint liData = word(P.leafIndirections, leafIndirection * 2u);
            const uint liVertex = word(P.leafIndirections, leafIndirection * 2u + 1u);
            const uint ldIndex = eLeafData + liData + voxelRank;
            const uint ld0 = word(P.leafData, ldIndex * 2u), ld1 = word(P.leafData, ldIndex * 2u + 1u);
            uint vtx[8];
            float d[8];
            [[unroll]] for (int q = 0; q < 8; ++q) {
                const uint corner = ((q < 4 ? ld0 : ld1) >> (8 * (q & 3))) & 0xFFu;
                vtx[q] = eVertex + liVertex + corner;
                d[q] = decodeDistance(word(P.vertices, vtx[q] * 2u + 1u), voxelMm);
            }
            float k[8];
            trilinear(d, k);
            const vec3 o = clamp((e + s * dir - voxelLo) * voxelScale, 0.0, 1.0);
            const float wEnd = max(0.0, (sExit - s) * voxelScale);
            const vec4 along = alongRay(k, o, dir);
            if (capPending) {
                if (capInsideAtEntry(evalCubic(along, 0.0), voxelMm,
                                     tEnter + s * tileSize - capDepth > 1e-3 * voxelMm)) {
                    hitCap(hit);
                    return true;
                }
                capPending = false;
            }
            float least = 0.0;
            const float w = firstCrossing(along, wEnd, least);
            // ReferenceTracer.cpp: how close the ray came to this voxel's surface, in units of the
            // check's clearance (the voxel pass of TraceQuality::Exact only).
            float clearance = kInf, allowed = float(KERF_EDGE_CHECK_CLEARANCE);
            if (kPass == kTraceVoxels && w < 0.0 &&
                least / voxelMm < float(KERF_EDGE_CHECK_CLEARANCE)) {
                // ReferenceTracer.cpp, cornerClearance.
                // A loop, not unrolled, over the corners' words again (not
                // vtx[]): unrolled, its loads were hoisted and held registers
                // through the whole voxel walk.
                const uint vertexBase = eVertex + liVertex;
                const vec3 first = decodeNormal(word(P.vertices, vtx[0] * 2u));
                float cosine = 1.0;
                [[dont_unroll]] for (int q = 1; q < 8; ++q) {
                    const uint corner = ((q < 4 ? ld0 : ld1) >> (8 * (q & 3))) & 0xFFu;
                    cosine = min(cosine, dot(first, decodeNormal(word(P.vertices, (vertexBase + corner) * 2u))));
                }
                allowed = clamp(float(KERF_EDGE_CHECK_CLEARANCE_PER_RADIAN) * acos(clamp(cosine, -1.0, 1.0)),
                                float(KERF_EDGE_CHECK_SMOOTH_CLEARANCE), float(KERF_EDGE_CHECK_CLEARANCE));
                clearance = least / voxelMm / allowed;
            }
            const bool near = w >= 0.0 || clearance < 1.0;
            if (kPass == kTraceVoxels && near) {
                const float margin = float(KERF_EXACT_MARGIN) / voxelScale;
                hit.nearFrom = min(hit.nearFrom, tEnter + (s - margin) * tileSize);
                hit.nearTo = max(hit.nearTo, tEnter + (sExit + margin) * tileSize);
            }
            if (kHybrid && tape != KERF_NO_TAPE &&
                (kPass != kTraceListed || refineRounds < KERF_EDGE_REFINE_ROUNDS)) {
                const float voxelEdge = 1.0 / voxelScale;
                const float sHit =
                    kPass == kTraceListed
                        ? exactCrossingLanes(tape, e, dir, tileSize, s, sExit, sTileEnd, voxelEdge, searched)
                        : exactCrossing(tape, e, dir, tileSize, s, sExit, sTileEnd, voxelEdge,
                                        w >= 0.0 ? s + w / voxelScale : -1.0, searched);
                if (sHit >= 0.0 && onlyTouches(tape, e, dir, tileSize, sHit, voxelEdge)) {
                    // A sheet of no thickness, not a surface: search on past it (ReferenceTracer.cpp).
                    searched = max(searched, sHit + float(KERF_EXACT_TOUCH_FAR) * voxelEdge);
                } else if (sHit >= 0.0) {
                    hit.tape = tape;
                    hit.point = (e + max(sHit - float(KERF_EXACT_EPSILON) * voxelEdge, 0.0) * dir) * tileSize;
                    hit.normal = -dir;
                    hit.feature = kNoFeature;
                    hit.depth = tEnter + sHit * tileSize;
                    return true;
                }
            }
            if (w >= 0.0) {
                // ReferenceTracer.cpp: the voxel passed just before on a smooth sheet.
                if (kPass == kTraceVoxels && !pendingAdjacent) hit.clearance = min(hit.clearance, pending);
                const vec3 u = clamp(o + w * dir, 0.0, 1.0);
                vec3 nrm = vec3(0.0);
                float nearest = kInf;
                uint feature = kNoFeature;
                [[unroll]] for (int q = 0; q < 8; ++q) {
                    const uint nw = word(P.vertices, vtx[q] * 2u);
                    const uint dw = word(P.vertices, vtx[q] * 2u + 1u);
                    const vec3 corner = vec3(float(q & 1), float((q >> 1) & 1), float(q >> 2));
                    const vec3 weight3 = mix(vec3(1.0) - u, u, corner);
                    nrm += (weight3.x * weight3.y * weight3.z) * decodeNormal(nw);
                    const vec3 toCorner = u - corner;
                    const float dist2 = dot(toCorner, toCorner);
                    if (dist2 < nearest) {
                        nearest = dist2;
                        feature = dw >> 16;
                    }
                }
                float len = length(nrm);
                if (!(len > 1e-6)) {
                    nrm = trilinearGradient(k, u);
                    len = length(nrm);
                }
                hit.normal = len > 0.0 ? nrm / len : -dir;
                hit.feature = feature;
                hit.depth = tEnter + (s + w / voxelScale) * tileSize;
                return true;
            }
            if (kPass == kTraceVoxels) {
                // (ReferenceTracer.cpp: a run of voxels closing in on the hit's sheet is let off.)
                if (clearance < 1.0 && allowed < float(KERF_EDGE_CHECK_CLEARANCE) && least >= evalCubic(along, wEnd)) {
                    pending = pendingAdjacent ? min(pending, clearance) : clearance;
                    pendingAdjacent = true;
                } else {
                    hit.clearance = min(hit.clearance, min(pending, clearance));
                    pending = kInf;
                    pendingAdjacent = false;
                }
            }
        } else if (kPass == kTraceVoxels) {
            hit.clearance = min(hit.clearance, pending); // an empty cell in between
            pending = kInf;
            pendingAdjacent = false;
        }

        s = max(s, sExit);
        const vec3 p = (e + s * dir) * fn;
        ivec3 next = clamp(ivec3(floor(p)), lo, hi - 1);
        if (sAxis.x <= sExit) next.x = dir.x > 0.0 ? hi.x : lo.x - 1;
        if (sAxis.y <= sExit) next.y = dir.y > 0.0 ? hi.y : lo.y - 1;
        if (sAxis.z <= sExit) next.z = dir.z > 0.0 ? hi.z : lo.z - 1;
        cell = next;
        if (cell.x < 0 || cell.y < 0 || cell.z < 0 || cell.x >= n || cell.y >= n || cell.z >= n) break;
    }
    if (kPass == kTraceVoxels) hit.clearance = min(hit.clearance, pending); // the tile ends
    return false;
}

// `from`, `to`: the stretch of the ray to trace where no section plane is
// set (ReferenceTracer.cpp, traceGrid).
Hit traceRay(vec3 origin, vec3 direction, float from, float to)
{
    Hit hit;
    hit.depth = kInf;
    hit.normal = vec3(0.0);
    hit.feature = kNoFeature;
    hit.tape = KERF_NO_TAPE;
    hit.point = vec3(0.0);
    hit.clearance = kInf;
    hit.nearFrom = kInf;
    hit.nearTo = -kInf;

    const vec3 dir = nonZero(direction);
    const vec3 invDir = 1.0 / dir;
    const float tileSize = P.eye.w;
    const ivec3 dims = P.dims.xyz;

    const vec3 t0 = (vec3(0.0) - origin) * invDir;
    const vec3 t1 = (vec3(dims) * tileSize - origin) * invDir;
    const vec3 tNear = min(t0, t1), tFar = max(t0, t1);
    float tEnter = max(max(tNear.x, tNear.y), max(tNear.z, 0.0));
    float tLeave = min(tFar.x, min(tFar.y, tFar.z));
    int enterAxis = tNear.x >= tNear.y && tNear.x >= tNear.z ? 0 : (tNear.y >= tNear.z ? 1 : 2);

    // The section plane keeps dot(n, p) <= offset (ReferenceTracer.cpp).
    const vec3 n = P.section.xyz;
    if (n != vec3(0.0)) {
        const float denom = dot(n, dir);
        const float above = dot(n, origin) - P.section.w;
        if (abs(denom) < 1e-12) {
            if (above > 0.0) return hit;
        } else {
            const float tPlane = -above / denom;
            if (denom > 0.0) {
                tLeave = min(tLeave, tPlane);
            } else if (tPlane > tEnter) {
                tEnter = tPlane;
                capPending = true;
                capDepth = tPlane;
                capNormal = n;
            }
        }
    }
    if (n == vec3(0.0)) {
        tEnter = max(tEnter, from);
        tLeave = min(tLeave, to);
    }
    if (!(tEnter <= tLeave)) return hit;

    const vec3 p = (origin + tEnter * dir) / tileSize;
    ivec3 tile = clamp(ivec3(floor(p)), ivec3(0), dims - 1);
    const ivec3 stepDir = ivec3(dir.x > 0.0 ? 1 : -1, dir.y > 0.0 ? 1 : -1, dir.z > 0.0 ? 1 : -1);
    const vec3 tDelta = abs(invDir) * tileSize;
    vec3 tNext = ((vec3(tile) + vec3(greaterThan(dir, vec3(0.0)))) * tileSize - origin) * invDir;
    const int maxTileSteps = dims.x + dims.y + dims.z + 3;
    // Vectors are indexed by axis through selections, never tNext[axis]: a
    // vector indexed by a variable went to local memory on NVIDIA
    // (kerf_gpu_bench --pipeline-statistics).
    for (int i = 0; i < maxTileSteps; ++i) {
        const int axis = tNext.x <= tNext.y && tNext.x <= tNext.z ? 0 : (tNext.y <= tNext.z ? 1 : 2);
        const bvec3 isAxis = equal(ivec3(axis), ivec3(0, 1, 2));
        const float tExitTile = min(tNext.x, min(tNext.y, tNext.z));
        const uint value = word(P.tiles, uint(tile.x + dims.x * (tile.y + dims.y * tile.z)));
        if (value == kFullTile && capPending) {
            hitCap(hit);
            return hit;
        }
        // Outside, as the plane's point was, where the ray crosses it for a length (ReferenceTracer.cpp).
        if (value == kEmptyTile && tExitTile - tEnter > 1e-3 * tileSize) capPending = false;
        if (value == kFullTile) {
            hit.depth = tEnter;
            hit.normal = mix(vec3(0.0), -vec3(stepDir), equal(ivec3(enterAxis), ivec3(0, 1, 2)));
            hit.feature = kNoFeature;
            return hit;
        }
        const uint tape =
            kHybrid && value != kEmptyTile && P.options.x == 1u ? word(P.entries, value * 8u + 5u) : KERF_NO_TAPE;
        if (value != kEmptyTile && traceTile(value, tape, tile, origin, dir, invDir, tileSize, tEnter, hit)) {
            if (hit.depth > tLeave) { // past the section plane: in the part cut away
                hit.depth = kInf;
                hit.normal = vec3(0.0);
                hit.feature = kNoFeature;
                hit.tape = KERF_NO_TAPE;
            }
            return hit;
        }
        if (tExitTile >= tLeave) break;
        tEnter = max(tEnter, tExitTile);
        tile += stepDir * ivec3(isAxis);
        tNext = mix(tNext, tNext + tDelta, isAxis);
        enterAxis = axis;
        if (any(lessThan(tile, ivec3(0))) || any(greaterThanEqual(tile, dims))) break;
    }
    return hit;
}

// The camera's ray through the pixel centre (tracer/src/Camera.cpp, Camera::ray).
void cameraRay(uvec2 px, out vec3 origin, out vec3 direction)
{
    const float width = float(P.image.x), height = float(P.image.y);
    const float aspect = width / height;
    const float u = (2.0 * (float(px.x) + 0.5) / width - 1.0) * aspect;
    const float v = 1.0 - 2.0 * (float(px.y) + 0.5) / height;
    const float halfHeight = P.right.w;
    if (P.forward.w > 0.5) {
        origin = P.eye.xyz + (u * halfHeight) * P.right.xyz + (v * halfHeight) * P.up.xyz;
        direction = P.forward.xyz;
    } else {
        origin = P.eye.xyz;
        direction = normalize(P.forward.xyz + (u * halfHeight) * P.right.xyz + (v * halfHeight) * P.up.xyz);
    }
}

// The check of a voxel hit on the exact field (tracer/src/VoxelHitCheck.cpp,
// checkVoxelHit): writes the pixel's confirmed hit, leaves the voxels' one,
// or lists the pixel for the refinement.
const int kVerdictKeep = 0, kVerdictConfirm = 1, kVerdictRefine = 2;

int checkVoxelHit(vec3 origin, vec3 dir, inout Hit hit)
{
    if (hit.clearance < 1.0) return kVerdictRefine;
    if (!(hit.depth < kInf) || hit.feature == kSectionCap) return kVerdictKeep;

    const float tileSize = P.eye.w;
    const ivec3 dims = P.dims.xyz;
    const vec3 p = origin + hit.depth * dir;
    const ivec3 tile = clamp(ivec3(floor(p / tileSize)), ivec3(0), dims - 1);
    const uint value = word(P.tiles, uint(tile.x + dims.x * (tile.y + dims.y * tile.z)));
    if (value == kEmptyTile || value == kFullTile) return kVerdictRefine;
    const uint tape = word(P.entries, value * 8u + 5u);
    if (tape == KERF_NO_TAPE) return kVerdictKeep;
    const float voxelEdge = tileSize / float(1 << (2 * int(word(P.entries, value * 8u + 4u))));

    const vec3 local = p - vec3(tile) * tileSize;
    const float f0 = evaluateTileTape(tape, local);
    const float voxelSlope = dot(hit.normal, dir);
    if (!(voxelSlope < -float(KERF_EDGE_CHECK_FACING))) return kVerdictRefine;
    const float step = -f0 / voxelSlope;
    if (!(abs(step) <= float(KERF_EDGE_CHECK_SHIFT) * voxelEdge)) return kVerdictRefine;
    const vec3 landed = local + step * dir;
    if (any(lessThan(landed, vec3(0.0))) || any(greaterThan(landed, vec3(tileSize)))) return kVerdictRefine;
    uint feature = kNoFeature;
    const vec4 fg = evaluateTileTapeGradient(tape, landed, feature);
    const vec3 g = fg.yzw;
    const float len = length(g);
    const float slope = dot(g, dir);
    if (!(slope < -float(KERF_EDGE_CHECK_FACING) * len)) return kVerdictRefine;
    const float finish = -fg.x / slope;
    if (!(abs(finish) <= float(KERF_EDGE_CHECK_RESIDUAL) * voxelEdge)) return kVerdictRefine;
    if (!(dot(g, hit.normal) >= cos(radians(float(KERF_EDGE_CHECK_SMOOTH_ANGLE))) * len)) return kVerdictRefine;

    const vec3 finished = landed + finish * dir;
    if (any(lessThan(finished, vec3(0.0))) || any(greaterThan(finished, vec3(tileSize)))) return kVerdictRefine;
    if (!(abs(evaluateTileTape(tape, finished)) <= float(KERF_EDGE_CHECK_ON_SURFACE) * voxelEdge))
        return kVerdictRefine;

    const float depth = hit.depth + step + finish;
    const vec3 n = P.section.xyz;
    if (n != vec3(0.0) && dot(n, origin + depth * dir) > P.section.w) return kVerdictRefine;
    hit.depth = depth;
    hit.normal = g / len;
    hit.feature = feature;
    return kVerdictConfirm;
}

// The exact field's gradient at a refined hit (ReferenceTracer.cpp, traceRay).
void takeExactNormal(inout Hit h)
{
    uint feature = kNoFeature;
    const vec4 fg = evaluateTileTapeGradient(h.tape, h.point, feature);
    const float len = length(fg.yzw);
    h.normal = len > 0.0 ? fg.yzw / len : h.normal;
    h.feature = feature;
}

void listVoxelPassPixel(uint i, Hit h);

// One pixel's trace (kTraceAll, kTraceVoxels, kTraceListed): its outputs written.
void tracePixel(uvec2 px)
{
    const uint i = px.x + P.image.x * px.y;
    vec3 origin, direction;
    cameraRay(px, origin, direction);
    capPending = false;
    refineRounds = 0u;
    // A listed ray: only the stretch where the voxels met the surface or came near it.
    const vec2 stretch = kPass == kTraceListed ? ReadVec4s(P.outVoxelPass).v[i].yz : vec2(0.0, kInf);
    Hit h = traceRay(origin, direction, stretch.x, stretch.y);
    if (kPass == kTraceListed) {
        if (refineLane != 0u) return; // the ray's first lane writes it
        // What kFinishListed completes, in the normal's w: 1, the refined hit's
        // point (the normal's xyz) on its tape (the feature); 2, a voxel hit
        // reached after the budget ran out, for the check's Newton steps
        // (ReferenceTracer.cpp); 0, nothing.
        const bool refined = h.tape != KERF_NO_TAPE;
        const bool spent = !refined && h.depth < kInf && refineRounds >= KERF_EDGE_REFINE_ROUNDS;
        Floats(P.outDepth).f[i] = h.depth;
        Vec4s(P.outNormal).v[i] = refined ? vec4(h.point, 1.0) : vec4(h.normal, spent ? 2.0 : 0.0);
        Uints(P.outFeature).u[i] = refined ? h.tape : h.feature;
        return;
    }
    if (kHybrid && h.tape != KERF_NO_TAPE) takeExactNormal(h);
    Floats(P.outDepth).f[i] = h.depth;
    Vec4s(P.outNormal).v[i] = vec4(h.normal, 0.0);
    Uints(P.outFeature).u[i] = h.feature;
    if (kPass == kTraceVoxels) listVoxelPassPixel(i, h);
}

// Lists pixel i for the refinement, with the stretch of its ray the voxels
// met or came near the surface in.
void listForRefinement(uint i, vec2 stretch)
{
    const uint listed = atomicAdd(RefineArgs(P.refineArgs).count, 1u);
    // A ray's refinement searches a window at every populated voxel of its
    // stretch: rays with long stretches take the most rounds. They go to
    // the list's front, the rest to its back, so that the refinement's
    // first workgroups, which the GPU starts first, take the long ones and
    // the frame does not wait on a long ray started last.
    const bool longStretch = stretch.y - stretch.x > float(KERF_EDGE_REFINE_LONG) * P.up.w;
    const uint slot = longStretch ? atomicAdd(RefineArgs(P.refineArgs).front, 1u)
                                  : P.image.x * P.image.y - 1u - atomicAdd(RefineArgs(P.refineArgs).back, 1u);
    RefineList(P.refineList).pixel[slot] = i;
    // One more workgroup of the refinement's indirect dispatch per 64 lanes listed.
    if (listed % uint(KERF_TRACE_LOCAL_SIZE * KERF_TRACE_LOCAL_SIZE / kRefineLanes) == 0u)
        atomicAdd(RefineArgs(P.refineArgs).groups, 1u);
    // And of the finishing pass's per 64 pixels.
    if (listed % uint(KERF_TRACE_LOCAL_SIZE * KERF_TRACE_LOCAL_SIZE) == 0u)
        atomicAdd(RefineArgs(P.refineArgs).finishGroups, 1u);
}

// The voxel pass's verdict on its pixel i: listed for the refinement (the
// ray passed too close to a voxel's surface), for the check (a voxel hit
// on the part), or neither (a miss, a section's cap): checkVoxelHit's
// first two rules, taken where the ray was traced, so that the check runs
// on the voxel hits alone, packed into whole subgroups. Every invocation
// of the subgroup that traced a pixel calls this (a ballot).
void listVoxelPassPixel(uint i, Hit h)
{
    const bool refine = h.clearance < 1.0;
    const bool check = !refine && h.depth < kInf && h.feature != kSectionCap;
    if (refine || check) Vec4s(P.outVoxelPass).v[i] = vec4(h.clearance, h.nearFrom, h.nearTo, 0.0);
    if (refine) listForRefinement(i, vec2(h.nearFrom, h.nearTo));
    const uvec4 votes = subgroupBallot(check);
    const uint n = subgroupBallotBitCount(votes);
    if (n == 0u) return;
    uint base = 0u;
    if (subgroupElect()) {
        base = atomicAdd(RefineArgs(P.refineArgs).checkCount, n);
        atomicMax(RefineArgs(P.refineArgs).checkGroups,
                  (base + n + uint(KERF_TRACE_LOCAL_SIZE * KERF_TRACE_LOCAL_SIZE) - 1u) /
                      uint(KERF_TRACE_LOCAL_SIZE * KERF_TRACE_LOCAL_SIZE));
    }
    base = subgroupBroadcastFirst(base);
    if (check) CheckList(P.checkList).pixel[base + subgroupBallotExclusiveBitCount(votes)] = i;
}

// The check of pixel i's voxel hit (kCheckHits), listed by the voxel pass.
void checkPixel(uint i)
{
    vec3 origin, direction;
    cameraRay(uvec2(i % P.image.x, i / P.image.x), origin, direction);
    Hit h;
    h.depth = ReadFloats(P.outDepth).f[i];
    h.normal = ReadVec4s(P.outNormal).v[i].xyz;
    h.feature = Words(P.outFeature).w[i];
    const vec4 voxelPass = ReadVec4s(P.outVoxelPass).v[i];
    h.clearance = voxelPass.x;
    const vec3 dir = nonZero(direction);
    const int verdict = checkVoxelHit(origin, dir, h);
    if (verdict == kVerdictConfirm) {
        Floats(P.outDepth).f[i] = h.depth;
        Vec4s(P.outNormal).v[i] = vec4(h.normal, 0.0);
        Uints(P.outFeature).u[i] = h.feature;
    } else if (verdict == kVerdictRefine) {
        listForRefinement(i, voxelPass.yz);
    }
}

// kFinishListed: what the listed pass left to complete at one listed pixel.
void finishPixel(uint i)
{
    const vec4 left = ReadVec4s(P.outNormal).v[i];
    if (left.w == 0.0) return;
    vec3 origin, direction;
    cameraRay(uvec2(i % P.image.x, i / P.image.x), origin, direction);
    const vec3 dir = nonZero(direction);
    Hit h;
    h.depth = ReadFloats(P.outDepth).f[i];
    h.feature = Words(P.outFeature).w[i];
    if (left.w == 1.0) {
        h.tape = h.feature;
        h.point = left.xyz;
        h.normal = -dir; // as the refinement left it
        takeExactNormal(h);
    } else {
        h.normal = left.xyz;
        h.clearance = kInf;
        checkVoxelHit(origin, dir, h);
    }
    Floats(P.outDepth).f[i] = h.depth;
    Vec4s(P.outNormal).v[i] = vec4(h.normal, 0.0);
    Uints(P.outFeature).u[i] = h.feature;
}

// The pixel of the refinement's list at a slot (the long stretches at its front, the rest at its back).
uint listedPixel(uint slot)
{
    const uint front = RefineArgs(P.refineArgs).front;
    return RefineList(P.refineList).pixel[slot < front ? slot : P.image.x * P.image.y - 1u - (slot - front)];
}

void main()
{
    P = ParamsRef(pc.params).p;
    if (kPass == kFinishListed) {
        const uint slot = gl_WorkGroupID.x * uint(KERF_TRACE_LOCAL_SIZE * KERF_TRACE_LOCAL_SIZE) + gl_LocalInvocationIndex;
        if (slot < RefineArgs(P.refineArgs).count) finishPixel(listedPixel(slot));
        return;
    }
    if (kPass == kTraceListed) {
        // kRefineLanes consecutive invocations of a subgroup per listed pixel.
        const uint lanes = uint(kRefineLanes);
        refineLane = gl_SubgroupInvocationID % lanes;
        refineLaneBase = gl_SubgroupInvocationID - refineLane;
        const uint slot = (gl_WorkGroupID.x * uint(KERF_TRACE_LOCAL_SIZE * KERF_TRACE_LOCAL_SIZE) +
                           gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID) / lanes;
        if (slot >= RefineArgs(P.refineArgs).count) return; // the same for the ray's every lane
        const uint listed = listedPixel(slot);
        tracePixel(uvec2(listed % P.image.x, listed / P.image.x));
        return;
    }
    if (kPass == kCheckHits) {
        const uint slot = gl_WorkGroupID.x * uint(KERF_TRACE_LOCAL_SIZE * KERF_TRACE_LOCAL_SIZE) + gl_LocalInvocationIndex;
        if (slot < RefineArgs(P.refineArgs).checkCount) checkPixel(CheckList(P.checkList).pixel[slot]);
        return;
    }
    const uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= P.image.x || px.y >= P.image.y) return;
    tracePixel(px);
}

#version 460
// The GPU voxelizer (the f-rep-voxel-rendering seed; Keeter 2020): builds
// the contrees of many surface tiles at once, level by level, into the flat
// buffers the tracer reads (docs/voxel-format.md). The C++ reference is
// voxelizer/src/TileBuilder.cpp; GpuVoxelizer.cpp drives the passes.
//
// Inner pass: one workgroup per node of the level; thread c tests child c's
// box with the tile's tape in interval arithmetic (tape.glsl). Children
// that may hold surface become the node's mask (subgroup ORs, no thread
// looping over the others); one atomic claims their
// node range (contiguous, in mask order, as the format wants) and another
// their jobs for the next level. Leaf pass: one workgroup per leaf node;
// the 125 lattice points are evaluated once, voxels whose corners change
// sign are populated, their corners become vertices (value, exact normal
// by forward differentiation, deciding feature), each once per leaf.
//
// Compiled twice (viewport/CMakeLists.txt): with KERF_VOXELIZE_INNER the
// inner pass, with KERF_VOXELIZE_LEAF the leaf and finish passes; each
// pipeline then has the registers of its own evaluator only (one shader
// for all passes gave the leaves the interval evaluator's register count,
// and fewer groups per multiprocessor).
//
// Tapes pruned per node (Keeter 2020, section 4): a node's box often lies
// where one operand of a min or max decides it (a leg far from the seat it
// is blended with), and its subtree then needs only that operand. Each
// thread of the inner pass records, while it evaluates its child's
// interval, the instructions that box leaves out of the tile's tape, on
// top of those its node left out (in the node's job); the child's job
// carries them down, and every evaluation below passes over them. The
// values are the whole tape's, bit for bit (tape.glsl says why). The chair
// at 0.25 mm: 6.5 instructions per leaf node's tile tape, 1.2 once pruned.
//
// Offsets: a tile's entry has its root node's index as `node` and 0 for
// the other three bases, so node pointers are relative to the root and
// every other pointer is absolute: pools are shared by all tiles.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "VoxelizeShared.h"
#include "voxel_format.glsl"

layout(local_size_x = KERF_VOXELIZE_GROUP) in;

layout(buffer_reference, std430, buffer_reference_align = 4) buffer Words { uint w[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ParamsRef { VoxelizeParams p; };

layout(push_constant) uniform Push
{
    uint64_t params;
    uint pass;
    uint level; // inner pass: the level of the nodes processed (0 = the tiles' roots)
    uint list;  // the job list read (0 or 1); the other one is written
    uint prune; // 1: tapes pruned per node (the benchmarks turn it off)
} pc;

VoxelizeParams P;

uint tapeWord(uint t, uint i) { return Words(P.tapes).w[t + i]; }

#define KERF_TAPE_PRUNING
#include "tape.glsl"

// Lattice coordinate n (in finest voxels) in tile-relative mm, as the CPU
// computes it: the product with the voxel edge in double, rounded to float
// once. A float product of the float edge rounds twice, and a face on a
// lattice plane then lands a hair inside on one side and exactly on the
// surface on the other. Here the edge is a 40-bit integer mantissa and a
// power of two: n (< 2^22) times the mantissa is exact in 64 bits, its
// conversion rounds once, and the power of two is exact.
float latticeMm(uint n)
{
    return ldexp(float(uint64_t(n) * P.voxelMantissa), int(P.sizes.w));
}
vec3 latticeMm(uvec3 n) { return vec3(latticeMm(n.x), latticeMm(n.y), latticeMm(n.z)); }

uint64_t jobList(uint which) { return which == 0u ? P.jobs0 : P.jobs1; }
uint jobCapacity(uint which) { return which == 0u ? P.limits.x : P.limits.w; }

// Claims `count` records of pool `counter` (capacity `capacity`); false
// when they do not fit. The counter counts the claim either way: after the
// level the host knows exactly what it asked for, grows the pool and runs
// the level again, so nothing is ever written past a pool's end.
bool claim(uint counter, uint count, uint capacity, out uint first)
{
    first = atomicAdd(Words(P.counters).w[counter], count);
    return first + count <= capacity && first + count >= first;
}

shared uint sPopulated[64];
shared uint sMaskLo, sMaskHi, sFirstNode, sFirstJob, sFirstData, sFirstVertex, sOk, sUsedPoints;
shared float sValue[125];

// Bit masks over the group's threads without a serial loop: each subgroup
// ORs its threads' bits (subgroupOr: no assumption on which threads share
// a subgroup) into its own slot, and after a barrier the slots are ORed.
// KERF_MASK_WORDS words per slot; subgroups of at least 4 threads (checked
// by the host) make at most KERF_VOXELIZE_GROUP / 4 slots.
#define KERF_MASK_WORDS 6
#define KERF_MAX_SUBGROUPS (KERF_VOXELIZE_GROUP / 4)
shared uint sSlots[KERF_MAX_SUBGROUPS * KERF_MASK_WORDS];
shared uint sMask[KERF_MASK_WORDS];

// Thread's share of mask word w: bit `bit` when `on`.
uint bitIn(bool on, uint bit, uint w) { return on && (bit >> 5) == w ? 1u << (bit & 31u) : 0u; }
// After a barrier: the group's mask word w.
uint groupMaskWord(uint w)
{
    uint word = 0u;
    for (uint s = 0u; s < gl_NumSubgroups; ++s) word |= sSlots[s * KERF_MASK_WORDS + w];
    return word;
}

uint groupIndex() { return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x; }

#ifdef KERF_VOXELIZE_INNER
void innerPass(uint job)
{
    const uint64_t jobs = jobList(pc.list);
    const uint entry = Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS];
    const uint node = Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 1u];
    const uvec3 lo = uvec3(Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 2u],
                           Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 3u],
                           Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 4u]);
    const uvec2 nodeSkip = uvec2(Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 5u],
                                 Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 6u]);
    const uint root = Words(P.entries).w[entry * 8u];
    const uint tape = Words(P.entries).w[entry * 8u + 5u];
    const uint childEdge = 1u << (2u * (P.limits.z - pc.level - 1u)); // in finest voxels
    const uint c = gl_LocalInvocationID.x;
    const uvec3 clo = lo + childEdge * uvec3(c & 3u, (c >> 2) & 3u, c >> 4);
    bool kept = false;
    uvec2 childSkip = uvec2(0u);
    if (c < 64u) {
        const float margin = P.sizes.z;
        tapeSkip = nodeSkip;
        tapePruning = pc.prune != 0u;
        const vec2 iv = evaluateTileTapeInterval(tape, latticeMm(clo) - margin, latticeMm(clo + childEdge) + margin);
        childSkip = tapeSkip; // what the child's box leaves out
        // Pruned only when provably empty or full (a NaN interval is kept, as in C++).
        kept = !(iv.x > 0.0 || iv.y < 0.0);
    }
    for (uint w = 0u; w < 2u; ++w) {
        const uint word = subgroupOr(bitIn(kept, c, w));
        if (subgroupElect()) sSlots[gl_SubgroupID * KERF_MASK_WORDS + w] = word;
    }
    barrier();
    if (c == 0u) {
        uint lo32 = groupMaskWord(0u), hi32 = groupMaskWord(1u);
        const uint count = uint(bitCount(lo32) + bitCount(hi32));
        uint firstNode = 0u, firstJob = 0u;
        bool ok = true;
        if (count != 0u) { // both claims always made: each counter then says what the level needs
            const bool nodesFit = claim(KERF_COUNT_NODES, count, P.capacity.x, firstNode);
            const bool jobsFit = claim(KERF_COUNT_JOBS + 1u - pc.list, count, jobCapacity(1u - pc.list), firstJob);
            ok = nodesFit && jobsFit;
        }
        if (!ok) lo32 = hi32 = 0u;
        sMaskLo = lo32;
        sMaskHi = hi32;
        sFirstNode = firstNode;
        sFirstJob = firstJob;
        Words(P.nodes).w[node * 3u] = count == 0u || !ok ? 0u : firstNode - root;
        Words(P.nodes).w[node * 3u + 1u] = lo32;
        Words(P.nodes).w[node * 3u + 2u] = hi32;
    }
    barrier();
    if (c < 64u && hasChild(sMaskLo, sMaskHi, int(c))) {
        const uint rank = childRank(sMaskLo, sMaskHi, int(c));
        const uint j = (sFirstJob + rank) * KERF_VOXELIZE_JOB_WORDS;
        const uint64_t next = jobList(1u - pc.list);
        Words(next).w[j] = entry;
        Words(next).w[j + 1u] = sFirstNode + rank;
        Words(next).w[j + 2u] = clo.x;
        Words(next).w[j + 3u] = clo.y;
        Words(next).w[j + 4u] = clo.z;
        Words(next).w[j + 5u] = childSkip.x;
        Words(next).w[j + 6u] = childSkip.y;
    }
    if (pc.level + 2u == P.limits.z) { // the leaf jobs: how many evaluate a pruned tape (the report's)
        const uint pruned = subgroupAdd(c < 64u && hasChild(sMaskLo, sMaskHi, int(c)) && childSkip != uvec2(0u) ? 1u : 0u);
        if (subgroupElect() && pruned != 0u) atomicAdd(Words(P.counters).w[KERF_COUNT_PRUNED_LEAF_JOBS], pruned);
    }
}

#else

uint latticeIndex(uint x, uint y, uint z) { return x + 5u * (y + 5u * z); }

// The position of the i-th (from 0) set bit of `word`, which has more than i.
uint selectBit(uint word, uint i)
{
    uint at = 0u;
    for (uint width = 16u; width > 0u; width >>= 1) {
        const uint low = uint(bitCount(word & ((1u << width) - 1u)));
        if (i >= low) {
            i -= low;
            word >>= width;
            at += width;
        }
    }
    return at;
}

// The lattice point of the i-th used point (i < sUsedPoints).
uint usedPoint(uint i)
{
    for (uint w = 2u; w < KERF_MASK_WORDS; ++w) {
        const uint n = uint(bitCount(sMask[w]));
        if (i < n) return 32u * w + selectBit(sMask[w], i) - 64u;
        i -= n;
    }
    return 0u; // not reached
}

// Lattice point i's vertex: its rank among the used points (mask bits 64..).
uint usedRank(uint i)
{
    const uint bit = i + 64u, w = bit >> 5;
    uint rank = uint(bitCount(sMask[w] & ((1u << (bit & 31u)) - 1u)));
    for (uint k = 2u; k < w; ++k) rank += uint(bitCount(sMask[k]));
    return rank;
}

void leafPass(uint job)
{
    const uint64_t jobs = jobList(pc.list);
    const uint entry = Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS];
    const uint node = Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 1u];
    const uvec3 lo = uvec3(Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 2u],
                           Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 3u],
                           Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 4u]);
    const uint tape = Words(P.entries).w[entry * 8u + 5u];
    tapeSkip = uvec2(Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 5u], Words(jobs).w[job * KERF_VOXELIZE_JOB_WORDS + 6u]);
    const float voxel = P.sizes.x;
    const uint t = gl_LocalInvocationID.x;
    const uvec3 l = uvec3(t % 5u, (t / 5u) % 5u, t / 25u);
    const vec3 at = latticeMm(lo + l);
    if (t < 125u) sValue[t] = evaluateTileTape(tape, at);
    barrier();
    // Voxel t: populated when its corners change sign (0 counts as outside).
    bool populated = false;
    if (t < 64u) {
        const uvec3 v = uvec3(t & 3u, (t >> 2) & 3u, t >> 4);
        uint inside = 0u;
        for (uint q = 0u; q < 8u; ++q)
            inside += sValue[latticeIndex(v.x + (q & 1u), v.y + ((q >> 1) & 1u), v.z + (q >> 2))] < 0.0 ? 1u : 0u;
        populated = inside != 0u && inside != 8u;
        sPopulated[t] = populated ? 1u : 0u;
    }
    barrier();
    // Lattice point t is used (gets a vertex) when a voxel it is a corner of is populated.
    bool used = false;
    if (t < 125u)
        for (uint q = 0u; q < 8u; ++q) {
            const ivec3 v = ivec3(l) - ivec3(q & 1u, (q >> 1) & 1u, q >> 2);
            if (all(greaterThanEqual(v, ivec3(0))) && all(lessThan(v, ivec3(4))))
                used = used || sPopulated[uint(v.x + 4 * (v.y + 4 * v.z))] != 0u;
        }
    // Mask bits 0 to 63: the populated voxels; 64 to 188: the used points.
    for (uint w = 0u; w < KERF_MASK_WORDS; ++w) {
        const uint word = subgroupOr(bitIn(populated, t, w) | bitIn(used, t + 64u, w));
        if (subgroupElect()) sSlots[gl_SubgroupID * KERF_MASK_WORDS + w] = word;
    }
    barrier();
    if (t == 0u) {
        for (uint w = 0u; w < KERF_MASK_WORDS; ++w) sMask[w] = groupMaskWord(w);
        uint lo32 = sMask[0], hi32 = sMask[1];
        // Vertices are numbered in lattice order (the rank of a used point among the used).
        const uint usedPoints = uint(bitCount(sMask[2]) + bitCount(sMask[3]) + bitCount(sMask[4]) + bitCount(sMask[5]));
        const uint count = uint(bitCount(lo32) + bitCount(hi32));
        uint indirection = 0u, firstData = 0u, firstVertex = 0u;
        bool ok = true;
        if (count != 0u) { // every claim always made: each counter then says what the level needs
            const bool leafFits = claim(KERF_COUNT_LEAF_INDIRECTIONS, 1u, P.capacity.y, indirection);
            const bool dataFits = claim(KERF_COUNT_LEAF_DATA, count, P.capacity.z, firstData);
            const bool verticesFit = claim(KERF_COUNT_VERTICES, usedPoints, P.capacity.w, firstVertex);
            ok = leafFits && dataFits && verticesFit;
        }
        if (!ok) lo32 = hi32 = 0u;
        sMaskLo = lo32;
        sMaskHi = hi32;
        sFirstData = firstData;
        sFirstVertex = firstVertex;
        sOk = ok && count != 0u ? 1u : 0u;
        sUsedPoints = usedPoints;
        Words(P.nodes).w[node * 3u] = kLeafFlag | (sOk != 0u ? indirection : 0u);
        Words(P.nodes).w[node * 3u + 1u] = lo32;
        Words(P.nodes).w[node * 3u + 2u] = hi32;
        if (sOk != 0u) {
            Words(P.leafIndirections).w[indirection * 2u] = firstData;
            Words(P.leafIndirections).w[indirection * 2u + 1u] = firstVertex;
            atomicAdd(Words(P.entryVoxels).w[entry - uint(P.firstEntry)], count);
        }
    }
    barrier();
    if (sOk == 0u) return;
    if (t < 64u && hasChild(sMaskLo, sMaskHi, int(t))) {
        const uvec3 v = uvec3(t & 3u, (t >> 2) & 3u, t >> 4);
        uint packed[2] = uint[2](0u, 0u);
        for (uint q = 0u; q < 8u; ++q) {
            const uint corner = usedRank(latticeIndex(v.x + (q & 1u), v.y + ((q >> 1) & 1u), v.z + (q >> 2)));
            packed[q >> 2] |= corner << (8u * (q & 3u));
        }
        const uint d = sFirstData + childRank(sMaskLo, sMaskHi, int(t));
        Words(P.leafData).w[d * 2u] = packed[0];
        Words(P.leafData).w[d * 2u + 1u] = packed[1];
    }
    // The used points' vertices, one thread each in lattice order (their
    // ranks): the exact gradients run on the first warps only, not on a
    // few lanes of every warp.
    if (t < sUsedPoints) {
        const uint point = usedPoint(t);
        uint feature;
        const vec4 dual =
            evaluateTileTapeGradient(tape, latticeMm(lo + uvec3(point % 5u, (point / 5u) % 5u, point / 25u)), feature);
        vec3 n = dual.yzw;
        const float len = length(n);
        n = len > 0.0 && !isinf(len) && !isnan(len) ? n / len : vec3(0.0, 0.0, 1.0);
        const uint vtx = sFirstVertex + t;
        Words(P.vertices).w[vtx * 2u] = encodeNormal(n);
        // The stored distance is the value whose sign populated the voxel.
        Words(P.vertices).w[vtx * 2u + 1u] = encodeDistanceFeature(sValue[point], voxel, feature);
    }
}

// Finish pass: one thread per entry: its tile's word.
void finishPass()
{
    const uint k = gl_GlobalInvocationID.x; // this build's k-th entry
    if (k >= P.limits.y) return;
    const uint entry = uint(P.firstEntry) + k;
    const uint tile = Words(P.entryTiles).w[k];
    if (Words(P.entryVoxels).w[k] != 0u) {
        Words(P.tiles).w[tile] = entry;
        return;
    }
    // Ambiguous to intervals but nothing populated: which side is it on?
    const uint tape = Words(P.entries).w[entry * 8u + 5u];
    const float c = 0.5 * P.sizes.y;
    Words(P.tiles).w[tile] = evaluateTileTape(tape, vec3(c)) < 0.0 ? kFullTile : kEmptyTile;
}
#endif

void main()
{
    P = ParamsRef(pc.params).p;
#ifndef KERF_VOXELIZE_INNER
    if (pc.pass == KERF_PASS_FINISH) {
        finishPass();
        return;
    }
#endif
    const uint job = groupIndex();
    const uint count = Words(P.counters).w[KERF_COUNT_JOBS + pc.list];
    if (job >= min(count, jobCapacity(pc.list))) return; // uniform over the group
#ifdef KERF_VOXELIZE_INNER
    innerPass(job);
#else
    leafPass(job);
#endif
}

// The voxel format's words in GLSL (docs/voxel-format.md; C++:
// voxelizer/include/kerf/voxelizer/VoxelFormat.hpp and VoxelFormat.cpp):
// the tile buffer's markers, the node's leaf flag, child indices and ranks
// in a 64-bit mask split in two words, and the compact vertex (octahedral
// normal, snorm16 distance with the deciding feature), decoded by the
// tracer and encoded by the GPU voxelizer bit for bit as the C++ does.
#ifndef KERF_VOXEL_FORMAT_GLSL
#define KERF_VOXEL_FORMAT_GLSL

const uint kEmptyTile = 0xFFFFFFFFu;
const uint kFullTile = 0xFFFFFFFEu;
const uint kLeafFlag = 0x80000000u;
const float kDistanceRange = 2.0;

int childIndex(int x, int y, int z) { return x | (y << 2) | (z << 4); }

bool hasChild(uint maskLo, uint maskHi, int c)
{
    return c < 32 ? ((maskLo >> c) & 1u) != 0u : ((maskHi >> (c - 32)) & 1u) != 0u;
}

uint childRank(uint maskLo, uint maskHi, int c)
{
    if (c < 32) return uint(bitCount(maskLo & ((1u << c) - 1u)));
    const uint below = c == 32 ? 0u : maskHi & ((1u << (c - 32)) - 1u);
    return uint(bitCount(maskLo) + bitCount(below));
}

float signNotZero(float v) { return v < 0.0 ? -1.0 : 1.0; }

float decodeDistance(uint packed, float voxelMm)
{
    const int s = int(packed << 16) >> 16;
    return max(float(s) / 32767.0, -1.0) * kDistanceRange * voxelMm;
}

vec3 decodeNormal(uint packed)
{
    const float u = max(float(int(packed << 16) >> 16) / 32767.0, -1.0);
    const float v = max(float(int(packed) >> 16) / 32767.0, -1.0);
    vec3 n = vec3(u, v, 1.0 - abs(u) - abs(v));
    if (n.z < 0.0) {
        const float pu = n.x, pv = n.y;
        n.x = (1.0 - abs(pv)) * signNotZero(pu);
        n.y = (1.0 - abs(pu)) * signNotZero(pv);
    }
    return normalize(n);
}

// Round half away from zero, as VoxelFormat.cpp's toSnorm16.
uint toSnorm16(float v)
{
    const float scaled = clamp(v, -1.0, 1.0) * 32767.0;
    return uint(int(scaled + (scaled < 0.0 ? -0.5 : 0.5))) & 0xFFFFu;
}

uint encodeNormal(vec3 n)
{
    const float l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if (!(l1 > 0.0) || isinf(l1) || isnan(l1)) return 0u; // no gradient: decodes to +z
    float u = n.x / l1, v = n.y / l1;
    if (n.z < 0.0) {
        const float pu = u, pv = v;
        u = (1.0 - abs(pv)) * signNotZero(pu);
        v = (1.0 - abs(pu)) * signNotZero(pv);
    }
    return toSnorm16(u) | (toSnorm16(v) << 16);
}

// A negative distance never encodes to 0: the sign that populated the voxel is kept.
uint encodeDistanceFeature(float distance, float voxelMm, uint feature)
{
    const bool finite = !isinf(distance) && !isnan(distance);
    const float scaled = finite ? distance / (kDistanceRange * voxelMm) : (distance > 0.0 ? 1.0 : -1.0);
    uint bits = toSnorm16(scaled);
    if (scaled < 0.0 && bits == 0u) bits = 0xFFFFu;
    return bits | (min(feature, 0xFFFFu) << 16);
}

#endif

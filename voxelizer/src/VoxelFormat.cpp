#include "kerf/voxelizer/VoxelFormat.hpp"

#include <algorithm>

namespace kerf::voxel {

namespace {
std::uint32_t toSnorm16(float v)
{
    const float c = std::clamp(v, -1.0f, 1.0f);
    // Round half away from zero without a libm call (hot: every stored vertex).
    const float scaled = c * 32767.0f;
    const auto rounded = static_cast<std::int32_t>(scaled + (scaled < 0.0f ? -0.5f : 0.5f));
    return static_cast<std::uint32_t>(rounded) & 0xFFFF;
}
// As toSnorm16, but a negative value never rounds to zero: the sign of a
// stored distance is what decides inside and outside, and a corner a hair
// inside the surface must read back inside.
std::uint32_t toSnorm16KeepingSign(float v)
{
    std::uint32_t bits = toSnorm16(v);
    if (v < 0.0f && (bits & 0xFFFF) == 0) bits = 0xFFFF; // -1 quantum
    return bits;
}
float fromSnorm16(std::uint32_t bits)
{
    const auto s = static_cast<std::int16_t>(static_cast<std::uint16_t>(bits & 0xFFFF));
    return std::max(float(s) / 32767.0f, -1.0f);
}
float signNotZero(float v) { return v < 0.0f ? -1.0f : 1.0f; }
} // namespace

std::uint32_t encodeNormal(const glm::vec3& n)
{
    // Octahedral mapping (Cigolle et al. 2014): the unit sphere onto a square.
    const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
    if (!(l1 > 0.0f) || !std::isfinite(l1)) return 0; // no gradient (a crease point): decodes to +z
    float u = n.x / l1, v = n.y / l1;
    if (n.z < 0.0f) {
        const float pu = u, pv = v;
        u = (1.0f - std::fabs(pv)) * signNotZero(pu);
        v = (1.0f - std::fabs(pu)) * signNotZero(pv);
    }
    return toSnorm16(u) | toSnorm16(v) << 16;
}

glm::vec3 decodeNormal(std::uint32_t packed)
{
    const float u = fromSnorm16(packed), v = fromSnorm16(packed >> 16);
    glm::vec3 n(u, v, 1.0f - std::fabs(u) - std::fabs(v));
    if (n.z < 0.0f) {
        const float pu = n.x, pv = n.y;
        n.x = (1.0f - std::fabs(pv)) * signNotZero(pu);
        n.y = (1.0f - std::fabs(pu)) * signNotZero(pv);
    }
    const float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    return n / len;
}

std::uint32_t encodeDistanceFeature(float distance, float voxel, std::uint32_t feature)
{
    const float scaled = std::isfinite(distance) ? distance / (kDistanceRange * voxel) : (distance > 0 ? 1.0f : -1.0f);
    return toSnorm16KeepingSign(scaled) | std::min<std::uint32_t>(feature, 0xFFFFu) << 16;
}

float decodeDistance(std::uint32_t packed, float voxel) { return fromSnorm16(packed) * kDistanceRange * voxel; }

std::uint32_t decodeFeature(std::uint32_t packed) { return packed >> 16; }

} // namespace kerf::voxel

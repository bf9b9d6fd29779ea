#pragma once
// The GPU-ready layout of voxelized parts, identical on CPU and GPU
// (docs/voxel-format.md has the byte-level description). Every record is made
// of 32-bit words so that GLSL std430 arrays read them unchanged.
//
// A tile holds one contree ("64-tree"): every node splits its cube 4 x 4 x 4,
// with a 64-bit mask of populated children. Children of a node are stored
// contiguously in mask order; a leaf node's children are voxels, whose data
// sit behind a leaf indirection.

#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstdint>

namespace kerf::voxel {

/// Tile buffer values that are not offsets.
inline constexpr std::uint32_t kEmptyTile = 0xFFFFFFFFu; // no surface: nothing inside
inline constexpr std::uint32_t kFullTile = 0xFFFFFFFEu;  // entirely inside the solid

/// Node header: bit 31 set for a leaf node; bits 0..30 the pointer (first
/// child node for inner nodes, the leaf indirection for leaves), relative to
/// the tile's first node / first leaf indirection.
inline constexpr std::uint32_t kLeafFlag = 0x80000000u;

/// Deepest contree the format allows: positions inside a tile are float
/// coordinates in [0, 1) whose 23-bit mantissa holds 11 base-4 digits.
inline constexpr int kMaxLevels = 11;

struct Node {
    std::uint32_t header = 0;
    std::uint32_t maskLo = 0; // children 0..31
    std::uint32_t maskHi = 0; // children 32..63

    std::uint64_t mask() const { return std::uint64_t(maskHi) << 32 | maskLo; }
    bool isLeaf() const { return header & kLeafFlag; }
    std::uint32_t pointer() const { return header & ~kLeafFlag; }
};
static_assert(sizeof(Node) == 12);

struct LeafIndirection {
    std::uint32_t leafData = 0; // first LeafData of this leaf (tile-relative)
    std::uint32_t vertex = 0;   // first vertex of this leaf (tile-relative)
};
static_assert(sizeof(LeafIndirection) == 8);

/// The eight corners of one populated voxel: indices into the leaf's
/// vertices (< 125), corner c = x + 2y + 4z.
struct LeafData {
    std::array<std::uint8_t, 8> corner{};
};
static_assert(sizeof(LeafData) == 8);

/// One lattice point of a leaf: the field's unit normal (octahedral, two
/// snorm16) and its distance (snorm16, in units of two voxel edges, so a
/// populated voxel's corners, never farther than a diagonal from the
/// surface, use the whole range) with the deciding feature (u16).
struct Vertex {
    std::uint32_t normal = 0;
    std::uint32_t distanceFeature = 0;
};
static_assert(sizeof(Vertex) == 8);

/// Children index of cell (x, y, z) in a node, each in 0..3.
constexpr int childIndex(int x, int y, int z) { return x | y << 2 | z << 4; }

/// Lattice index of corner point (x, y, z) of a leaf, each in 0..4.
constexpr int latticeIndex(int x, int y, int z) { return x + 5 * (y + 5 * z); }

/// Distances are stored in units of this many voxel edges (range +-).
inline constexpr float kDistanceRange = 2.0f;

std::uint32_t encodeNormal(const glm::vec3& n);
glm::vec3 decodeNormal(std::uint32_t packed);

/// `distance` in mm, `voxel` the voxel edge in mm; clamps to the range.
std::uint32_t encodeDistanceFeature(float distance, float voxel, std::uint32_t feature);
float decodeDistance(std::uint32_t packed, float voxel);
std::uint32_t decodeFeature(std::uint32_t packed);

} // namespace kerf::voxel

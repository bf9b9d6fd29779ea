#include "kerf/voxelizer/VoxelQuery.hpp"

#include <bit>

namespace kerf {

namespace {
// Rank of bit `c` among the set bits of `mask`: the child's position in the
// contiguous children array.
std::uint32_t rankOf(std::uint64_t mask, int c)
{
    return std::uint32_t(std::popcount(mask & ((std::uint64_t(1) << c) - 1)));
}

int childAt(const glm::ivec3& voxel, int levels, int level)
{
    const int shift = 2 * (levels - 1 - level);
    return voxel::childIndex((voxel.x >> shift) & 3, (voxel.y >> shift) & 3, (voxel.z >> shift) & 3);
}
} // namespace

int populatedDepth(const TileData& tile, const glm::ivec3& voxel)
{
    if (tile.state != TileState::Surface || tile.nodes.empty()) return 0;
    std::uint32_t node = 0;
    for (int level = 0; level < tile.levels; ++level) {
        const voxel::Node& n = tile.nodes[node];
        const int c = childAt(voxel, tile.levels, level);
        if (!(n.mask() >> c & 1)) return level;
        if (n.isLeaf()) return tile.levels;
        node = n.pointer() + rankOf(n.mask(), c);
    }
    return tile.levels;
}

namespace {
VoxelCorners decodeCorners(const TileData& tile, const voxel::LeafIndirection& li, std::uint32_t rank, float voxelSize)
{
    const voxel::LeafData& ld = tile.leafData[li.leafData + rank];
    VoxelCorners out;
    for (int q = 0; q < 8; ++q) {
        const voxel::Vertex& v = tile.vertices[li.vertex + ld.corner[std::size_t(q)]];
        out.distance[q] = voxel::decodeDistance(v.distanceFeature, voxelSize);
        out.normal[q] = voxel::decodeNormal(v.normal);
        out.feature[q] = voxel::decodeFeature(v.distanceFeature);
    }
    return out;
}

void visitNode(const TileData& tile, std::uint32_t node, const glm::ivec3& origin, int level, float voxelSize,
               const std::function<void(const glm::ivec3&, const VoxelCorners&)>& visit)
{
    const voxel::Node& n = tile.nodes[node];
    const std::uint64_t mask = n.mask();
    std::uint32_t rank = 0;
    for (int c = 0; c < 64; ++c) {
        if (!(mask >> c & 1)) continue;
        const glm::ivec3 cell = origin * 4 + glm::ivec3(c & 3, (c >> 2) & 3, c >> 4);
        if (n.isLeaf())
            visit(cell, decodeCorners(tile, tile.leafIndirections[n.pointer()], rank, voxelSize));
        else
            visitNode(tile, n.pointer() + rank, cell, level + 1, voxelSize, visit);
        ++rank;
    }
}
} // namespace

void forEachVoxel(const TileData& tile, float voxelSize,
                  const std::function<void(const glm::ivec3& voxel, const VoxelCorners& corners)>& visit)
{
    if (tile.state != TileState::Surface || tile.nodes.empty()) return;
    visitNode(tile, 0, glm::ivec3(0), 0, voxelSize, visit);
}

std::optional<VoxelCorners> findVoxel(const TileData& tile, const glm::ivec3& voxel, float voxelSize)
{
    if (tile.state != TileState::Surface || tile.nodes.empty()) return std::nullopt;
    std::uint32_t node = 0;
    for (int level = 0; level < tile.levels; ++level) {
        const voxel::Node& n = tile.nodes[node];
        const int c = childAt(voxel, tile.levels, level);
        if (!(n.mask() >> c & 1)) return std::nullopt;
        if (n.isLeaf()) return decodeCorners(tile, tile.leafIndirections[n.pointer()], rankOf(n.mask(), c), voxelSize);
        node = n.pointer() + rankOf(n.mask(), c);
    }
    return std::nullopt;
}

} // namespace kerf

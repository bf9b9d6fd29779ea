#include "Seeds.hpp"

#include <bit>

namespace kerf::mesher {

namespace {
void visitNode(const TileData& tile, std::uint32_t node, const glm::ivec3& origin,
               const std::function<void(const glm::ivec3&)>& visit)
{
    const voxel::Node& n = tile.nodes[node];
    std::uint64_t mask = n.mask();
    std::uint32_t rank = 0;
    while (mask) {
        const int c = std::countr_zero(mask);
        mask &= mask - 1;
        const glm::ivec3 cell = origin * 4 + glm::ivec3(c & 3, (c >> 2) & 3, c >> 4);
        if (n.isLeaf())
            visit(cell);
        else
            visitNode(tile, n.pointer() + rank, cell, visit); // children are contiguous, in mask order
        ++rank;
    }
}
} // namespace

void forEachSeed(const TileData& tile, const std::function<void(const glm::ivec3&)>& visit)
{
    if (tile.state != TileState::Surface || tile.nodes.empty()) return;
    visitNode(tile, 0, glm::ivec3(0), visit);
}

} // namespace kerf::mesher

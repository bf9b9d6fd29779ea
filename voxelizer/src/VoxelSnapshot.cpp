#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <algorithm>

namespace kerf {

std::size_t VoxelSnapshot::bytes() const
{
    std::size_t b = tiles.size() * sizeof(std::uint32_t);
    for (const auto& t : tiles)
        if (t && t->state == TileState::Surface) b += sizeof(TileEntry) + t->bytes();
    return b;
}

std::size_t VoxelSnapshot::populatedVoxels() const
{
    std::size_t n = 0;
    for (const auto& t : tiles)
        if (t) n += t->populatedVoxels();
    return n;
}

int VoxelSnapshot::shallowestLevels() const
{
    int lv = layout.levels;
    for (const auto& t : tiles)
        if (t && t->state == TileState::Surface) lv = std::min(lv, t->levels);
    return lv;
}

std::size_t FlatVoxelBuffers::bytes() const
{
    return tiles.size() * sizeof(std::uint32_t) + entries.size() * sizeof(TileEntry) +
           nodes.size() * sizeof(voxel::Node) + leafIndirections.size() * sizeof(voxel::LeafIndirection) +
           leafData.size() * sizeof(voxel::LeafData) + vertices.size() * sizeof(voxel::Vertex) +
           tapes.size() * sizeof(std::uint32_t);
}

FlatVoxelBuffers FlatVoxelBuffers::flatten(const VoxelSnapshot& snapshot)
{
    FlatVoxelBuffers f;
    f.layout = snapshot.layout;
    f.tiles.assign(snapshot.tiles.size(), voxel::kEmptyTile);
    for (std::size_t i = 0; i < snapshot.tiles.size(); ++i) {
        const auto& t = snapshot.tiles[i];
        if (!t || t->state == TileState::Empty) continue;
        if (t->state == TileState::Full) {
            f.tiles[i] = voxel::kFullTile;
            continue;
        }
        f.tiles[i] = std::uint32_t(f.entries.size());
        f.entries.push_back({std::uint32_t(f.nodes.size()), std::uint32_t(f.leafIndirections.size()),
                             std::uint32_t(f.leafData.size()), std::uint32_t(f.vertices.size()),
                             std::uint32_t(t->levels),
                             t->tape.empty() ? voxel::kNoTape : std::uint32_t(f.tapes.size()),
                             {0, 0}});
        f.nodes.insert(f.nodes.end(), t->nodes.begin(), t->nodes.end());
        f.leafIndirections.insert(f.leafIndirections.end(), t->leafIndirections.begin(), t->leafIndirections.end());
        f.leafData.insert(f.leafData.end(), t->leafData.begin(), t->leafData.end());
        f.vertices.insert(f.vertices.end(), t->vertices.begin(), t->vertices.end());
        f.tapes.insert(f.tapes.end(), t->tape.begin(), t->tape.end());
    }
    return f;
}

} // namespace kerf

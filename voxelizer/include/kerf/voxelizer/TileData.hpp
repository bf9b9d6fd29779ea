#pragma once
// One tile's voxel data in the GPU layout, with offsets relative to the
// tile's own arrays. Immutable once built; shared between snapshots.

#include "kerf/voxelizer/VoxelFormat.hpp"

#include <cstdint>
#include <vector>

namespace kerf {

enum class TileState : std::uint8_t { Empty, Full, Surface };

struct TileData {
    TileState state = TileState::Empty;
    int levels = 0; // contree depth this tile was built at
    /// Empty or full at this depth only: the intervals could not rule a
    /// surface out, but no voxel had corners on both sides of it. Material
    /// thinner than these voxels (a 6 mm drawer bottom between the 8 mm
    /// voxels of a coarse pass) may lie in it: a deeper build may find it.
    bool unresolved = false;
    /// Whether a deeper build might give another answer.
    bool mayRefine() const { return state == TileState::Surface || unresolved; }
    std::vector<voxel::Node> nodes; // nodes[0] is the root
    std::vector<voxel::LeafIndirection> leafIndirections;
    std::vector<voxel::LeafData> leafData; // one per populated voxel
    std::vector<voxel::Vertex> vertices;
    /// The tile's exact tape in the GPU form (TileTape.hpp), for the hybrid
    /// refinement; empty when the tile has none.
    std::vector<std::uint32_t> tape;

    std::size_t populatedVoxels() const { return leafData.size(); }
    std::size_t bytes() const
    {
        return nodes.size() * sizeof(voxel::Node) + leafIndirections.size() * sizeof(voxel::LeafIndirection) +
               leafData.size() * sizeof(voxel::LeafData) + vertices.size() * sizeof(voxel::Vertex) +
               tape.size() * sizeof(std::uint32_t);
    }
};

} // namespace kerf

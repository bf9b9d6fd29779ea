#pragma once
// A published, consistent voxelization: every tile belongs to the same
// document (some possibly at a coarser depth while refinement runs).
// Immutable; readers hold it by shared_ptr as long as they need it.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/TileData.hpp"
#include "kerf/voxelizer/TileTape.hpp"

#include <memory>
#include <vector>

namespace kerf {

struct VoxelSnapshot {
    std::uint64_t version = 0;          // increases with every publication
    std::uint64_t documentRevision = 0; // the request this snapshot answers
    bool complete = false;              // every tile at the depth planned for it
    std::size_t coarsenedForBudget = 0; // tiles shallower than the view needs, to fit the memory budget
    std::size_t outsideView = 0;        // surface tiles kept coarse because the camera does not see them
    std::size_t hiddenTiles = 0;        // surface tiles kept coarse because the part hides them (OcclusionMap)
    GridLayout layout;
    std::vector<std::shared_ptr<const TileData>> tiles; // layout.tileCount() entries, null = empty
    std::shared_ptr<const std::vector<Feature>> features;

    std::size_t bytes() const;
    std::size_t populatedVoxels() const;
    int shallowestLevels() const; // of surface tiles
};

/// Concatenated GPU buffers of a snapshot: the tile buffer maps each tile to
/// a TileEntry (or kEmptyTile / kFullTile); the entry's offsets turn the
/// tile-relative offsets into absolute ones.
struct TileEntry {
    std::uint32_t node = 0;
    std::uint32_t leafIndirection = 0;
    std::uint32_t leafData = 0;
    std::uint32_t vertex = 0;
    std::uint32_t levels = 0;
    std::uint32_t tape = voxel::kNoTape; // first word of the tile's exact tape in `tapes`
    std::uint32_t reserved[2] = {0, 0};
};
static_assert(sizeof(TileEntry) == 32);

struct FlatVoxelBuffers {
    GridLayout layout;
    std::vector<std::uint32_t> tiles;
    std::vector<TileEntry> entries;
    std::vector<voxel::Node> nodes;
    std::vector<voxel::LeafIndirection> leafIndirections;
    std::vector<voxel::LeafData> leafData;
    std::vector<voxel::Vertex> vertices;
    std::vector<std::uint32_t> tapes; // the tiles' exact tapes (TileTape.hpp), concatenated

    std::size_t bytes() const;
    static FlatVoxelBuffers flatten(const VoxelSnapshot& snapshot);
};

} // namespace kerf

#pragma once
// Synchronous voxelization of a whole part, in parallel over tiles with
// oneTBB (tests, benchmarks, `kerf check`, export). The interactive path is
// the background Voxelizer.

#include "kerf/voxelizer/VoxelSnapshot.hpp"

namespace kerf {

struct VoxelizeOptions {
    int levels = -1;  // contree depth; -1: the layout's
    int threads = 0;  // 0: every core
};

/// Builds every tile of `layout` from `tape` (world coordinates).
VoxelSnapshot voxelize(const Tape& tape, const GridLayout& layout, const VoxelizeOptions& options = {});

} // namespace kerf

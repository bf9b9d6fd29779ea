#pragma once
// Synchronous voxelization of a whole part, in parallel over tiles with
// oneTBB (tests, benchmarks, `kerf check`, export). The interactive path is
// the background Voxelizer.

#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <optional>

namespace kerf {

struct VoxelizeOptions {
    int levels = -1;  // contree depth; -1: the layout's
    int threads = 0;  // 0: every core
};

/// Builds every tile of `layout` from `tape` (world coordinates).
VoxelSnapshot voxelize(const Tape& tape, const GridLayout& layout, const VoxelizeOptions& options = {});

struct VoxelEstimate {
    double populatedVoxels = 0.0; // at the layout's full depth
    double bytes = 0.0;
    int measuredLevels = 0;       // the depth actually voxelized to estimate
    bool exact = false;           // measuredLevels == layout.levels
    std::optional<VoxelSnapshot> snapshot; // the full voxelization, when exact
};

/// Estimates the cost of voxelize() without risking it: voxelizes at 1, 2,
/// ... levels while fewer than `probeVoxels` voxels are populated, then
/// extrapolates (each level down has about 16 times the surface voxels, and
/// bytes per voxel stay put).
VoxelEstimate estimateVoxels(const Tape& tape, const GridLayout& layout, double probeVoxels = 2e6);

} // namespace kerf

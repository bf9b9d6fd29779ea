#pragma once
// Synchronous voxelization of a whole part, in parallel over tiles with
// oneTBB (tests, benchmarks, `kerf check`, export). The interactive path is
// the background Voxelizer.

#include "kerf/document/Progress.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>

namespace kerf {

struct VoxelizeOptions {
    int levels = -1;  // contree depth; -1: the layout's
    int threads = 0;  // 0: every core
    /// When set, the CPU time the workers spent building tiles is added
    /// here (ns, each thread's own clock): what the work costs whatever
    /// else the machine runs.
    std::atomic<std::int64_t>* cpuNanos = nullptr;
};

/// Builds every tile of `layout` from `tape` (world coordinates), reporting
/// the fraction of tiles built to `work`. Stops early when `work` is
/// cancelled (checked between and inside tiles): the snapshot is then not
/// complete (whole tiles only, some missing).
VoxelSnapshot voxelize(const Tape& tape, const GridLayout& layout, const VoxelizeOptions& options = {},
                       const Progress& work = {});

struct VoxelEstimate {
    double populatedVoxels = 0.0; // at the layout's full depth
    double bytes = 0.0;
    int measuredLevels = 0;       // the depth actually voxelized to estimate
    bool exact = false;           // measuredLevels == layout.levels
    double seconds = 0.0;         // to build it all with every core of an idle machine (measured when exact)
    double probeSeconds = 0.0;    // what the estimate itself took (wall clock)
    std::optional<VoxelSnapshot> snapshot; // the full voxelization, when exact
};

/// Estimates the cost of voxelize() without risking it: voxelizes at 1, 2,
/// ... levels while the next level would populate fewer than `probeVoxels`
/// voxels and keep the probing under about `probeSeconds`, then extrapolates
/// (each level down has about 16 times the surface voxels, and bytes per
/// voxel stay put).
VoxelEstimate estimateVoxels(const Tape& tape, const GridLayout& layout, double probeVoxels = 2e6,
                             double probeSeconds = 2.0);

} // namespace kerf

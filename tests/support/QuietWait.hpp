#pragma once
// Waiting for the background voxelizer in tests.

#include "kerf/voxelizer/Voxelizer.hpp"

#include <chrono>
#include <cstdint>
#include <thread>

namespace kerf {

/// Waits (up to two minutes) until the voxelizer has finished a revision at
/// least `revision`, not cancelled, and is idle, by its stats: for requests
/// that need not publish (a new view, a new picture).
inline bool QuietWait(const Voxelizer& vox, std::uint64_t revision)
{
    for (int i = 0; i < 120000; ++i) {
        const auto s = vox.lastStats();
        if (s.revision >= revision && !s.cancelled && !vox.progress().busy) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

} // namespace kerf

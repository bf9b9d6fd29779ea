#pragma once
// The oneTBB arena every parallel part of Kerf runs its work in (voxelizer,
// mesher, tracers, accuracy): `threads` workers as the caller's options say,
// or one per core for 0. One place, so that "threads = 0 means every core"
// cannot mean something else in one module.

#include <tbb/task_arena.h>

namespace kerf {

inline tbb::task_arena workerArena(int threads)
{
    return tbb::task_arena(threads > 0 ? threads : tbb::task_arena::automatic);
}

} // namespace kerf

#pragma once
// Builds one tile's contree: interval tests prune empty and full space and
// simplify the tape at every level, so deep nodes evaluate short tapes; at a
// leaf node the 5 x 5 x 5 shared corner points are sampled in one batched
// call, voxels whose corners change sign are populated, and their corners
// keep distance, normal and deciding feature (each shared corner once).

#include "kerf/document/Progress.hpp"
#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/Tape.hpp"
#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/TileData.hpp"

#include <glm/vec3.hpp>

#include <functional>
#include <optional>

namespace kerf {

/// Interval boxes (a tile's, a node's children's) grow by this fraction of
/// the tile edge on every side before they are tested: eight float ulps of
/// the largest tile-relative coordinate, more than the rounding of a float
/// sample point and of its float evaluation (the field is 1-Lipschitz). The
/// interval is the double field's over the box; the leaves sample the float
/// field at float-rounded points, and a box whose face lies on the surface
/// was proven full by a 1e-13 while its corners read 0, outside: a hole in
/// a face on a lattice plane (the turned leg's pommel top at 1.8 mm). The
/// GPU voxelizer grows its boxes by the same hair.
inline constexpr double kIntervalBoxHair = 1.0 / 1048576.0;

/// A voxel of a leaf node whose corners agree in sign although one of them
/// lies within the voxel's half-diagonal of the surface: the field is
/// 1-Lipschitz, so only such a voxel can hide material or a gap thinner than
/// itself between its corners (the export mesher looks inside).
struct QuietVoxel {
    glm::ivec3 voxel; // tile-local voxel coordinates
    bool inside;      // the side of its corners
};

/// Per-thread scratch memory for building tiles (reused across tiles).
struct TileBuildScratch {
    IntervalEvaluator intervals;
    PointEvaluator<float> points;
    GradientEvaluator<float> gradients;
    std::vector<Tape> levelTapes; // the simplified tape of the node being built at each level
    /// When set, buildTile appends the tile's quiet voxels here.
    std::vector<QuietVoxel>* quietVoxels = nullptr;
    /// When set (and no quiet voxels are asked for), the subtrees of a
    /// tile's 64 children are built in parallel, each thread with the
    /// scratch this returns for it (a oneTBB enumerable_thread_specific's
    /// local()): a part with a few heavy tiles then uses every core, not one
    /// per tile. The calling thread waits in an isolated arena, so it never
    /// picks up another tile that would reuse its own scratch meanwhile.
    std::function<TileBuildScratch&()> helper;
};

/// Builds tile `tile` of `layout` from `tape` (a tape in world coordinates,
/// origin at zero) with a contree `levels` deep (1..voxel::kMaxLevels).
/// Returns nothing when `work` is cancelled (polled between nodes): never half a tile.
std::optional<TileData> buildTile(const Tape& tape, const GridLayout& layout, const glm::ivec3& tile, int levels,
                                  TileBuildScratch& scratch, const Progress& work = {});

} // namespace kerf

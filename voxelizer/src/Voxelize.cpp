#include "kerf/voxelizer/Voxelize.hpp"

#include "kerf/voxelizer/BlockTapes.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"

#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace kerf {

VoxelSnapshot voxelize(const Tape& tape, const GridLayout& layout, const VoxelizeOptions& options)
{
    VoxelSnapshot snap;
    snap.layout = layout;
    snap.features = tape.sharedFeatures();
    snap.complete = true;
    snap.tiles.resize(std::size_t(layout.tileCount()));
    const int levels = options.levels > 0 ? options.levels : layout.levels;
    tbb::enumerable_thread_specific<TileBuildScratch> scratch;
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    const BlockTapes blocks(tape, layout);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<long>(0, layout.tileCount(), 1), [&](const tbb::blocked_range<long>& r) {
            auto& s = scratch.local();
            for (long i = r.begin(); i != r.end(); ++i) {
                const glm::ivec3 t = layout.tileCoord(i);
                auto tile = buildTile(blocks.forTile(t), layout, t, levels, s);
                if (tile && tile->state != TileState::Empty)
                    snap.tiles[std::size_t(i)] = std::make_shared<const TileData>(std::move(*tile));
            }
        });
    });
    return snap;
}

VoxelEstimate estimateVoxels(const Tape& tape, const GridLayout& layout, double probeVoxels)
{
    VoxelEstimate e;
    if (layout.empty()) {
        e.exact = true;
        return e;
    }
    for (int levels = 1; levels <= layout.levels; ++levels) {
        VoxelSnapshot s = voxelize(tape, layout, {.levels = levels, .threads = 0});
        const double voxels = double(s.populatedVoxels());
        const double scale = std::pow(16.0, layout.levels - levels);
        e.populatedVoxels = voxels * scale;
        // The surface grows 16-fold per level; the tiles' exact tapes do not.
        std::size_t tapeBytes = 0;
        for (const auto& t : s.tiles)
            if (t) tapeBytes += t->tape.size() * sizeof(std::uint32_t);
        e.bytes = double(s.bytes() - tapeBytes) * scale + double(tapeBytes);
        e.measuredLevels = levels;
        e.exact = levels == layout.levels;
        if (e.exact) e.snapshot = std::move(s);
        if (voxels * 16.0 > probeVoxels) break; // the next level would cost too much to probe
    }
    return e;
}

} // namespace kerf

#include "kerf/voxelizer/Voxelize.hpp"

#include "kerf/voxelizer/BlockTapes.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"
#include "kerf/voxelizer/WorkerArena.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace kerf {

namespace {

// Adds the calling thread's CPU time between construction and destruction
// to a total (when there is one).
class ThreadCpuClock {
public:
    explicit ThreadCpuClock(std::atomic<std::int64_t>* total) : total_(total)
    {
        if (total_) start_ = now();
    }
    ~ThreadCpuClock()
    {
        if (total_) *total_ += now() - start_;
    }
    ThreadCpuClock(const ThreadCpuClock&) = delete;
    ThreadCpuClock& operator=(const ThreadCpuClock&) = delete;

private:
    static std::int64_t now()
    {
        timespec t{};
        ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
        return std::int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
    }
    std::atomic<std::int64_t>* total_;
    std::int64_t start_ = 0;
};

} // namespace

VoxelSnapshot voxelize(const Tape& tape, const GridLayout& layout, const VoxelizeOptions& options,
                       const Progress& work)
{
    VoxelSnapshot snap;
    snap.layout = layout;
    snap.features = tape.sharedFeatures();
    snap.complete = true;
    snap.tiles.resize(std::size_t(layout.tileCount()));
    const int levels = options.levels > 0 ? options.levels : layout.levels;
    tbb::enumerable_thread_specific<TileBuildScratch> scratch;
    tbb::task_arena arena = workerArena(options.threads);
    const BlockTapes blocks(tape, layout);
    std::atomic<long> built{0};
    std::atomic<bool> stopped{false};
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<long>(0, layout.tileCount(), 1), [&](const tbb::blocked_range<long>& r) {
            const ThreadCpuClock cpu(options.cpuNanos);
            auto& s = scratch.local();
            s.helper = [&scratch]() -> TileBuildScratch& { return scratch.local(); };
            for (long i = r.begin(); i != r.end(); ++i) {
                if (stopped) return;
                const glm::ivec3 t = layout.tileCoord(i);
                if (work.cancelled()) {
                    stopped = true;
                    return;
                }
                auto tile = buildTile(blocks.forTile(t), layout, t, levels, s, work);
                if (!tile) {
                    stopped = true;
                    return;
                }
                if (tile && tile->state != TileState::Empty)
                    snap.tiles[std::size_t(i)] = std::make_shared<const TileData>(std::move(*tile));
                if (work.reporting()) work.report(double(++built) / double(layout.tileCount()));
            }
        });
    });
    snap.complete = !stopped;
    return snap;
}

VoxelEstimate estimateVoxels(const Tape& tape, const GridLayout& layout, double probeVoxels, double probeSeconds)
{
    VoxelEstimate e;
    if (layout.empty()) {
        e.exact = true;
        return e;
    }
    // Each probe level runs against a deadline: a level that would overrun it
    // is abandoned (the previous one stands), so the estimate takes about
    // probeSeconds at most, whatever the part.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(probeSeconds);
    const Progress pastDeadline = Progress::cancelledWhen([deadline] { return std::chrono::steady_clock::now() > deadline; });
    // The time a level takes is its CPU time spread over the cores, not the
    // wall clock: on a machine busy with other work the wall clock grew
    // fourfold (the table top at 0.1 mm: 13 min estimated idle, 1.5 h beside
    // six busy processes), and a request near the budget was refused or not
    // by the load of the moment.
    const double cores = double(std::max(1, workerArena(0).max_concurrency()));
    for (int levels = 1; levels <= layout.levels; ++levels) {
        const auto start = std::chrono::steady_clock::now();
        std::atomic<std::int64_t> cpuNanos{0};
        VoxelSnapshot s = voxelize(tape, layout, {.levels = levels, .threads = 0, .cpuNanos = &cpuNanos},
                                   e.measuredLevels > 0 ? pastDeadline : Progress{});
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double seconds = 1e-9 * double(cpuNanos.load()) / cores;
        if (!s.complete) {
            // Overran: the time a whole level would take is at least this.
            e.seconds = std::max(e.seconds, seconds * std::pow(16.0, layout.levels - levels));
            e.probeSeconds += wall;
            break;
        }
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
        // The last probe's time per populated voxel, times the voxels of the
        // full depth: the per-tile interval work of a coarse probe counts in,
        // so this errs on the slow side.
        e.seconds = e.exact ? seconds : seconds * scale;
        e.probeSeconds += wall;
        if (e.exact) e.snapshot = std::move(s);
        // The next level has about 16 times the voxels, and takes up to 16
        // times as long: probe it only when both stay within bounds, so the
        // estimate itself always answers in seconds (a part of 100,000
        // small spheres is slow per voxel at coarse levels).
        if (voxels * 16.0 > probeVoxels || e.probeSeconds + 4.0 * wall > probeSeconds) break;
    }
    return e;
}

} // namespace kerf

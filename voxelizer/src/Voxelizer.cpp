#include "kerf/voxelizer/Voxelizer.hpp"

#include "kerf/document/NodeBounds.hpp"
#include "kerf/voxelizer/BlockTapes.hpp"
#include "kerf/voxelizer/DirtyRegion.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <set>

namespace kerf {

namespace {
double millisecondsSince(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}
} // namespace

Voxelizer::Voxelizer(VoxelizerOptions options) : options_(std::move(options))
{
    worker_ = std::thread([this] { run(); });
}

Voxelizer::~Voxelizer()
{
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    changed_.notify_all();
    worker_.join();
}

std::uint64_t Voxelizer::setDocument(const Document& doc)
{
    std::uint64_t revision;
    {
        std::lock_guard lock(mutex_);
        revision = latestRevision_.load() + 1;
        latestRevision_ = revision; // running work sees it and stops
        pending_ = Request{doc, revision, std::chrono::steady_clock::now()};
    }
    changed_.notify_all();
    return revision;
}

void Voxelizer::setFocus(const glm::dvec3& point)
{
    std::lock_guard lock(mutex_);
    focus_ = point;
}

std::shared_ptr<const VoxelSnapshot> Voxelizer::snapshot() const
{
    std::lock_guard lock(mutex_);
    return published_;
}

bool Voxelizer::waitFor(std::uint64_t revision, bool complete, std::chrono::milliseconds timeout) const
{
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] {
        return published_ && published_->documentRevision >= revision && (!complete || published_->complete ||
                                                                            published_->documentRevision > revision);
    });
}

VoxelizerStats Voxelizer::lastStats() const
{
    std::lock_guard lock(mutex_);
    return stats_;
}

VoxelizerProgress Voxelizer::progress() const
{
    std::lock_guard lock(mutex_);
    VoxelizerProgress p = progress_;
    p.tilesBuilt = std::min(tilesBuilt_.load(), p.tilesToBuild);
    return p;
}

void Voxelizer::run()
{
    for (;;) {
        Request request;
        {
            std::unique_lock lock(mutex_);
            changed_.wait(lock, [&] { return stopping_.load() || pending_.has_value(); });
            if (stopping_) return;
            request = std::move(*pending_);
            pending_.reset();
        }
        process(std::move(request));
    }
}

void Voxelizer::publish(std::shared_ptr<VoxelSnapshot> snap)
{
    snap->version = nextVersion_++;
    // The callback runs before waiters wake: whoever waits for a revision
    // finds every consumer already told.
    if (options_.onPublish) options_.onPublish(snap);
    {
        std::lock_guard lock(mutex_);
        published_ = snap;
    }
    changed_.notify_all();
}

void Voxelizer::process(Request request)
{
    const std::uint64_t revision = request.revision;
    const Tape tape = compileTape(request.doc, &features_);
    const double featureSize = options_.featureSize > 0.0 ? options_.featureSize
                                                          : request.doc.settings.featureSize.value_or(
                                                                defaultFeatureSize(tape.bounds()));
    const GridLayout layout = GridLayout::choose(tape.bounds(), featureSize, options_.limits);
    const auto base = snapshot();

    // Which tiles to rebuild: everything when the grid changed; otherwise the
    // tiles still unfinished for the previous version plus those this edit reaches.
    // The unfinished tiles are indices into the grid of the last request; a
    // request cancelled with a grid of its own leaves them meaningless here.
    const bool sameGrid = base && builtDocument_ && base->layout == layout && builtLayout_ == layout;
    std::set<long> dirty;
    if (!sameGrid) {
        // A new grid: every tile of it (the unfinished tiles of the old grid
        // are indices into a grid that is gone).
        for (long i = 0; i < layout.tileCount(); ++i) dirty.insert(i);
    } else {
        dirty.insert(unfinishedTiles_.begin(), unfinishedTiles_.end());
        // Tiles outside unfinishedTiles_ are at full depth: a fine voxel's
        // diagonal (doubled for safety) is as far as a stored sample reaches.
        const double margin = 2.0 * std::sqrt(3.0) * layout.voxelSize;
        const DirtyRegion region = dirtyRegion(*builtDocument_, request.doc, margin);
        if (region.everything) {
            for (long i = 0; i < layout.tileCount(); ++i) dirty.insert(i);
        } else {
            for (const Aabb& box : region.boxes) {
                const Aabb clipped = box.intersected(layout.bounds());
                if (clipped.isEmpty()) continue;
                const glm::ivec3 lo = glm::clamp(glm::ivec3(glm::floor((clipped.min - layout.origin) / layout.tileSize)),
                                                 glm::ivec3(0), layout.dims - 1);
                const glm::ivec3 hi = glm::clamp(glm::ivec3(glm::floor((clipped.max - layout.origin) / layout.tileSize)),
                                                 glm::ivec3(0), layout.dims - 1);
                for (int z = lo.z; z <= hi.z; ++z)
                    for (int y = lo.y; y <= hi.y; ++y)
                        for (int x = lo.x; x <= hi.x; ++x) dirty.insert(layout.tileIndex({x, y, z}));
            }
        }
    }
    builtDocument_ = request.doc;
    builtLayout_ = layout;
    unfinishedTiles_.assign(dirty.begin(), dirty.end());

    // Nearest tiles first.
    glm::dvec3 focus;
    {
        std::lock_guard lock(mutex_);
        focus = focus_;
    }
    std::vector<long> order(dirty.begin(), dirty.end());
    std::sort(order.begin(), order.end(), [&](long a, long b) {
        return glm::length(layout.tileBox(layout.tileCoord(a)).center() - focus) <
               glm::length(layout.tileBox(layout.tileCoord(b)).center() - focus);
    });

    auto start = [&] {
        auto s = std::make_shared<VoxelSnapshot>();
        s->layout = layout;
        s->documentRevision = revision;
        s->features = tape.sharedFeatures();
        if (sameGrid)
            s->tiles = base->tiles;
        else
            s->tiles.assign(std::size_t(layout.tileCount()), nullptr);
        return s;
    };

    VoxelizerStats stats;
    stats.revision = revision;
    stats.tilesInGrid = std::size_t(layout.tileCount());
    stats.dirtyTiles = order.size();
    tbb::task_arena arena(options_.threads > 0 ? options_.threads : tbb::task_arena::automatic);
    tbb::enumerable_thread_specific<TileBuildScratch> scratch;
    const BlockTapes blocks(tape, layout);
    const CancelCheck cancelled = [&] { return stale(revision); };

    auto pass = [&](bool coarse, std::size_t tiles, int levels) {
        std::lock_guard lock(mutex_);
        progress_.revision = revision;
        progress_.busy = tiles > 0;
        progress_.coarsePass = coarse;
        progress_.tilesToBuild = tiles;
        progress_.levels = levels;
        progress_.targetLevels = layout.levels;
        tilesBuilt_ = 0;
    };

    // Builds `tiles` at `levels` into `snap`; false when cancelled.
    auto buildInto = [&](VoxelSnapshot& snap, const std::vector<long>& tiles, int levels) {
        std::vector<std::shared_ptr<const TileData>> built(tiles.size());
        std::atomic<bool> aborted{false};
        arena.execute([&] {
            tbb::parallel_for(std::size_t(0), tiles.size(), [&](std::size_t k) {
                if (aborted.load()) return;
                const glm::ivec3 tc = layout.tileCoord(tiles[k]);
                auto t = buildTile(blocks.forTile(tc), layout, tc, levels, scratch.local(), cancelled);
                if (!t) {
                    aborted = true;
                    return;
                }
                if (t->state != TileState::Empty) built[k] = std::make_shared<const TileData>(std::move(*t));
                ++tilesBuilt_;
            });
        });
        if (aborted || stale(revision)) return false;
        for (std::size_t k = 0; k < tiles.size(); ++k) snap.tiles[std::size_t(tiles[k])] = built[k];
        return true;
    };

    auto finish = [&](bool cancelledNow) {
        stats.cancelled = cancelledNow;
        std::lock_guard lock(mutex_);
        stats_ = stats;
        progress_.busy = false;
    };

    const int coarseLevels = std::max(1, layout.levels - options_.coarseLevelDrop);
    auto current = start();
    const bool coarsePass = coarseLevels < layout.levels && !order.empty();
    if (coarsePass) {
        pass(true, order.size(), coarseLevels);
        if (!buildInto(*current, order, coarseLevels)) return finish(true);
        current->complete = false;
        publish(current);
        stats.coarseMs = millisecondsSince(request.submitted);
        current = std::make_shared<VoxelSnapshot>(*current);
    }
    // Full depth, nearest tiles first. After a coarse pass every dirty tile
    // already describes the new document, so batches can be published as
    // they finish (each a consistent snapshot); without one, only the end.
    const std::size_t batch = std::max<std::size_t>(64, order.size() / 4);
    pass(false, order.size(), layout.levels);
    for (std::size_t first = 0; first < order.size(); first += batch) {
        const std::vector<long> part(order.begin() + long(first),
                                     order.begin() + long(std::min(order.size(), first + batch)));
        if (!buildInto(*current, part, layout.levels)) return finish(true);
        const bool last = first + batch >= order.size();
        if (!last && coarsePass) {
            // Only what is published counts as done: a cancelled revision's
            // successor starts from the published snapshot.
            unfinishedTiles_.assign(order.begin() + long(first + batch), order.end());
            current->complete = false;
            publish(current);
            current = std::make_shared<VoxelSnapshot>(*current);
        }
    }
    current->complete = true;
    unfinishedTiles_.clear();
    stats.fineMs = millisecondsSince(request.submitted);
    if (stats.coarseMs == 0.0) stats.coarseMs = stats.fineMs;
    finish(false); // before publishing: a waiter for this revision reads its stats
    publish(current);
}

} // namespace kerf

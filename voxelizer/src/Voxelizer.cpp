#include "kerf/voxelizer/Voxelizer.hpp"

#include "kerf/document/NodeBounds.hpp"
#include "kerf/voxelizer/BlockTapes.hpp"
#include "kerf/voxelizer/DirtyRegion.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "kerf/voxelizer/WorkerArena.hpp"

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
        pending_ = Request{doc, revision, std::chrono::steady_clock::now(), true};
        latestDocument_ = doc;
    }
    changed_.notify_all();
    return revision;
}

void Voxelizer::setView(std::optional<ViewRequirement> view)
{
    {
        std::lock_guard lock(mutex_);
        if (view == view_) return;
        view_ = std::move(view);
        // A pending request reads the view when it runs; otherwise the
        // present document is planned again for it.
        if (pending_ || !latestDocument_) return;
        const std::uint64_t revision = latestRevision_.load() + 1;
        latestRevision_ = revision;
        pending_ = Request{*latestDocument_, revision, std::chrono::steady_clock::now(), false};
    }
    changed_.notify_all();
}

void Voxelizer::setOcclusion(std::shared_ptr<const OcclusionMap> picture)
{
    bool queued = false;
    {
        std::lock_guard lock(mutex_);
        occlusion_ = std::move(picture);
        ++occlusionGeneration_;
        queued = !processing_ && replanForPictureLocked();
    }
    if (queued) changed_.notify_all();
}

bool Voxelizer::replanForPictureLocked()
{
    if (hiddenBoxes_.empty() || plannedGeneration_ == occlusionGeneration_ || pending_ || !latestDocument_ || !view_ ||
        !occlusion_ || !(occlusion_->view == *view_))
        return false;
    plannedGeneration_ = occlusionGeneration_; // judged: the same picture is not judged again
    if (std::all_of(hiddenBoxes_.begin(), hiddenBoxes_.end(),
                    [&](const Aabb& box) { return occlusion_->hides(box, hiddenMargin_); }))
        return false;
    const std::uint64_t revision = latestRevision_.load() + 1;
    latestRevision_ = revision;
    pending_ = Request{*latestDocument_, revision, std::chrono::steady_clock::now(), false};
    return true;
}

void Voxelizer::setMemoryBudget(std::size_t bytes)
{
    std::lock_guard lock(mutex_);
    options_.memoryBudgetBytes = bytes;
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
            processing_ = true;
        }
        process(std::move(request));
        bool queued = false;
        {
            // A picture that came while this worked may show tiles its plan hid.
            std::lock_guard lock(mutex_);
            processing_ = false;
            queued = replanForPictureLocked();
        }
        if (queued) changed_.notify_all();
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

GridLayout Voxelizer::layoutFor(const Document& doc, const Tape& tape) const
{
    const double featureSize =
        options_.featureSize > 0.0 ? options_.featureSize : doc.settings.featureSize.value_or(defaultFeatureSize(tape.bounds()));
    return GridLayout::choose(tape.bounds(), featureSize, options_.limits);
}

void Voxelizer::process(Request request)
{
    const std::uint64_t revision = request.revision;
    const Tape tape = compileTape(request.doc, &features_);
    const GridLayout layout = layoutFor(request.doc, tape);
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
        // A stored distance saturates at two voxel edges of its tile's depth,
        // so twice a voxel diagonal at that depth is as far as an edit can
        // change what a tile stores: each depth present gets its own region,
        // and a tile is dirty when the region of its own depth reaches it
        // (tiles with no records, at the finest depth's).
        std::vector<int> depthOf(std::size_t(layout.tileCount()), layout.levels);
        std::set<int> depths = {layout.levels};
        for (long i = 0; i < layout.tileCount(); ++i) {
            const auto& t = base->tiles[std::size_t(i)];
            if (t && t->state == TileState::Surface) {
                depthOf[std::size_t(i)] = std::clamp(t->levels, 1, layout.levels);
                depths.insert(depthOf[std::size_t(i)]);
            }
        }
        for (int depth : depths) {
            const double margin = 2.0 * std::sqrt(3.0) * layout.voxelSizeAt(depth);
            const DirtyRegion region = dirtyRegion(*builtDocument_, request.doc, margin);
            if (region.everything) {
                for (long i = 0; i < layout.tileCount(); ++i) dirty.insert(i);
                break;
            }
            for (const long i : tilesReached(region, layout))
                if (depthOf[std::size_t(i)] == depth) dirty.insert(i);
        }
    }
    builtDocument_ = request.doc;
    builtLayout_ = layout;
    unfinishedTiles_.assign(dirty.begin(), dirty.end());

    glm::dvec3 focus;
    std::optional<ViewRequirement> view;
    std::size_t budget;
    {
        std::lock_guard lock(mutex_);
        focus = focus_;
        view = view_;
        budget = options_.memoryBudgetBytes;
    }
    if (view) focus = view->eye;
    auto nearestFirst = [&](std::vector<long>& tiles) {
        std::sort(tiles.begin(), tiles.end(), [&](long a, long b) {
            return glm::length(layout.tileBox(layout.tileCoord(a)).center() - focus) <
                   glm::length(layout.tileBox(layout.tileCoord(b)).center() - focus);
        });
    };
    std::vector<long> order(dirty.begin(), dirty.end());
    nearestFirst(order);

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
    tbb::task_arena arena = workerArena(options_.threads);
    tbb::enumerable_thread_specific<TileBuildScratch> scratch;
    const BlockTapes blocks(tape, layout);
    const Progress superseded = Progress::cancelledWhen([&] { return stale(revision); });

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

    // Builds each of `tiles` at its depth (`levelsOf`) into `snap`; false when cancelled.
    auto buildInto = [&](VoxelSnapshot& snap, const std::vector<long>& tiles, const auto& levelsOf) {
        std::vector<std::shared_ptr<const TileData>> built(tiles.size());
        std::atomic<bool> aborted{false};
        arena.execute([&] {
            tbb::parallel_for(std::size_t(0), tiles.size(), [&](std::size_t k) {
                if (aborted.load()) return;
                const glm::ivec3 tc = layout.tileCoord(tiles[k]);
                TileBuildScratch& s = scratch.local();
                s.helper = [&scratch]() -> TileBuildScratch& { return scratch.local(); };
                auto t = buildTile(blocks.forTile(tc), layout, tc, levelsOf(tiles[k]), s, superseded);
                // Empty only at this depth: a level deeper at once, until a
                // surface shows or the depth is the grid's. A board thinner
                // than the coarse voxels (a 6.5 mm cabinet back under 8 mm
                // voxels) vanished from the coarse preview for seconds.
                while (t && t->unresolved && t->levels < layout.levels)
                    t = buildTile(blocks.forTile(tc), layout, tc, t->levels + 1, s, superseded);
                if (!t) {
                    aborted = true;
                    return;
                }
                // Empty tiles are kept as null, except those empty only at a
                // depth short of the grid's (a deeper build may find a surface).
                if (t->state != TileState::Empty || (t->unresolved && t->levels < layout.levels))
                    built[k] = std::make_shared<const TileData>(std::move(*t));
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

    // 1. The coarse pass: every tile the edit reaches, at the coarse depth,
    // published at once (the preview). Without one, those tiles are built
    // at their planned depth below, and nothing is published before the end.
    int coarseLevels = std::max(1, layout.levels - options_.coarseLevelDrop);
    // The coarse pass builds every tile the edit reaches, whatever the
    // budget: at the coarse depth of a feature size far too fine for the
    // part (2 um on a 2 m panel) that was billions of voxels, and the
    // application grew by 250 MB a second until the system killed it. Its
    // depth is lowered until the estimate fits half of the budget (each
    // level up has about a sixteenth of the surface voxels).
    bool coarsePassOverBudget = false;
    if (budget > 0 && coarseLevels > 1 && !order.empty()) {
        if (!budgetedCoarseLevels_ || !(budgetedCoarseLevels_->first == layout)) {
            GridLayout coarse = layout;
            coarse.levels = coarseLevels;
            coarse.voxelSize = layout.voxelSizeAt(coarseLevels);
            const VoxelEstimate e = estimateVoxels(tape, coarse, 2e5, 0.25);
            int fits = coarseLevels;
            for (double bytes = e.bytes; fits > 1 && bytes > 0.5 * double(budget); bytes /= 16.0)
                --fits;
            budgetedCoarseLevels_ = std::pair{layout, fits};
        }
        coarsePassOverBudget = budgetedCoarseLevels_->second < coarseLevels;
        coarseLevels = std::min(coarseLevels, budgetedCoarseLevels_->second);
    }
    auto current = start();
    pass(false, 0, layout.levels); // this revision is under way
    const bool coarsePass = coarseLevels < layout.levels && !order.empty();
    std::set<long> stale = dirty; // tiles still describing an older document
    if (coarsePass) {
        pass(true, order.size(), coarseLevels);
        if (!buildInto(*current, order, [&](long) { return coarseLevels; })) return finish(true);
        current->complete = false;
        current->coarsenedForBudget = coarsePassOverBudget ? order.size() : 0; // said in the status bar
        publish(current);
        stats.coarseMs = millisecondsSince(request.submitted);
        current = std::make_shared<VoxelSnapshot>(*current);
        stale.clear();
        unfinishedTiles_.clear(); // every tile the edit reached is published for the new document
    }

    // 2. The plan: each tile's depth for this view and budget, estimated from
    // the tiles as they now are; then 3. the building, nearest first,
    // published batch by batch once every tile describes the document (each
    // a consistent snapshot). A tile with no data yet (no coarse pass ran)
    // has no estimate: it is built first (at full depth without a view, at
    // the coarse depth with one) and planned again in the next round.
    RefinementOptions ro;
    ro.view = view;
    ro.memoryBudgetBytes = budget;
    ro.coarseLevels = coarseLevels;
    ro.focus = focus;
    RefinementPlan plan;
    for (int round = 0; round < 3; ++round) {
        {
            std::lock_guard lock(mutex_); // the newest picture, each round
            ro.occlusion = occlusion_;
            plannedGeneration_ = occlusionGeneration_;
        }
        plan = planRefinement(layout, current->tiles, ro);
        const bool overBudget = plan.coarsenedForBudget > 0;
        // Stale tiles, those shallower than planned and, over the budget,
        // those deeper than planned. A tile the view has left keeps its depth
        // while the budget allows: building it again would only cost time.
        std::vector<long> work;
        std::size_t refined = 0;
        for (long i = 0; i < layout.tileCount(); ++i) {
            const auto& t = current->tiles[std::size_t(i)];
            if (stale.count(i)) {
                work.push_back(i);
                continue;
            }
            // A tile empty only at its depth is refined as a surface tile
            // is: the coarse pass's voxels may have stepped over a thin plate.
            if (!t || !t->mayRefine()) continue;
            const int planned = plan.levels[std::size_t(i)];
            if (t->levels < planned || (overBudget && t->levels > planned)) {
                work.push_back(i);
                ++refined;
            }
        }
        if (work.empty()) break;
        nearestFirst(work);
        stats.refinedTiles += refined;
        auto plannedLevels = [&](long i) {
            const int planned = plan.levels[std::size_t(i)];
            return planned > 0 ? planned : (view ? coarseLevels : layout.levels);
        };
        const bool publishBatches = stale.empty();
        const std::size_t batch = std::max<std::size_t>(64, work.size() / 4);
        pass(false, work.size(), layout.levels);
        for (std::size_t first = 0; first < work.size(); first += batch) {
            const std::vector<long> part(work.begin() + long(first),
                                         work.begin() + long(std::min(work.size(), first + batch)));
            if (!buildInto(*current, part, plannedLevels)) return finish(true);
            const bool last = first + batch >= work.size();
            if (!last && publishBatches) {
                // Only what is published counts as done: a cancelled
                // revision's successor starts from the published snapshot.
                unfinishedTiles_.clear();
                current->complete = false;
                current->coarsenedForBudget = plan.coarsenedForBudget;
                current->outsideView = plan.outsideView;
                current->hiddenTiles = plan.hidden;
                publish(current);
                current = std::make_shared<VoxelSnapshot>(*current);
            }
        }
        stale.clear();
    }
    stats.coarsenedForBudget = plan.coarsenedForBudget;
    stats.hiddenTiles = plan.hidden;
    {
        std::lock_guard lock(mutex_);
        hiddenBoxes_.clear();
        for (long i : plan.hiddenTiles) hiddenBoxes_.push_back(layout.tileBox(layout.tileCoord(i)));
        hiddenMargin_ = plan.occlusionMargin;
    }
    current->complete = true;
    current->coarsenedForBudget = plan.coarsenedForBudget;
    current->outsideView = plan.outsideView;
    current->hiddenTiles = plan.hidden;
    unfinishedTiles_.clear();
    stats.fineMs = millisecondsSince(request.submitted);
    if (stats.coarseMs == 0.0) stats.coarseMs = stats.fineMs;
    finish(false); // before publishing: a waiter for this revision reads its stats
    publish(current);
}

} // namespace kerf

#include "kerf/viewport/GpuVoxelWorker.hpp"

#include <algorithm>
#include <exception>
#include <utility>

namespace kerf::vk {

namespace {

using Clock = std::chrono::steady_clock;

} // namespace

GpuVoxelWorker::GpuVoxelWorker(const Context& ctx, std::function<void()> onChange)
    : onChange_(std::move(onChange)), voxelizer_(ctx)
{
    thread_ = std::thread([this] { run(); });
}

GpuVoxelWorker::~GpuVoxelWorker()
{
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        cancel_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void GpuVoxelWorker::request(GpuVoxelRequest request)
{
    {
        std::lock_guard lock(mutex_);
        if (!request.dirtyTiles || request.dirtySince != lastRequested_)
            everythingDirty_ = true;
        else
            dirtySinceBase_.insert(request.dirtyTiles->begin(), request.dirtyTiles->end());
        lastRequested_ = request.revision;
        pending_ = std::make_unique<GpuVoxelRequest>(std::move(request));
        pendingSince_ = Clock::now();
        if (building_) cancel_ = true;
    }
    wake_.notify_all();
}

void GpuVoxelWorker::cancel()
{
    {
        std::lock_guard lock(mutex_);
        pending_.reset();
        if (building_) cancel_ = true;
        release_ = true;
    }
    wake_.notify_all();
}

std::unique_ptr<GpuVoxelResult> GpuVoxelWorker::take()
{
    std::lock_guard lock(mutex_);
    return std::move(ready_);
}

void GpuVoxelWorker::recycle(std::unique_ptr<GpuVoxelResult> old)
{
    if (!old) return;
    {
        std::lock_guard lock(mutex_);
        returned_.push_back(std::move(old->voxels));
    }
    wake_.notify_all();
}

bool GpuVoxelWorker::busy() const
{
    std::lock_guard lock(mutex_);
    return building_ || pending_;
}

std::string GpuVoxelWorker::refusal() const
{
    std::lock_guard lock(mutex_);
    return refusal_;
}

std::uint64_t GpuVoxelWorker::refusedRevision() const
{
    std::lock_guard lock(mutex_);
    return refusedRevision_;
}

void GpuVoxelWorker::recycleBuild(std::shared_ptr<GpuVoxels>& build)
{
    if (build && build.use_count() == 1) voxelizer_.recycle(std::move(*build));
    build.reset();
}

void GpuVoxelWorker::takeInReturned()
{
    std::vector<std::shared_ptr<GpuVoxels>> returned;
    {
        std::lock_guard lock(mutex_);
        returned.swap(returned_);
    }
    for (auto& v : returned)
        recycleBuild(v);
}

void GpuVoxelWorker::run()
{
    for (;;) {
        GpuVoxelRequest request;
        Clock::time_point requested;
        // What changed since the base build: taken with the request, given back if its build does not finish.
        std::set<long> dirty;
        bool everything = false;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || pending_ || release_ || !returned_.empty(); });
            if (stop_) return;
            if (!pending_) {
                // Housekeeping: builds handed back; after cancel(), the device memory let go.
                released_ = released_ || std::exchange(release_, false);
                const bool free = released_;
                lock.unlock();
                takeInReturned();
                if (free) {
                    recycleBuild(base_);
                    voxelizer_.releaseSpares();
                }
                continue;
            }
            request = std::move(*pending_);
            requested = pendingSince_;
            pending_.reset();
            release_ = released_ = false;
            building_ = true;
            cancel_ = false;
            refusal_.clear();
            refusedRevision_ = 0;
            dirty.swap(dirtySinceBase_);
            everything = std::exchange(everythingDirty_, false);
        }
        bool finished = false;
        try {
            build(request, requested, dirty, everything, finished);
        } catch (const std::exception& e) {
            // A device error: the viewport says so and the CPU voxelizer takes over.
            std::lock_guard lock(mutex_);
            refusal_ = e.what();
            refusedRevision_ = request.revision;
        }
        {
            std::lock_guard lock(mutex_);
            if (!finished) {
                dirtySinceBase_.insert(dirty.begin(), dirty.end());
                everythingDirty_ = everythingDirty_ || everything;
            }
            building_ = false;
        }
        if (onChange_) onChange_();
    }
}

void GpuVoxelWorker::build(const GpuVoxelRequest& request, Clock::time_point requested, std::set<long>& dirty,
                           bool& everything, bool& finished)
{
    const auto publish = [&](std::shared_ptr<GpuVoxels> voxels, bool complete, const GpuVoxelizeReport& report) {
        auto result = std::make_unique<GpuVoxelResult>();
        result->revision = request.revision;
        result->complete = complete;
        result->voxels = std::move(voxels);
        result->features = request.tape ? request.tape->sharedFeatures() : nullptr;
        result->report = report;
        result->requestMilliseconds = std::chrono::duration<double, std::milli>(Clock::now() - requested).count();
        std::unique_ptr<GpuVoxelResult> superseded;
        {
            std::lock_guard lock(mutex_);
            result->version = ++version_;
            superseded = std::move(ready_); // never shown: straight back to the pools
            ready_ = std::move(result);
        }
        if (superseded) recycleBuild(superseded->voxels);
        if (onChange_) onChange_();
    };

    takeInReturned();
    if (!request.tape || request.tape->empty() || request.layout.tileCount() == 0) {
        // Nothing to build: an empty picture, at once.
        auto none = std::make_shared<GpuVoxels>();
        none->layout = request.layout;
        recycleBuild(base_);
        finished = true;
        publish(std::move(none), true, {});
        return;
    }
    // The preview, then full depth; a grid of one level has no preview.
    // An edit of the part on screen (same grid) skips the preview: the full
    // build takes a few frames on a GPU, and a preview would blur the whole
    // part meanwhile where the CPU path keeps its clean tiles sharp.
    std::vector<int> depths;
    const int full = request.layout.levels;
    const bool edit = base_ && base_->layout == request.layout && base_->levels == request.layout.levels;
    if (!edit && request.coarseLevelDrop > 0 && full - request.coarseLevelDrop >= 1)
        depths.push_back(full - request.coarseLevelDrop);
    depths.push_back(full);
    for (const int levels : depths) {
        takeInReturned();
        GpuVoxelizeOptions options;
        options.levels = levels;
        options.cancel = &cancel_;
        options.memoryBudget = request.memoryBudget;
        GpuVoxelizeReport report;
        std::optional<GpuVoxels> voxels;
        if (levels == full && edit && !everything) {
            const std::vector<long> tiles(dirty.begin(), dirty.end());
            voxels = voxelizer_.update(*base_, *request.tape, tiles, options, &report);
            // The base's pools count whole, replaced records included: a
            // refused update may still fit as a whole build.
            if (!voxels && !report.cancelled) {
                recycleBuild(base_);
                voxels = voxelizer_.build(*request.tape, request.layout, options, &report);
            }
        } else {
            voxels = voxelizer_.build(*request.tape, request.layout, options, &report);
        }
        if (!voxels) {
            if (report.cancelled) return;
            std::lock_guard lock(mutex_);
            refusal_ = report.whyNot;
            refusedRevision_ = request.revision;
            return;
        }
        auto shared = std::make_shared<GpuVoxels>(std::move(*voxels));
        if (levels == full) {
            recycleBuild(base_);
            base_ = shared;
            finished = true;
        }
        publish(std::move(shared), levels == full, report);
        if (cancel_) return;
    }
}

} // namespace kerf::vk

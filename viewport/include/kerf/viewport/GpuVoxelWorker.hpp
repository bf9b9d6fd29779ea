#pragma once
// The GPU voxelizer working for the viewport in the background: the newest
// request (a document's tape and grid) is built on a thread of its own,
// coarse first (a preview a few levels shallower, on screen within a frame
// or two; not for an edit on the grid already shown, whose build stays
// until the new one is complete), then at full depth, so the render thread
// never waits for a build. A request made while another is being built stops that one before
// its next level and takes its pools.
//
// An edit whose request names the tiles it reaches (relative to the
// request before it) is an update of the last complete build: only those
// tiles are built again, into the same pools (GpuVoxelizer::update); the
// tiles of requests superseded on the way are added up, so the update is
// always against what the base build shows.
//
// Results wait in a mailbox of one: the render thread take()s the newest
// (an older one it never took goes straight back to the pools) and hands
// the one it showed before back with recycle() once no frame reads it, so
// that a rebuild of the same part allocates nothing.
//
// Threading: request(), take(), recycle() and the queries are for one
// thread (the render thread); `onChange` is called on the worker's thread
// after every result and whenever it goes idle. The context's queue is
// shared with the render thread (Context::lockQueue).

#include "kerf/viewport/GpuVoxelizer.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace kerf::vk {

struct GpuVoxelRequest {
    std::uint64_t revision = 0;       // the document revision it describes
    std::shared_ptr<const Tape> tape; // world coordinates, features included
    GridLayout layout;
    /// The preview's depth below the layout's (each level 4x coarser
    /// voxels); 0: no preview.
    int coarseLevelDrop = 2;
    /// Device memory the build's pools may take (the user's voxel budget);
    /// 0: half the device-local memory.
    std::size_t memoryBudget = 0;
    /// The tiles this document differs in from the document of request
    /// `dirtySince` (same grid; DirtyRegion.hpp's tilesAnEditReaches); none:
    /// unknown, all. Used only when `dirtySince` is the request the worker
    /// was given last (a request the viewport skipped leaves a gap: all).
    std::optional<std::vector<long>> dirtyTiles;
    std::uint64_t dirtySince = 0;

    /// A request for every tile (the other fields at their defaults).
    static GpuVoxelRequest of(std::uint64_t revision, std::shared_ptr<const Tape> tape, const GridLayout& layout,
                              int coarseLevelDrop = 2)
    {
        GpuVoxelRequest r;
        r.revision = revision;
        r.tape = std::move(tape);
        r.layout = layout;
        r.coarseLevelDrop = coarseLevelDrop;
        return r;
    }
};

struct GpuVoxelResult {
    std::uint64_t revision = 0;
    std::uint64_t version = 0; // increases with every result of a worker
    bool complete = false;     // at the layout's full depth
    std::shared_ptr<GpuVoxels> voxels; // no tiles for an empty part
    std::shared_ptr<const std::vector<Feature>> features;
    GpuVoxelizeReport report;
    double requestMilliseconds = 0.0; // from request() to this result
};

class GpuVoxelWorker {
public:
    GpuVoxelWorker(const Context& ctx, std::function<void()> onChange);
    ~GpuVoxelWorker(); // stops the build under way and joins
    GpuVoxelWorker(const GpuVoxelWorker&) = delete;
    GpuVoxelWorker& operator=(const GpuVoxelWorker&) = delete;

    /// Builds `request` next (replaces one not started, stops one under way).
    void request(GpuVoxelRequest request);
    /// Stops the build under way, forgets any request not started, and lets
    /// go of the device memory it keeps (its last build, its spare pools)
    /// once the builds handed out come back.
    void cancel();
    /// The newest result not taken yet, else null.
    std::unique_ptr<GpuVoxelResult> take();
    /// A result no frame reads any more: its pools serve the next build.
    void recycle(std::unique_ptr<GpuVoxelResult> old);
    /// A request is waiting or being built.
    bool busy() const;
    /// Why the last request could not be built on the GPU (pools beyond the
    /// memory budget, a device error), with its revision; empty otherwise.
    std::string refusal() const;
    std::uint64_t refusedRevision() const;

private:
    void run();
    // `dirty`, `everything`: what changed since the base build, taken with the request.
    void build(const GpuVoxelRequest& request, std::chrono::steady_clock::time_point requested, std::set<long>& dirty,
               bool& everything, bool& finished);
    void recycleBuild(std::shared_ptr<GpuVoxels>& build); // to the pools, unless another build still holds it
    void takeInReturned();

    std::function<void()> onChange_;
    GpuVoxelizer voxelizer_; // the worker thread's only
    std::shared_ptr<GpuVoxels> base_; // the last complete build: an edit updates it (the worker thread's only)

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::unique_ptr<GpuVoxelRequest> pending_;
    std::chrono::steady_clock::time_point pendingSince_;
    bool building_ = false;
    bool stop_ = false;
    std::atomic<bool> cancel_{false};
    std::unique_ptr<GpuVoxelResult> ready_;
    std::vector<std::shared_ptr<GpuVoxels>> returned_; // recycled by the render thread, for the worker to take in
    // The tiles changed since the base build's request (guarded by mutex_).
    std::set<long> dirtySinceBase_;
    bool everythingDirty_ = true;
    std::uint64_t lastRequested_ = 0; // the revision of the last request
    bool release_ = false;            // cancel() asked to let go of the device memory
    bool released_ = false;           // ... and it was: builds coming back are freed, not kept
    std::string refusal_;
    std::uint64_t refusedRevision_ = 0;
    std::uint64_t version_ = 0;
    std::thread thread_;
};

} // namespace kerf::vk

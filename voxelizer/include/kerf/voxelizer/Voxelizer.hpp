#pragma once
// The background voxelizer: give it each new version of the document; it
// rebuilds only the tiles the edit can change, first at a coarse depth, then
// at the depth each tile needs, and publishes consistent snapshots as it goes.
//
// Depth per tile (RefinementPlan.hpp): full depth everywhere without a view;
// with one (setView), only as fine as the camera can see, refined when the
// view changes; tiles the last picture showed hidden behind the part
// (setOcclusion) stay coarse until a picture shows them; and within the
// memory budget, the farthest tiles coarsened first when a scene would
// exceed it.
//
// Threading: setDocument() and every other public function return at once
// and may be called from any thread (the GUI thread, typically). Work runs on
// one coordinating thread and a oneTBB arena. A newer document cancels the
// work for an older one within one contree node's work; a cancelled tile is
// discarded, never published. Each snapshot's tiles all describe the same
// document (a tile the edit cannot reach is the same for both versions).
//
// Lifetime: the destructor cancels the work and waits for it.

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/OcclusionMap.hpp"
#include "kerf/voxelizer/RefinementPlan.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

namespace kerf {

struct VoxelizerOptions {
    GridLimits limits;
    /// The coarse pass builds dirty tiles this many levels shallower
    /// (each level is 4x coarser voxels); 0 disables it.
    int coarseLevelDrop = 2;
    int threads = 0; // 0: every core
    /// Overrides the document's feature size (mm); 0: the document's or the default.
    double featureSize = 0.0;
    /// Called on the coordinating thread after each publication.
    std::function<void(std::shared_ptr<const VoxelSnapshot>)> onPublish;
    /// Voxel bytes a snapshot may reach (estimated ahead); 0: no limit.
    std::size_t memoryBudgetBytes = 0;
};

struct VoxelizerStats {
    std::uint64_t revision = 0;
    std::size_t tilesInGrid = 0;
    std::size_t dirtyTiles = 0;   // tiles the edit reached (rebuilt for the new document)
    std::size_t refinedTiles = 0; // tiles rebuilt at another depth (the view or the budget asked)
    std::size_t coarsenedForBudget = 0; // tiles below what the view needs, to fit the budget
    std::size_t hiddenTiles = 0;  // tiles kept coarse as hidden behind the part
    double coarseMs = 0.0;        // from the request to the coarse publication
    double fineMs = 0.0;          // from the request to the complete publication
    bool cancelled = false;
};

/// Where the background work stands (for a progress display).
struct VoxelizerProgress {
    std::uint64_t revision = 0; // the revision being built (or last built)
    bool busy = false;
    bool coarsePass = false;    // building the coarse preview (else full depth)
    std::size_t tilesToBuild = 0;
    std::size_t tilesBuilt = 0; // of this pass
    int levels = 0;             // depth this pass builds to
    int targetLevels = 0;       // full depth
};

class Voxelizer {
public:
    explicit Voxelizer(VoxelizerOptions options = {});
    ~Voxelizer();
    Voxelizer(const Voxelizer&) = delete;
    Voxelizer& operator=(const Voxelizer&) = delete;

    /// Queues a version of the document; returns its revision number.
    std::uint64_t setDocument(const Document& doc);
    /// Tiles nearer this world point are rebuilt first.
    void setFocus(const glm::dvec3& point);
    /// What the viewer needs (none: full depth everywhere). A changed view
    /// refines (or, over budget, coarsens) the tiles it concerns.
    void setView(std::optional<ViewRequirement> view);
    /// The last picture of the view (null: none). Used while its view is the
    /// one set; a picture that shows a tile the last plan kept coarse as
    /// hidden plans the present document again, so that the tile refines
    /// (after the work under way, which it does not interrupt). A picture
    /// that reveals nothing new plans nothing: the loop through the viewport
    /// ends once the pictures agree with the plan.
    void setOcclusion(std::shared_ptr<const OcclusionMap> picture);
    /// The memory budget (0: none); applies from the next request on.
    void setMemoryBudget(std::size_t bytes);
    /// The grid this voxelizer builds `doc` on (`tape` compiled from it):
    /// the feature size the options or the document ask for, within the
    /// options' limits. For a builder of the same voxels elsewhere (the GPU).
    GridLayout layoutFor(const Document& doc, const Tape& tape) const;

    /// The latest publication (null before the first).
    std::shared_ptr<const VoxelSnapshot> snapshot() const;
    /// Waits until `revision` is published (complete if asked). False on timeout.
    bool waitFor(std::uint64_t revision, bool complete, std::chrono::milliseconds timeout) const;
    /// Statistics of the last revision whose work finished or was cancelled.
    VoxelizerStats lastStats() const;
    /// What the background work is doing now (cheap; any thread).
    VoxelizerProgress progress() const;

private:
    struct Request {
        Document doc;
        std::uint64_t revision;
        std::chrono::steady_clock::time_point submitted;
        bool documentChanged = true; // false: the same document, a new view or budget
    };
    void queue(Request request);
    /// Queues a new plan of the present document when a picture newer than
    /// the last plan's shows a tile that plan hid (mutex_ held).
    bool replanForPictureLocked();
    void run();
    void process(Request request);
    void publish(std::shared_ptr<VoxelSnapshot> snap);
    bool stale(std::uint64_t revision) const { return latestRevision_.load() != revision || stopping_.load(); }

    VoxelizerOptions options_;
    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;
    std::optional<Request> pending_;
    std::shared_ptr<const VoxelSnapshot> published_;
    VoxelizerStats stats_;
    glm::dvec3 focus_{0.0};
    std::optional<ViewRequirement> view_;      // guarded by mutex_
    std::shared_ptr<const OcclusionMap> occlusion_; // guarded by mutex_
    std::uint64_t occlusionGeneration_ = 0;    // guarded by mutex_: counts setOcclusion() calls
    std::uint64_t plannedGeneration_ = 0;      // guarded by mutex_: the picture the last plan used
    std::vector<Aabb> hiddenBoxes_;            // guarded by mutex_: the tiles the last plan kept hidden
    double hiddenMargin_ = 0.0;                // guarded by mutex_: ... and by how much
    bool processing_ = false;                  // guarded by mutex_: a request is being worked on
    std::optional<Document> latestDocument_;   // guarded by mutex_: the newest setDocument()
    std::atomic<std::uint64_t> latestRevision_{0};
    std::atomic<bool> stopping_{false};
    VoxelizerProgress progress_;               // guarded by mutex_
    std::atomic<std::size_t> tilesBuilt_{0};    // of the current pass
    std::uint64_t nextVersion_ = 1; // coordinating thread only

    // Owned by the coordinating thread.
    std::optional<Document> builtDocument_;   // the document the last processed request described
    GridLayout builtLayout_;                  // ... and its grid
    // The coarse pass's depth within the memory budget, for the grid it was
    // estimated on (an estimate takes a coarse voxelization: once a grid).
    std::optional<std::pair<GridLayout, int>> budgetedCoarseLevels_;
    std::vector<long> unfinishedTiles_;       // tiles not yet at full depth for builtDocument_
    FeatureRegistry features_;

    std::thread worker_;
};

} // namespace kerf

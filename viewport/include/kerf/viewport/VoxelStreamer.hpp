#pragma once
// Streams published voxel snapshots to the GPU under a per-frame byte
// budget. Tiles live in one device heap (one allocation per tile holding its
// nodes, leaf indirections, leaf data, vertices and exact tape); a tile the new snapshot
// shares with the resident one (the voxelizer keeps unchanged tiles as the
// same objects) is not uploaded again.
//
// Consistency: the tracer reads the resident set, a tile table and the heap.
// A new snapshot's tiles are uploaded over as many frames as the budget
// needs; only when every one of them is on the device is the small tile
// table switched, all at once. Until then the previous set stays visible:
// never half a tile, never a mix of two snapshots.
//
// Frames in flight: memory a frame may still read (staging space, replaced
// tiles, old tables) is reused only `framesInFlight` frames later; the caller
// must not have more frames in flight than that.
//
// Threading: one thread (the render thread).

#include "kerf/viewport/GpuBuffer.hpp"
#include "kerf/viewport/HeapAllocator.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <deque>
#include <functional>
#include <memory>
#include <unordered_map>

namespace kerf::vk {

/// What the tracer reads: one consistent snapshot on the device.
struct ResidentSet {
    std::uint64_t snapshotVersion = 0;
    GridLayout layout;
    VkDeviceAddress tiles = 0;   // u32 per tile
    VkDeviceAddress entries = 0; // TileEntry per surface tile
    VkDeviceAddress heap = 0;    // base of nodes, leaf indirections, leaf data, vertices and tapes alike
    std::size_t bytes = 0;       // voxel bytes of this set (tables + its tiles)
    bool valid() const { return tiles != 0; }
};

struct StreamingOptions {
    std::size_t budgetBytesPerFrame = 32u << 20;
    int framesInFlight = 3;
    std::size_t initialHeapBytes = 64u << 20;
};

struct FrameUpload {
    std::size_t bytes = 0;         // uploaded by this frame's commands (never above the budget)
    std::size_t tilesCompleted = 0;
    std::size_t tilesPending = 0;  // tiles of the target not yet resident
    bool switched = false;         // the resident set became the target this frame
};

class VoxelStreamer {
public:
    VoxelStreamer(const Context& ctx, StreamingOptions options = {});
    ~VoxelStreamer();

    /// The snapshot to stream towards (replaces any earlier target).
    void setTarget(std::shared_ptr<const VoxelSnapshot> snapshot);
    /// Records this frame's uploads into `cb` (transfer commands followed by
    /// a barrier to compute shader reads). Call once per frame.
    FrameUpload recordFrame(VkCommandBuffer cb);
    const ResidentSet& resident() const { return resident_; }
    /// The snapshot the resident set holds (null before the first switch).
    const std::shared_ptr<const VoxelSnapshot>& residentSnapshot() const { return residentSnapshot_; }
    bool upToDate() const;
    std::size_t heapCapacity() const { return heap_.capacity(); }
    /// Heap bytes allocated to tiles (the resident set's, the target's, and
    /// ranges waiting for the frames in flight).
    std::size_t heapBytesInUse() const { return heap_.used(); }

private:
    struct Placement {
        // Held, not only pointed at: the map is keyed by the tile's address,
        // and a tile freed while its entry stayed let a new tile made at the
        // same address pass for it (a plain box drawn with pieces of the
        // chair that was open before File > New).
        std::shared_ptr<const TileData> tile;
        std::size_t offset = 0, bytes = 0;
        std::size_t uploaded = 0; // bytes of the blob already copied
        TileEntry entry{};        // offsets in elements of the heap base
    };
    struct Retired {
        std::uint64_t frame;
        std::function<void()> release;
    };
    void beginTarget();
    /// Frees the heap ranges of placed tiles that neither the resident set
    /// nor the target holds (those of a target replaced before it became
    /// resident), once the frames in flight that may still copy into them
    /// are done.
    void dropAbandonedTiles();
    void releaseLater(std::vector<std::pair<std::size_t, std::size_t>> ranges, std::function<void()> alsoRelease = {});
    void growHeap(std::size_t needed);
    std::size_t stage(VkCommandBuffer cb, const void* data, std::size_t bytes, VkBuffer dst, std::size_t dstOffset);

    const Context& ctx_;
    StreamingOptions options_;
    std::uint64_t frame_ = 0;

    std::shared_ptr<GpuBuffer> heapBuffer_;
    std::vector<std::shared_ptr<GpuBuffer>> replacedHeaps_; // outgrown heaps the resident set may still read
    std::uint64_t heapGeneration_ = 0;                      // counts heaps: freed ranges name theirs
    HeapAllocator heap_;
    std::unordered_map<const TileData*, Placement> placed_; // tiles in heapBuffer_
    std::shared_ptr<const VoxelSnapshot> residentSnapshot_, target_;
    std::vector<const TileData*> pending_; // target tiles not fully uploaded, in upload order

    GpuBuffer staging_;
    std::size_t stagingHead_ = 0;
    std::vector<std::shared_ptr<GpuBuffer>> tables_; // the tile table + entries buffers of the resident set
    ResidentSet resident_;
    std::deque<Retired> retired_;
};

} // namespace kerf::vk

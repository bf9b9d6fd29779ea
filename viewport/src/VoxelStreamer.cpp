#include "kerf/viewport/VoxelStreamer.hpp"

#include "kerf/viewport/VulkanError.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <unordered_set>

namespace kerf::vk {

namespace {

constexpr std::size_t kAlign = 24; // lcm of the record sizes 12 and 8

std::size_t alignUp(std::size_t v) { return (v + kAlign - 1) / kAlign * kAlign; }

// A tile's records, laid out as one blob: nodes, leaf indirections, leaf
// data, vertices and its exact tape (32-bit words), each part starting on a
// 24-byte boundary so that its offset is a whole number of records of any
// of the sizes.
struct BlobLayout {
    std::size_t leafIndirections, leafData, vertices, tape, total;
    explicit BlobLayout(const TileData& t)
    {
        leafIndirections = alignUp(t.nodes.size() * sizeof(voxel::Node));
        leafData = alignUp(leafIndirections + t.leafIndirections.size() * sizeof(voxel::LeafIndirection));
        vertices = alignUp(leafData + t.leafData.size() * sizeof(voxel::LeafData));
        tape = alignUp(vertices + t.vertices.size() * sizeof(voxel::Vertex));
        total = alignUp(tape + t.tape.size() * sizeof(std::uint32_t));
    }
};

// Writes bytes [from, from + bytes) of `t`'s blob to `out`: the records
// where the layout has them, zeros in the padding between the parts. Straight
// from the tile's arrays into the staging ring, without assembling the blob.
void copyBlobRange(const TileData& t, const BlobLayout& layout, std::size_t from, std::size_t bytes, std::uint8_t* out)
{
    struct Part {
        std::size_t start;
        const void* data;
        std::size_t size;
        std::size_t end; // where the next part starts: [start + size, end) is padding
    };
    const std::array<Part, 5> parts{{
        {0, t.nodes.data(), t.nodes.size() * sizeof(voxel::Node), layout.leafIndirections},
        {layout.leafIndirections, t.leafIndirections.data(), t.leafIndirections.size() * sizeof(voxel::LeafIndirection),
         layout.leafData},
        {layout.leafData, t.leafData.data(), t.leafData.size() * sizeof(voxel::LeafData), layout.vertices},
        {layout.vertices, t.vertices.data(), t.vertices.size() * sizeof(voxel::Vertex), layout.tape},
        {layout.tape, t.tape.data(), t.tape.size() * sizeof(std::uint32_t), layout.total},
    }};
    const std::size_t to = from + bytes;
    for (const Part& part : parts) {
        const std::size_t dataEnd = part.start + part.size;
        if (const std::size_t a = std::max(from, part.start), b = std::min(to, dataEnd); a < b)
            std::memcpy(out + (a - from), static_cast<const std::uint8_t*>(part.data) + (a - part.start), b - a);
        if (const std::size_t a = std::max(from, dataEnd), b = std::min(to, part.end); a < b)
            std::memset(out + (a - from), 0, b - a);
    }
}

} // namespace

VoxelStreamer::VoxelStreamer(const Context& ctx, StreamingOptions options)
    : ctx_(ctx), options_(options), heap_(0, kAlign)
{
    // The staging ring holds the uploads of every frame that may be in flight.
    staging_ = GpuBuffer(ctx, options_.budgetBytesPerFrame * std::size_t(std::max(1, options_.framesInFlight)),
                         VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GpuBuffer::Kind::HostVisible, "staging ring");
    growHeap(options_.initialHeapBytes);
}

VoxelStreamer::~VoxelStreamer() = default;

bool VoxelStreamer::upToDate() const { return !target_ || (pending_.empty() && residentSnapshot_ == target_); }

void VoxelStreamer::growHeap(std::size_t needed)
{
    // A new heap: every tile of the target is uploaded into it again; the old
    // heap stays alive (held by retired_) while the resident set reads it.
    const std::size_t limit = ctx_.maxAllocationBytes();
    std::size_t capacity = std::max<std::size_t>(options_.initialHeapBytes, needed);
    if (capacity > limit) capacity = limit;
    if (needed > capacity)
        throw VulkanError("voxel heap: the scene needs " + std::to_string(needed >> 20) +
                              " MiB, more than the device allocates at once (" + std::to_string(limit >> 20) + " MiB)",
                          VK_ERROR_OUT_OF_DEVICE_MEMORY);
    // The resident set may read the old heap until the next switch, however
    // many frames the new target takes to arrive: it is retired then.
    if (heapBuffer_) replacedHeaps_.push_back(heapBuffer_);
    ++heapGeneration_;
    heapBuffer_ = std::make_shared<GpuBuffer>(ctx_, capacity,
                                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                              GpuBuffer::Kind::DeviceLocal, "voxel heap");
    heap_ = HeapAllocator(capacity, kAlign);
    placed_.clear();
}

void VoxelStreamer::setTarget(std::shared_ptr<const VoxelSnapshot> snapshot)
{
    target_ = std::move(snapshot);
    beginTarget();
}

void VoxelStreamer::releaseLater(std::vector<std::pair<std::size_t, std::size_t>> ranges,
                                 std::function<void()> alsoRelease)
{
    const std::uint64_t generation = heapGeneration_;
    retired_.push_back({frame_ + std::uint64_t(options_.framesInFlight) + 1,
                        [this, ranges = std::move(ranges), alsoRelease = std::move(alsoRelease), generation] {
                            if (alsoRelease) alsoRelease();
                            // Ranges of a heap since replaced are not this allocator's.
                            if (generation != heapGeneration_) return;
                            for (auto [offset, size] : ranges) heap_.release(offset, size);
                        }});
}

void VoxelStreamer::dropAbandonedTiles()
{
    std::unordered_set<const TileData*> kept;
    for (const auto* snap : {residentSnapshot_.get(), target_.get()})
        if (snap)
            for (const auto& t : snap->tiles) kept.insert(t.get());
    std::vector<std::pair<std::size_t, std::size_t>> freed;
    for (auto it = placed_.begin(); it != placed_.end();) {
        if (kept.count(it->first)) {
            ++it;
            continue;
        }
        freed.emplace_back(it->second.offset, it->second.bytes);
        it = placed_.erase(it);
    }
    if (!freed.empty()) releaseLater(std::move(freed));
}

void VoxelStreamer::beginTarget()
{
    pending_.clear();
    dropAbandonedTiles();
    if (!target_) return;
    std::size_t needed = 0;
    for (const auto& t : target_->tiles)
        if (t && t->state == TileState::Surface && !placed_.count(t.get())) needed += BlobLayout(*t).total;
    if (needed > heap_.capacity() - heap_.used() || needed > heap_.largestFree()) {
        std::size_t all = 0;
        for (const auto& t : target_->tiles)
            if (t && t->state == TileState::Surface) all += BlobLayout(*t).total;
        growHeap(2 * all + options_.initialHeapBytes / 2);
    }
    for (const auto& t : target_->tiles) {
        if (!t || t->state != TileState::Surface) continue;
        auto it = placed_.find(t.get());
        if (it != placed_.end() && it->second.uploaded == it->second.bytes) continue;
        if (it == placed_.end()) {
            const BlobLayout blob(*t);
            const auto offset = heap_.allocate(blob.total);
            if (!offset) throw VulkanError("voxel heap: allocation", VK_ERROR_OUT_OF_DEVICE_MEMORY);
            Placement p;
            p.tile = t;
            p.offset = *offset;
            p.bytes = blob.total;
            p.entry.node = std::uint32_t(*offset / sizeof(voxel::Node));
            p.entry.leafIndirection = std::uint32_t((*offset + blob.leafIndirections) / sizeof(voxel::LeafIndirection));
            p.entry.leafData = std::uint32_t((*offset + blob.leafData) / sizeof(voxel::LeafData));
            p.entry.vertex = std::uint32_t((*offset + blob.vertices) / sizeof(voxel::Vertex));
            p.entry.levels = std::uint32_t(t->levels);
            p.entry.tape =
                t->tape.empty() ? voxel::kNoTape : std::uint32_t((*offset + blob.tape) / sizeof(std::uint32_t));
            placed_.emplace(t.get(), p);
        }
        pending_.push_back(t.get());
    }
}

std::size_t VoxelStreamer::stage(VkCommandBuffer cb, const void* data, std::size_t bytes, VkBuffer dst,
                                 std::size_t dstOffset)
{
    if (bytes == 0) return 0; // an empty part's tables: nothing to copy (a zero-size copy is invalid)
    if (stagingHead_ + bytes > staging_.size()) stagingHead_ = 0; // wrap: that space is frames old
    std::memcpy(static_cast<std::uint8_t*>(staging_.mapped()) + stagingHead_, data, bytes);
    VkBufferCopy region{stagingHead_, dstOffset, bytes};
    vkCmdCopyBuffer(cb, staging_.buffer(), dst, 1, &region);
    stagingHead_ += bytes;
    return bytes;
}

FrameUpload VoxelStreamer::recordFrame(VkCommandBuffer cb)
{
    ++frame_;
    while (!retired_.empty() && retired_.front().frame <= frame_) {
        retired_.front().release();
        retired_.pop_front();
    }
    // Each frame starts its own stretch of the ring.
    const std::size_t perFrame = options_.budgetBytesPerFrame;
    stagingHead_ = std::size_t(frame_ % std::uint64_t(std::max(1, options_.framesInFlight))) * perFrame;
    const std::size_t frameEnd = stagingHead_ + perFrame;

    FrameUpload up;
    std::size_t budget = perFrame;
    std::size_t done = 0;
    // Which bytes of which tiles go this frame, and where in the ring.
    struct Piece {
        const TileData* tile;
        std::size_t from, bytes, staging;
    };
    std::vector<Piece> pieces;
    std::vector<VkBufferCopy> regions;
    for (const TileData* t : pending_) {
        if (budget == 0) break;
        Placement& p = placed_.at(t);
        const std::size_t chunk = std::min(budget, p.bytes - p.uploaded);
        if (stagingHead_ + chunk > staging_.size()) stagingHead_ = 0; // wrap: that space is frames old
        pieces.push_back({t, p.uploaded, chunk, stagingHead_});
        regions.push_back({stagingHead_, p.offset + p.uploaded, chunk});
        stagingHead_ += chunk;
        p.uploaded += chunk;
        budget -= chunk;
        up.bytes += chunk;
        if (p.uploaded < p.bytes) break; // the budget ran out inside this tile
        ++done;
        ++up.tilesCompleted;
    }
    // The copies into the ring are the frame's CPU cost: spread them over the
    // cores. Isolated, so that this thread, while it waits, does not pick up
    // a voxelizer task and hold the frame for a tile's build.
    auto* ring = static_cast<std::uint8_t*>(staging_.mapped());
    tbb::this_task_arena::isolate([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces.size()), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const Piece& piece = pieces[i];
                copyBlobRange(*piece.tile, BlobLayout(*piece.tile), piece.from, piece.bytes, ring + piece.staging);
            }
        });
    });
    if (!regions.empty())
        vkCmdCopyBuffer(cb, staging_.buffer(), heapBuffer_->buffer(), std::uint32_t(regions.size()), regions.data());
    pending_.erase(pending_.begin(), pending_.begin() + long(done));
    up.tilesPending = pending_.size();

    if (target_ && pending_.empty() && residentSnapshot_ != target_) {
        // Every tile is on the device: build and upload the small tables.
        const GridLayout& g = target_->layout;
        std::vector<std::uint32_t> tiles(target_->tiles.size(), voxel::kEmptyTile);
        std::vector<TileEntry> entries;
        std::size_t bytes = 0;
        for (std::size_t i = 0; i < target_->tiles.size(); ++i) {
            const auto& t = target_->tiles[i];
            if (!t || t->state == TileState::Empty) continue;
            if (t->state == TileState::Full) {
                tiles[i] = voxel::kFullTile;
                continue;
            }
            tiles[i] = std::uint32_t(entries.size());
            entries.push_back(placed_.at(t.get()).entry);
            bytes += placed_.at(t.get()).bytes;
        }
        const std::size_t tableBytes = tiles.size() * 4 + entries.size() * sizeof(TileEntry);
        if (tableBytes <= budget || up.bytes == 0) { // a table alone may exceed a tiny budget; it goes whole
            auto tileBuf = std::make_shared<GpuBuffer>(ctx_, tiles.size() * 4,
                                                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                       GpuBuffer::Kind::DeviceLocal, "tile table");
            auto entryBuf = std::make_shared<GpuBuffer>(ctx_, entries.size() * sizeof(TileEntry),
                                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                        GpuBuffer::Kind::DeviceLocal, "tile entries");
            if (stagingHead_ + tableBytes > frameEnd && tableBytes <= staging_.size()) stagingHead_ = 0;
            if (tableBytes > staging_.size()) {
                // Larger than the whole ring: a dedicated staging buffer, freed frames later.
                auto extra = std::make_shared<GpuBuffer>(ctx_, tableBytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                         GpuBuffer::Kind::HostVisible, "table staging");
                std::memcpy(extra->mapped(), tiles.data(), tiles.size() * 4);
                std::memcpy(static_cast<std::uint8_t*>(extra->mapped()) + tiles.size() * 4, entries.data(),
                            entries.size() * sizeof(TileEntry));
                VkBufferCopy a{0, 0, tiles.size() * 4};
                if (!tiles.empty()) vkCmdCopyBuffer(cb, extra->buffer(), tileBuf->buffer(), 1, &a);
                if (!entries.empty()) {
                    VkBufferCopy b{tiles.size() * 4, 0, entries.size() * sizeof(TileEntry)};
                    vkCmdCopyBuffer(cb, extra->buffer(), entryBuf->buffer(), 1, &b);
                }
                retired_.push_back({frame_ + std::uint64_t(options_.framesInFlight) + 1, [extra] {}});
            } else {
                stage(cb, tiles.data(), tiles.size() * 4, tileBuf->buffer(), 0);
                if (!entries.empty())
                    stage(cb, entries.data(), entries.size() * sizeof(TileEntry), entryBuf->buffer(), 0);
            }
            up.bytes += tableBytes;
            // The old tables and the tiles only they used go after the frames in flight.
            auto oldTables = tables_;
            std::vector<std::pair<std::size_t, std::size_t>> freed;
            std::unordered_set<const TileData*> kept;
            if (residentSnapshot_) {
                kept.reserve(target_->tiles.size());
                for (const auto& t : target_->tiles) kept.insert(t.get());
            }
            if (residentSnapshot_)
                for (const auto& t : residentSnapshot_->tiles) {
                    if (!t || t->state != TileState::Surface) continue;
                    if (kept.count(t.get())) continue;
                    const auto it = placed_.find(t.get());
                    if (it == placed_.end()) continue; // lived in an older heap
                    freed.emplace_back(it->second.offset, it->second.bytes);
                    placed_.erase(it);
                }
            auto oldSnapshot = residentSnapshot_;
            auto oldHeaps = std::move(replacedHeaps_);
            replacedHeaps_.clear();
            releaseLater(std::move(freed), [oldTables, oldSnapshot, oldHeaps] {});
            tables_ = {tileBuf, entryBuf};
            residentSnapshot_ = target_;
            resident_.snapshotVersion = target_->version;
            resident_.layout = g;
            resident_.tiles = tileBuf->address();
            resident_.entries = entryBuf->address();
            resident_.heap = heapBuffer_->address();
            resident_.bytes = bytes + tableBytes;
            up.switched = true;
        }
    }
    if (up.bytes > 0) {
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0,
                             nullptr, 0, nullptr);
    }
    return up;
}

} // namespace kerf::vk

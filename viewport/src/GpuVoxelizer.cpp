#include "kerf/viewport/GpuVoxelizer.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/viewport/ShaderModules.hpp"
#include "kerf/viewport/VulkanError.hpp"
#include "kerf/voxelizer/BlockTapes.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"
#include "kerf/voxelizer/TileTape.hpp"
#include "kerf/voxelizer/VoxelFormat.hpp"
#include "kerf/voxelizer/WorkerArena.hpp"

#include "VoxelizeShared.h"
#include "voxelize.comp.inner.h"
#include "voxelize.comp.leaf.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>

namespace kerf::vk {

namespace {

struct VoxelizePush {
    std::uint64_t params;
    std::uint32_t pass, level, list, prune;
};

using Clock = std::chrono::steady_clock;
double millisecondsSince(Clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Every device buffer of a build: read and written by the shaders, copied when a pool grows.
constexpr VkBufferUsageFlags kStorage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
constexpr std::size_t kJobBytes = KERF_VOXELIZE_JOB_WORDS * sizeof(std::uint32_t);
constexpr std::size_t kMaxRecords = std::size_t(1) << 31; // pointers are 31 bits
// A level whose nodes could all have 64 children in this many bytes of
// nodes and jobs gets room for all of them.
constexpr std::size_t kAllChildrenBytes = std::size_t(64) << 20;

// What the host knows of one tile before the device builds it.
struct TilePlan {
    TileState state = TileState::Empty;
    std::vector<std::uint32_t> tape; // surface tiles: the encoded tape (empty: beyond the shaders' limits)
    std::optional<TileData> built;   // a surface tile whose tape the shaders cannot hold, built here
};

// Everything the host sends for one build, laid out in one staging buffer.
struct HostData {
    std::vector<std::uint32_t> plannedTiles; // the tiles planned (every tile for a whole build), in order
    std::vector<std::uint32_t> tiles;        // per planned tile: empty / full markers, host-built tiles' entries;
                                             // the device's surface tiles are set by the finish pass
    std::vector<TileEntry> entries;          // per surface tile
    std::vector<std::uint32_t> entryTiles;   // per surface tile: its tile
    std::vector<std::uint32_t> tapes;        // concatenated
    std::vector<std::uint32_t> roots;        // the first job list: each entry's root
    // Tiles the host built (tapes beyond the shaders' limits), in the format's
    // own tile-relative layout: they take the first records of each pool.
    std::vector<voxel::Node> nodes;
    std::vector<voxel::LeafIndirection> leafIndirections;
    std::vector<voxel::LeafData> leafData;
    std::vector<voxel::Vertex> vertices;
    std::size_t deviceTiles = 0; // the first entries: the device builds them
};

// The host's share of a build: every tile's interval over its box (grown by
// the hair the CPU voxelizer's boxes grow by) and, for a surface tile, its
// tape simplified for the box, rebased and encoded; a surface tile whose
// tape the shaders cannot hold is built here by the CPU's TileBuilder.
// The device's tiles come first among the entries, their roots the first
// nodes; the host's follow.
// Where a build's records start in each buffer: 0 for a whole build; the
// records already there for an update of some tiles (appended after them).
struct RecordBases {
    std::uint32_t entries = 0, nodes = 0, leafIndirections = 0, leafData = 0, vertices = 0, tapeWords = 0;
};

HostData planTiles(const Tape& tape, const GridLayout& layout, int levels, int threads, bool simplify,
                   const std::vector<long>* only = nullptr, const RecordBases& bases = {})
{
    HostData host;
    if (only)
        host.plannedTiles.assign(only->begin(), only->end());
    else {
        host.plannedTiles.resize(std::size_t(layout.tileCount()));
        for (std::size_t i = 0; i < host.plannedTiles.size(); ++i)
            host.plannedTiles[i] = std::uint32_t(i);
    }
    std::vector<TilePlan> plans(host.plannedTiles.size());
    {
        const BlockTapes blocks(tape, layout);
        tbb::enumerable_thread_specific<std::pair<IntervalEvaluator, Tape>> scratch;
        tbb::enumerable_thread_specific<TileBuildScratch> builders;
        tbb::task_arena arena = workerArena(threads);
        arena.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<long>(0, long(plans.size()), 16), [&](const tbb::blocked_range<long>& range) {
                    auto& [intervals, simple] = scratch.local();
                    for (long i = range.begin(); i != range.end(); ++i) {
                        const glm::ivec3 t = layout.tileCoord(long(host.plannedTiles[std::size_t(i)]));
                        const Aabb box = layout.tileBox(t);
                        const Interval iv = intervals.simplify(blocks.forTile(t),
                                                               box.grown(layout.tileSize * kIntervalBoxHair), simple);
                        TilePlan& plan = plans[std::size_t(i)];
                        if (iv.lo > 0.0) continue;
                        if (iv.hi < 0.0) {
                            plan.state = TileState::Full;
                            continue;
                        }
                        plan.state = TileState::Surface;
                        plan.tape = voxel::encodeTileTape((simplify ? simple : tape).rebased(box.min));
                        if (plan.tape.empty()) {
                            // Beyond the shaders' stack or length: the CPU's builder does this tile.
                            plan.built = buildTile(blocks.forTile(t), layout, t, levels, builders.local());
                            if (plan.built) plan.state = plan.built->state;
                        }
                    }
                });
        });
    }
    host.tiles.resize(plans.size());
    std::vector<std::size_t> hostBuilt;
    for (std::size_t i = 0; i < plans.size(); ++i) {
        const TilePlan& plan = plans[i];
        host.tiles[i] = plan.state == TileState::Full ? voxel::kFullTile : voxel::kEmptyTile;
        if (plan.state != TileState::Surface) continue;
        if (plan.built) {
            hostBuilt.push_back(i);
            continue;
        }
        // The roots are the first new nodes, in the order of the entries.
        const auto index = std::uint32_t(host.entries.size());
        TileEntry e;
        e.node = bases.nodes + index;
        e.levels = std::uint32_t(levels);
        e.tape = bases.tapeWords + std::uint32_t(host.tapes.size());
        host.tapes.insert(host.tapes.end(), plan.tape.begin(), plan.tape.end());
        host.entryTiles.push_back(host.plannedTiles[i]);
        host.roots.insert(host.roots.end(), {bases.entries + index, bases.nodes + index, 0u, 0u, 0u, 0u, 0u});
        host.entries.push_back(e);
    }
    const std::size_t surface = host.entries.size(); // built by the device
    host.deviceTiles = surface;
    for (const std::size_t i : hostBuilt) {
        const TileData& t = *plans[i].built;
        TileEntry e;
        e.node = bases.nodes + std::uint32_t(surface + host.nodes.size());
        e.leafIndirection = bases.leafIndirections + std::uint32_t(host.leafIndirections.size());
        e.leafData = bases.leafData + std::uint32_t(host.leafData.size());
        e.vertex = bases.vertices + std::uint32_t(host.vertices.size());
        e.levels = std::uint32_t(t.levels);
        host.tiles[i] = bases.entries + std::uint32_t(host.entries.size());
        host.entries.push_back(e);
        host.nodes.insert(host.nodes.end(), t.nodes.begin(), t.nodes.end());
        host.leafIndirections.insert(host.leafIndirections.end(), t.leafIndirections.begin(), t.leafIndirections.end());
        host.leafData.insert(host.leafData.end(), t.leafData.begin(), t.leafData.end());
        host.vertices.insert(host.vertices.end(), t.vertices.begin(), t.vertices.end());
    }
    return host;
}

// Transfers recorded after it see the writes of the transfers before it.
void transferBarrier(VkCommandBuffer cb)
{
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, nullptr, 0,
                         nullptr);
}

void computeBarrier(VkCommandBuffer cb)
{
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, nullptr,
                         0, nullptr);
}

std::size_t deviceLocalHeapBytes(const Context& ctx)
{
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice(), &mp);
    VkDeviceSize largest = 0;
    for (std::uint32_t i = 0; i < mp.memoryHeapCount; ++i)
        if (mp.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            largest = std::max(largest, mp.memoryHeaps[i].size);
    return std::size_t(largest);
}

// Why the shaders cannot run here (empty: they can). voxelize.comp builds
// its masks with subgroupOr in groups of at most KERF_VOXELIZE_GROUP / 4
// subgroups.
std::string subgroupShortfall(const Context& ctx)
{
    VkPhysicalDeviceSubgroupProperties subgroups{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &subgroups;
    vkGetPhysicalDeviceProperties2(ctx.physicalDevice(), &properties);
    if (!(subgroups.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
        !(subgroups.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT))
        return "this device has no subgroup arithmetic in compute shaders";
    if (subgroups.subgroupSize < 4)
        return "this device's subgroups have " + std::to_string(subgroups.subgroupSize) +
               " threads (the voxelizer needs 4 or more)";
    return {};
}

std::string megabytes(std::size_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MB"; }

} // namespace

std::size_t GpuVoxels::bytes() const
{
    return tiles.size() + entries.size() + nodeCount * sizeof(voxel::Node) +
           leafCount * sizeof(voxel::LeafIndirection) + populatedVoxels * sizeof(voxel::LeafData) +
           vertexCount * sizeof(voxel::Vertex) + tapes.size();
}

VoxelAddresses GpuVoxels::addresses(std::uint64_t version) const
{
    VoxelAddresses a;
    a.grid = layout;
    a.tiles = tiles.address();
    a.entries = entries.address();
    const auto at = [](const std::shared_ptr<GpuBuffer>& b) -> VkDeviceAddress { return b ? b->address() : 0; };
    a.nodes = at(nodes);
    a.leafIndirections = at(leafIndirections);
    a.leafData = at(leafData);
    a.vertices = at(vertices);
    a.tapes = tapes.address();
    a.version = version;
    return a;
}

FlatVoxelBuffers GpuVoxels::readBack(const Context& ctx) const
{
    FlatVoxelBuffers out;
    out.layout = layout;
    out.tiles.resize(std::size_t(layout.tileCount()));
    out.entries.resize(entryCount());
    out.nodes.resize(nodeCount);
    out.leafIndirections.resize(leafCount);
    out.leafData.resize(populatedVoxels);
    out.vertices.resize(vertexCount);
    out.tapes.resize(tapes.size() / sizeof(std::uint32_t));
    struct Part {
        const GpuBuffer* from;
        void* to;
        std::size_t bytes;
    };
    const Part parts[] = {{&tiles, out.tiles.data(), out.tiles.size() * 4},
                          {&entries, out.entries.data(), out.entries.size() * sizeof(TileEntry)},
                          {nodes.get(), out.nodes.data(), out.nodes.size() * sizeof(voxel::Node)},
                          {leafIndirections.get(), out.leafIndirections.data(),
                           out.leafIndirections.size() * sizeof(voxel::LeafIndirection)},
                          {leafData.get(), out.leafData.data(), out.leafData.size() * sizeof(voxel::LeafData)},
                          {vertices.get(), out.vertices.data(), out.vertices.size() * sizeof(voxel::Vertex)},
                          {&tapes, out.tapes.data(), out.tapes.size() * 4}};
    std::size_t total = 0;
    for (const Part& p : parts)
        total += p.bytes;
    const GpuBuffer staging(ctx, total, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GpuBuffer::Kind::Readback, "voxel read-back");
    ctx.submitAndWait([&](VkCommandBuffer cb) {
        std::size_t at = 0;
        for (const Part& p : parts) {
            if (p.bytes == 0) continue;
            const VkBufferCopy region{0, at, p.bytes};
            vkCmdCopyBuffer(cb, p.from->buffer(), staging.buffer(), 1, &region);
            at += p.bytes;
        }
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0,
                             nullptr);
    });
    std::size_t at = 0;
    for (const Part& p : parts) {
        std::memcpy(p.to, static_cast<const char*>(staging.mapped()) + at, p.bytes);
        at += p.bytes;
    }
    return out;
}

GpuVoxelizer::GpuVoxelizer(const Context& ctx)
    : ctx_(ctx),
      inner_(makeComputePipeline(ctx.device(), kVoxelizeInnerComp, sizeof(kVoxelizeInnerComp), sizeof(VoxelizePush),
                                 "voxelize.comp (inner)")),
      leaf_(makeComputePipeline(ctx.device(), kVoxelizeLeafComp, sizeof(kVoxelizeLeafComp), sizeof(VoxelizePush),
                                "voxelize.comp (leaf)")),
      unsupported_(subgroupShortfall(ctx))
{
    // The scratch a part of a few thousand surface tiles needs, made with
    // the pipelines rather than in the first build.
    constexpr std::size_t kTiles = 8192;
    scratch(scratch_.entryTiles, kTiles * 4, kStorage, GpuBuffer::Kind::DeviceLocal);
    scratch(scratch_.entryVoxels, kTiles * 4, kStorage, GpuBuffer::Kind::DeviceLocal);
    scratch(scratch_.counters, KERF_COUNT_WORDS * 4, kStorage, GpuBuffer::Kind::DeviceLocal);
    scratch(scratch_.params, sizeof(gpu::VoxelizeParams), kStorage, GpuBuffer::Kind::DeviceLocal);
    scratch(scratch_.countsBack, KERF_COUNT_WORDS * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GpuBuffer::Kind::Readback);
    scratch(scratch_.staging, std::size_t(1) << 20, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GpuBuffer::Kind::HostVisible);
}

GpuVoxelizer::~GpuVoxelizer() = default;

void GpuVoxelizer::recycle(GpuVoxels&& old)
{
    // Pools another build shares (an update's base and the update) stay with it.
    for (std::shared_ptr<GpuBuffer>* b : {&old.nodes, &old.leafIndirections, &old.leafData, &old.vertices})
        if (*b && b->use_count() == 1) giveSpare(std::move(**b));
    old = GpuVoxels{};
}

void GpuVoxelizer::giveSpare(GpuBuffer&& buffer)
{
    if (buffer.size() < (std::size_t(1) << 20)) return; // small ones cost little to make
    spare_.push_back(std::move(buffer));
    // Keep the largest few: what a rebuild of the same part will ask for.
    std::sort(spare_.begin(), spare_.end(), [](const GpuBuffer& a, const GpuBuffer& b) { return a.size() > b.size(); });
    if (spare_.size() > kSpareBuffers) spare_.resize(kSpareBuffers);
}

GpuBuffer GpuVoxelizer::takeSpare(std::size_t bytes)
{
    // The smallest spare that holds `bytes`, unless it is more than twice as large.
    for (std::size_t i = spare_.size(); i-- > 0;) {
        if (spare_[i].size() < bytes) continue;
        if (spare_[i].size() > 2 * bytes + (std::size_t(1) << 20)) return {};
        GpuBuffer b = std::move(spare_[i]);
        spare_.erase(spare_.begin() + long(i));
        return b;
    }
    return {};
}

const GpuBuffer& GpuVoxelizer::scratch(GpuBuffer& buffer, std::size_t bytes, VkBufferUsageFlags usage,
                                       GpuBuffer::Kind kind)
{
    // Grown by half again beyond the need, so that a slightly larger part does not make another.
    // (Made even for 0 bytes: every buffer a submission names must exist.)
    if (buffer.size() == 0 || buffer.size() < bytes)
        buffer = GpuBuffer(ctx_, bytes + bytes / 2, usage, kind, "voxelizer scratch");
    return buffer;
}

std::optional<GpuVoxels> GpuVoxelizer::build(const Tape& tape, const GridLayout& layout,
                                             const GpuVoxelizeOptions& options, GpuVoxelizeReport* report)
{
    return make(tape, layout, options, report, nullptr, nullptr);
}

std::optional<GpuVoxels> GpuVoxelizer::update(const GpuVoxels& base, const Tape& tape,
                                              const std::vector<long>& dirtyTiles, const GpuVoxelizeOptions& options,
                                              GpuVoxelizeReport* report)
{
    const int levels = std::clamp(options.levels > 0 ? options.levels : base.layout.levels, 1, voxel::kMaxLevels);
    // Rebuilt whole: a different depth, many dirty tiles (as cheap whole),
    // or pools that the replaced tiles have filled to twice a whole build.
    const bool whole = levels != base.levels || 4 * dirtyTiles.size() > std::size_t(base.layout.tileCount()) ||
                       base.nodeCount > 2 * std::max<std::size_t>(base.wholeBuildNodes, 1024);
    if (whole) return make(tape, base.layout, options, report, nullptr, nullptr);
    return make(tape, base.layout, options, report, &base, &dirtyTiles);
}

std::optional<GpuVoxels> GpuVoxelizer::make(const Tape& tape, const GridLayout& layout,
                                            const GpuVoxelizeOptions& options, GpuVoxelizeReport* report,
                                            const GpuVoxels* base, const std::vector<long>* dirty)
{
    GpuVoxelizeReport local;
    GpuVoxelizeReport& r = report ? *report : local;
    r = {};
    const int levels = std::clamp(options.levels > 0 ? options.levels : layout.levels, 1, voxel::kMaxLevels);
    // An update appends the dirty tiles' records after the base's, in its
    // pools (shared: the base stays readable, the frames on screen read it),
    // and copies its tile table, entries and tapes.
    RecordBases bases;
    if (base) {
        bases.entries = std::uint32_t(base->entryCount());
        bases.nodes = std::uint32_t(base->nodeCount);
        bases.leafIndirections = std::uint32_t(base->leafCount);
        bases.leafData = std::uint32_t(base->populatedVoxels);
        bases.vertices = std::uint32_t(base->vertexCount);
        bases.tapeWords = std::uint32_t(base->tapes.size() / 4);
    }
    r.updatedTiles = dirty ? dirty->size() : 0;
    if (!unsupported_.empty()) {
        r.whyNot = unsupported_;
        return std::nullopt;
    }

    // The host's share: tile intervals in double, exactly as the CPU voxelizer.
    const auto prepareStart = Clock::now();
    HostData host = planTiles(tape, layout, levels, options.threads, options.simplifyTileTapes, dirty, bases);
    const std::size_t surface = host.deviceTiles;
    r.hostBuiltTiles = host.entries.size() - surface;
    r.prepareMilliseconds = millisecondsSince(prepareStart);

    GpuVoxels out;
    out.layout = layout;
    out.levels = levels;
    out.surfaceTiles = host.entries.size();
    const std::size_t budget = options.memoryBudget > 0 ? options.memoryBudget : deviceLocalHeapBytes(ctx_) / 2;
    const std::size_t perBuffer = ctx_.maxAllocationBytes();
    // What the leaf level will probably ask for: the last build's voxels per
    // leaf node processed (empty leaves included: a leaf level's nodes are
    // what the host knows before it runs) and vertices per voxel, a little
    // above. A fresh voxelizer takes what the chair (1 to 0.1 mm) and the
    // showcase (0.1, 0.01) have, 13.2 to 14.2 voxels per leaf node and 3.12
    // to 3.13 vertices per voxel, a little above again: its leaf level then
    // fits the first time without pools far beyond the need (making them is
    // a third of a cold build).
    const double voxelsPerLeafJob = (voxelsPerLeafJob_ > 0.0 ? voxelsPerLeafJob_ : 14.3) * 1.05;
    const double verticesPerVoxel = (verticesPerVoxel_ > 0.0 ? verticesPerVoxel_ : 3.15) * 1.05;

    const auto allocateStart = Clock::now();
    out.tiles = GpuBuffer(ctx_, std::size_t(layout.tileCount()) * 4, kStorage, GpuBuffer::Kind::DeviceLocal, "tiles");
    out.entries = GpuBuffer(ctx_, (bases.entries + host.entries.size()) * sizeof(TileEntry), kStorage,
                            GpuBuffer::Kind::DeviceLocal, "entries");
    out.tapes =
        GpuBuffer(ctx_, (bases.tapeWords + host.tapes.size()) * 4, kStorage, GpuBuffer::Kind::DeviceLocal, "tapes");
    // The build's own scratch: kept by the voxelizer between builds (each
    // allocation costs a fraction of a millisecond; a build made nine).
    const GpuBuffer& entryTiles = scratch(scratch_.entryTiles, surface * 4, kStorage, GpuBuffer::Kind::DeviceLocal);
    const GpuBuffer& entryVoxels = scratch(scratch_.entryVoxels, surface * 4, kStorage, GpuBuffer::Kind::DeviceLocal);
    const GpuBuffer& counters = scratch(scratch_.counters, KERF_COUNT_WORDS * 4, kStorage, GpuBuffer::Kind::DeviceLocal);
    const GpuBuffer& params =
        scratch(scratch_.params, sizeof(gpu::VoxelizeParams), kStorage, GpuBuffer::Kind::DeviceLocal);
    const GpuBuffer& countsBack = scratch(scratch_.countsBack, KERF_COUNT_WORDS * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                          GpuBuffer::Kind::Readback);

    // The pools. Each level runs in its own submission, and the host reads
    // the counters after it: a level that asked for more records than a pool
    // holds (the shaders write nothing past the end, but every claim counts)
    // has its pools grown to exactly what it asked, their contents kept, and
    // runs again. So a build needs at most one rerun per level, and what it
    // holds is known before each level starts.
    struct Pool {
        std::shared_ptr<GpuBuffer> buffer = std::make_shared<GpuBuffer>(); // shared with the base of an update
        std::size_t capacity = 0;                                          // records
        std::size_t recordBytes = 0;
        const char* name = "";
    };
    Pool nodes{.recordBytes = sizeof(voxel::Node), .name = "nodes"},
        leafIndirections{.recordBytes = sizeof(voxel::LeafIndirection), .name = "leaves"},
        leafData{.recordBytes = sizeof(voxel::LeafData), .name = "voxels"},
        vertices{.recordBytes = sizeof(voxel::Vertex), .name = "vertices"},
        jobs[2] = {{.recordBytes = kJobBytes, .name = "jobs"}, {.recordBytes = kJobBytes, .name = "jobs"}};
    Pool* const all[] = {&nodes, &leafIndirections, &leafData, &vertices, &jobs[0], &jobs[1]};
    if (base) {
        const std::pair<Pool*, const std::shared_ptr<GpuBuffer>*> shared[] = {
            {&nodes, &base->nodes},
            {&leafIndirections, &base->leafIndirections},
            {&leafData, &base->leafData},
            {&vertices, &base->vertices}};
        for (const auto& [pool, buffer] : shared) {
            pool->buffer = *buffer;
            pool->capacity = (*buffer)->size() / pool->recordBytes;
        }
    }
    const auto poolBytes = [&] {
        std::size_t b = 0;
        for (const Pool* p : all)
            b += p->capacity * p->recordBytes;
        return b;
    };
    struct Copy {
        std::shared_ptr<GpuBuffer> from, to;
        std::size_t bytes;
    };
    std::vector<Copy> copies;                        // contents to carry into grown pools, in the next submission
    std::vector<std::shared_ptr<GpuBuffer>> retired; // pools replaced: kept until that submission has run
    // A pool no other build shares goes to the spares.
    const auto release = [&](std::shared_ptr<GpuBuffer>& b) {
        if (b && b.use_count() == 1) giveSpare(std::move(*b));
        b.reset();
    };
    // Grows `p` to at least `records`, keeping its first `keep` records; false
    // when over the budget. A `guess` (what a level will probably ask for) is
    // cut to what the budget allows instead: only a level's real need refuses.
    const auto grow = [&](Pool& p, std::size_t records, std::size_t keep, bool guess = false) {
        if (guess) {
            const std::size_t room = budget > poolBytes() ? (budget - poolBytes()) / p.recordBytes + p.capacity : 0;
            records = std::min({records, kMaxRecords, perBuffer / p.recordBytes, room});
        }
        if (records <= p.capacity) return true;
        records = std::max<std::size_t>(records, 16);
        if (records > kMaxRecords || records * p.recordBytes > perBuffer ||
            poolBytes() + (records - p.capacity) * p.recordBytes > budget) {
            r.whyNot = "the voxels need more than " + megabytes(poolBytes() + (records - p.capacity) * p.recordBytes) +
                       " of device memory (the budget is " + megabytes(budget) + ", one buffer at most " +
                       megabytes(perBuffer) + "; the " + p.name + " alone ask for " +
                       megabytes(records * p.recordBytes) + ")";
            return false;
        }
        auto bigger = std::make_shared<GpuBuffer>(takeSpare(records * p.recordBytes));
        if (bigger->size() == 0) {
            // Made one at a time: made on threads of their own, the chair's
            // pools at 0.25 mm took as long (the driver serializes them).
            const auto made = Clock::now();
            *bigger = GpuBuffer(ctx_, records * p.recordBytes, kStorage, GpuBuffer::Kind::DeviceLocal, p.name);
            r.poolAllocateMilliseconds += millisecondsSince(made);
        }
        if (keep > 0) copies.push_back({p.buffer, bigger, keep * p.recordBytes});
        retired.push_back(std::move(p.buffer));
        p.buffer = std::move(bigger);
        p.capacity = p.buffer->size() / p.recordBytes;
        return true;
    };
    // The host's tiles take the first records of each pool; the device's
    // roots are the first nodes.
    std::uint32_t count[KERF_COUNT_WORDS] = {};
    count[KERF_COUNT_NODES] = bases.nodes + std::uint32_t(surface + host.nodes.size());
    count[KERF_COUNT_LEAF_INDIRECTIONS] = bases.leafIndirections + std::uint32_t(host.leafIndirections.size());
    count[KERF_COUNT_LEAF_DATA] = bases.leafData + std::uint32_t(host.leafData.size());
    count[KERF_COUNT_VERTICES] = bases.vertices + std::uint32_t(host.vertices.size());
    count[KERF_COUNT_JOBS] = std::uint32_t(surface);
    const std::uint32_t started[KERF_COUNT_WORDS] = {count[0], count[1], count[2], count[3]};
    // Every level's nodes are about 16 times the last's (a surface, four
    // times finer each way); the leaves' records as `voxelsPerLeafJob` and
    // `verticesPerVoxel` (above) say.
    const double guessScale = std::clamp(options.poolGuessScale, 1e-3, 1.0);
    std::size_t leafJobs = 0;
    if (!grow(nodes, count[KERF_COUNT_NODES] + 16 * surface, bases.nodes) || !grow(jobs[0], surface, 0) ||
        !grow(jobs[1], 16 * surface, 0) ||
        !grow(leafIndirections, count[KERF_COUNT_LEAF_INDIRECTIONS] + 1, bases.leafIndirections) ||
        !grow(leafData, count[KERF_COUNT_LEAF_DATA] + 1, bases.leafData) ||
        !grow(vertices, count[KERF_COUNT_VERTICES] + 1, bases.vertices))
        return std::nullopt;
    if (!base) {
        for (auto& b : retired)
            release(b);
        retired.clear();
    }

    struct Upload {
        const void* data;
        std::size_t bytes;
        VkBuffer to;
        std::size_t at = 0; // bytes into `to`
    };
    // A whole build sends the tile table; an update copies its base's and
    // sets its planned tiles (below).
    const Upload uploads[] = {
        {host.tiles.data(), base ? 0 : host.tiles.size() * 4, out.tiles.buffer()},
        {host.entries.data(), host.entries.size() * sizeof(TileEntry), out.entries.buffer(),
         bases.entries * sizeof(TileEntry)},
        {host.tapes.data(), host.tapes.size() * 4, out.tapes.buffer(), bases.tapeWords * 4u},
        {host.entryTiles.data(), surface * 4, entryTiles.buffer()},
        {host.roots.data(), host.roots.size() * 4, jobs[0].buffer->buffer()},
        {host.nodes.data(), host.nodes.size() * sizeof(voxel::Node), nodes.buffer->buffer(),
         (bases.nodes + surface) * sizeof(voxel::Node)},
        {host.leafIndirections.data(), host.leafIndirections.size() * sizeof(voxel::LeafIndirection),
         leafIndirections.buffer->buffer(), bases.leafIndirections * sizeof(voxel::LeafIndirection)},
        {host.leafData.data(), host.leafData.size() * sizeof(voxel::LeafData), leafData.buffer->buffer(),
         bases.leafData * sizeof(voxel::LeafData)},
        {host.vertices.data(), host.vertices.size() * sizeof(voxel::Vertex), vertices.buffer->buffer(),
         bases.vertices * sizeof(voxel::Vertex)}};
    std::size_t stagingBytes = 0;
    for (const Upload& u : uploads)
        stagingBytes += u.bytes;
    const GpuBuffer& staging =
        scratch(scratch_.staging, stagingBytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GpuBuffer::Kind::HostVisible);
    r.allocateMilliseconds = millisecondsSince(allocateStart);
    const auto uploadStart = Clock::now();
    {
        std::size_t at = 0;
        for (const Upload& u : uploads) {
            if (u.bytes > 0) std::memcpy(static_cast<char*>(staging.mapped()) + at, u.data, u.bytes);
            at += u.bytes;
        }
    }
    r.uploadMilliseconds = millisecondsSince(uploadStart);

    const std::uint32_t row = std::min<std::uint32_t>(ctx_.properties().limits.maxComputeWorkGroupCount[0], 65535u);
    const auto paramsNow = [&] {
        gpu::VoxelizeParams p{};
        p.tapes = out.tapes.address();
        p.entries = out.entries.address();
        p.entryTiles = entryTiles.address();
        p.entryVoxels = entryVoxels.address();
        p.tiles = out.tiles.address();
        p.nodes = nodes.buffer->address();
        p.leafIndirections = leafIndirections.buffer->address();
        p.leafData = leafData.buffer->address();
        p.vertices = vertices.buffer->address();
        p.jobs0 = jobs[0].buffer->address();
        p.jobs1 = jobs[1].buffer->address();
        p.firstEntry = bases.entries;
        p.counters = counters.address();
        p.capacity = {std::uint32_t(nodes.capacity), std::uint32_t(leafIndirections.capacity),
                      std::uint32_t(leafData.capacity), std::uint32_t(vertices.capacity)};
        p.limits = {std::uint32_t(jobs[0].capacity), std::uint32_t(surface), std::uint32_t(levels),
                    std::uint32_t(jobs[1].capacity)};
        const double voxelMm = layout.tileSize / std::pow(4.0, levels);
        int exponent = 0;
        const double fraction = std::frexp(voxelMm, &exponent);
        p.voxelMantissa = std::uint64_t(std::llround(std::ldexp(fraction, 40)));
        // The interval boxes grow by a hair so that float corners never cut them short.
        p.sizes = {float(voxelMm), float(layout.tileSize), float(layout.tileSize * kIntervalBoxHair),
                   float(exponent - 40)};
        return p;
    };
    // One submission: carried contents, parameters and counters, then `record`, then the counters back.
    const auto submit = [&](bool first, const std::function<void(VkCommandBuffer)>& record) {
        const gpu::VoxelizeParams p = paramsNow();
        const auto deviceStart = Clock::now();
        ctx_.submitAndWait([&](VkCommandBuffer cb) {
            if (first) {
                if (base) {
                    // The base's tile table, entries and tapes first; the planned tiles' words after.
                    const std::pair<const GpuBuffer*, const GpuBuffer*> carried[] = {
                        {&base->tiles, &out.tiles}, {&base->entries, &out.entries}, {&base->tapes, &out.tapes}};
                    for (const auto& [from, to] : carried)
                        if (from->size() > 0) {
                            const VkBufferCopy region{0, 0, from->size()};
                            vkCmdCopyBuffer(cb, from->buffer(), to->buffer(), 1, &region);
                        }
                    transferBarrier(cb);
                    for (std::size_t i = 0; i < host.plannedTiles.size(); ++i)
                        vkCmdUpdateBuffer(cb, out.tiles.buffer(), host.plannedTiles[i] * 4u, 4, &host.tiles[i]);
                }
                std::size_t at = 0;
                for (const Upload& u : uploads) {
                    if (u.bytes == 0) continue;
                    const VkBufferCopy region{at, u.at, u.bytes};
                    vkCmdCopyBuffer(cb, staging.buffer(), u.to, 1, &region);
                    at += u.bytes;
                }
                vkCmdFillBuffer(cb, entryVoxels.buffer(), 0, VK_WHOLE_SIZE, 0);
                transferBarrier(cb);
            }
            // Grown pools, in the order they grew: a pool grown twice before
            // a submission is copied on from the copy before (and uploads
            // into the older buffer carried along).
            for (const Copy& c : copies) {
                const VkBufferCopy region{0, 0, c.bytes};
                vkCmdCopyBuffer(cb, c.from->buffer(), c.to->buffer(), 1, &region);
                transferBarrier(cb);
            }
            vkCmdUpdateBuffer(cb, params.buffer(), 0, sizeof p, &p);
            vkCmdUpdateBuffer(cb, counters.buffer(), 0, sizeof count, count);
            computeBarrier(cb);
            record(cb);
            computeBarrier(cb);
            const VkBufferCopy region{0, 0, KERF_COUNT_WORDS * 4};
            vkCmdCopyBuffer(cb, counters.buffer(), countsBack.buffer(), 1, &region);
            VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr,
                                 0, nullptr);
        });
        r.submissionMilliseconds.push_back(millisecondsSince(deviceStart));
        r.deviceMilliseconds += r.submissionMilliseconds.back();
        copies.clear();
        for (auto& b : retired)
            release(b);
        retired.clear();
    };
    const auto push = [&](VkCommandBuffer cb, std::uint32_t pass, int level) {
        const VoxelizePush pc{params.address(), pass, std::uint32_t(level), std::uint32_t(level & 1),
                              options.pruneNodeTapes ? 1u : 0u};
        const ComputePipeline& pipeline = pass == KERF_PASS_INNER ? inner_ : leaf_;
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline);
        vkCmdPushConstants(cb, pipeline.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
    };

    // Each surface tile's word: its entry, or empty or full when no voxel of it was populated.
    const auto recordFinish = [&](VkCommandBuffer cb) {
        if (surface == 0) return;
        push(cb, KERF_PASS_FINISH, 0);
        vkCmdDispatch(cb, std::uint32_t((surface + KERF_VOXELIZE_GROUP - 1) / KERF_VOXELIZE_GROUP), 1, 1);
    };
    bool first = true, finished = false;
    for (int level = 0; level < levels && surface > 0; ++level) {
        if (options.cancel && options.cancel->load(std::memory_order_relaxed)) {
            // Asked to stop (a newer request): the pools serve the next build.
            for (Pool* p : all)
                release(p->buffer);
            for (auto& b : retired)
                release(b);
            r.cancelled = true;
            r.whyNot = "cancelled";
            return std::nullopt;
        }
        const bool leaf = level == levels - 1;
        const int in = level & 1, next = 1 - in;
        const std::uint32_t jobsIn = count[KERF_COUNT_JOBS + in];
        if (jobsIn == 0) break;
        r.levelJobs.push_back(jobsIn);
        // What this level will probably ask for.
        bool fits = true;
        if (leaf) {
            leafJobs = jobsIn;
            const std::size_t voxelsGuess = std::size_t(voxelsPerLeafJob * guessScale * jobsIn);
            fits =
                grow(leafIndirections, count[KERF_COUNT_LEAF_INDIRECTIONS] + jobsIn,
                     count[KERF_COUNT_LEAF_INDIRECTIONS], true) &&
                grow(leafData, count[KERF_COUNT_LEAF_DATA] + voxelsGuess, count[KERF_COUNT_LEAF_DATA], true) &&
                grow(vertices, count[KERF_COUNT_VERTICES] + std::size_t(verticesPerVoxel * double(voxelsGuess)),
                     count[KERF_COUNT_VERTICES], true);
        } else {
            // Learned, else 20 (a surface, four times finer each way, has
            // about 16: measured 15.9 to 17.9 on the chair and the showcase,
            // and a level run twice costs more than the room); where all 64
            // children of every node cost little (the coarse levels), room
            // for all of them: such a level never runs twice.
            const double ratio =
                childrenPerNode_[std::size_t(level)] > 0.0 ? 1.1 * childrenPerNode_[std::size_t(level)] : 20.0;
            std::size_t children = std::size_t(std::ceil(ratio * guessScale * double(jobsIn)));
            if (guessScale >= 1.0 && 64 * std::size_t(jobsIn) * (sizeof(voxel::Node) + kJobBytes) <= kAllChildrenBytes)
                children = 64 * std::size_t(jobsIn);
            fits = grow(nodes, count[KERF_COUNT_NODES] + children, count[KERF_COUNT_NODES], true) &&
                   grow(jobs[next], children, 0, true);
        }
        if (!fits) return std::nullopt;
        for (int run = 0;; ++run) {
            count[KERF_COUNT_JOBS + next] = 0;
            submit(first, [&](VkCommandBuffer cb) {
                push(cb, leaf ? KERF_PASS_LEAF : KERF_PASS_INNER, level);
                vkCmdDispatch(cb, std::min(jobsIn, row), (jobsIn + row - 1) / row, 1);
                if (leaf) {
                    // The tile words in the same submission (a leaf level run
                    // again runs it again: it only reads the voxel counts).
                    computeBarrier(cb);
                    recordFinish(cb);
                }
            });
            finished = leaf;
            first = false;
            std::uint32_t back[KERF_COUNT_WORDS];
            std::memcpy(back, countsBack.mapped(), sizeof back);
            // Every claim counted, written or not: these are exactly what the level asked for.
            const bool ran =
                back[KERF_COUNT_NODES] <= nodes.capacity && back[KERF_COUNT_JOBS + next] <= jobs[next].capacity &&
                back[KERF_COUNT_LEAF_INDIRECTIONS] <= leafIndirections.capacity &&
                back[KERF_COUNT_LEAF_DATA] <= leafData.capacity && back[KERF_COUNT_VERTICES] <= vertices.capacity;
            if (ran) {
                if (!leaf) childrenPerNode_[std::size_t(level)] = double(back[KERF_COUNT_JOBS + next]) / double(jobsIn);
                std::memcpy(count, back, sizeof count);
                break;
            }
            if (run > 0) {
                r.whyNot = "a level of the voxelization asked for more records on its second run than on its first";
                return std::nullopt;
            }
            ++r.levelReruns;
            if (!grow(nodes, back[KERF_COUNT_NODES], count[KERF_COUNT_NODES]) ||
                !grow(jobs[next], back[KERF_COUNT_JOBS + next], 0) ||
                !grow(leafIndirections, back[KERF_COUNT_LEAF_INDIRECTIONS], count[KERF_COUNT_LEAF_INDIRECTIONS]) ||
                !grow(leafData, back[KERF_COUNT_LEAF_DATA], count[KERF_COUNT_LEAF_DATA]) ||
                !grow(vertices, back[KERF_COUNT_VERTICES], count[KERF_COUNT_VERTICES]))
                return std::nullopt;
        }
    }
    if (!finished) submit(first, recordFinish); // no leaf level ran

    release(jobs[0].buffer);
    release(jobs[1].buffer);
    out.nodes = std::move(nodes.buffer);
    out.leafIndirections = std::move(leafIndirections.buffer);
    out.leafData = std::move(leafData.buffer);
    out.vertices = std::move(vertices.buffer);
    out.nodeCount = count[KERF_COUNT_NODES];
    out.leafCount = count[KERF_COUNT_LEAF_INDIRECTIONS];
    out.populatedVoxels = count[KERF_COUNT_LEAF_DATA];
    out.vertexCount = count[KERF_COUNT_VERTICES];
    out.wholeBuildNodes = base ? base->wholeBuildNodes : out.nodeCount;
    r.poolBytes = poolBytes();
    r.prunedLeafJobs = count[KERF_COUNT_PRUNED_LEAF_JOBS]; // (zero at the start of every build)
    const std::size_t deviceVoxels = out.populatedVoxels - started[KERF_COUNT_LEAF_DATA];
    if (leafJobs > 0 && deviceVoxels > 0) {
        voxelsPerLeafJob_ = double(deviceVoxels) / double(leafJobs);
        verticesPerVoxel_ = double(out.vertexCount - started[KERF_COUNT_VERTICES]) / double(deviceVoxels);
    }
    return out;
}

} // namespace kerf::vk

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
#include "voxelize.comp.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

namespace kerf::vk {

namespace {

struct VoxelizePush {
    std::uint64_t params;
    std::uint32_t pass, level, list, pad;
};

using Clock = std::chrono::steady_clock;
double millisecondsSince(Clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

constexpr std::size_t kJobBytes = KERF_VOXELIZE_JOB_WORDS * sizeof(std::uint32_t);
constexpr std::size_t kMaxRecords = std::size_t(1) << 31; // pointers are 31 bits

// What the host knows of one tile before the device builds it.
struct TilePlan {
    TileState state = TileState::Empty;
    std::vector<std::uint32_t> tape; // surface tiles: the encoded tape (empty: beyond the shaders' limits)
    std::optional<TileData> built;   // a surface tile whose tape the shaders cannot hold, built here
};

// Everything the host sends for one build, laid out in one staging buffer.
struct HostData {
    std::vector<std::uint32_t> tiles;      // per tile: empty / full markers; surface tiles are set by the finish pass
    std::vector<TileEntry> entries;        // per surface tile
    std::vector<std::uint32_t> entryTiles; // per surface tile: its tile
    std::vector<std::uint32_t> tapes;      // concatenated
    std::vector<std::uint32_t> roots;      // the first job list: each entry's root
    // Tiles the host built (tapes beyond the shaders' limits), in the format's
    // own tile-relative layout: they take the first records of each pool.
    std::vector<voxel::Node> nodes;
    std::vector<voxel::LeafIndirection> leafIndirections;
    std::vector<voxel::LeafData> leafData;
    std::vector<voxel::Vertex> vertices;
};

void computeBarrier(VkCommandBuffer cb)
{
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT |
                       VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                             VK_PIPELINE_STAGE_TRANSFER_BIT,
                         0, 1, &mb, 0, nullptr, 0, nullptr);
}

std::size_t deviceLocalHeapBytes(const Context& ctx)
{
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice(), &mp);
    VkDeviceSize largest = 0;
    for (std::uint32_t i = 0; i < mp.memoryHeapCount; ++i)
        if (mp.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) largest = std::max(largest, mp.memoryHeaps[i].size);
    return std::size_t(largest);
}

std::string megabytes(std::size_t bytes)
{
    return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MB";
}

} // namespace

std::size_t GpuVoxels::bytes() const
{
    return tiles.size() + surfaceTiles * sizeof(TileEntry) + nodeCount * sizeof(voxel::Node) +
           leafCount * sizeof(voxel::LeafIndirection) + populatedVoxels * sizeof(voxel::LeafData) +
           vertexCount * sizeof(voxel::Vertex) + tapes.size();
}

VoxelAddresses GpuVoxels::addresses(std::uint64_t version) const
{
    VoxelAddresses a;
    a.grid = layout;
    a.tiles = tiles.address();
    a.entries = entries.address();
    a.nodes = nodes.address();
    a.leafIndirections = leafIndirections.address();
    a.leafData = leafData.address();
    a.vertices = vertices.address();
    a.tapes = tapes.address();
    a.version = version;
    return a;
}

FlatVoxelBuffers GpuVoxels::readBack(const Context& ctx) const
{
    FlatVoxelBuffers out;
    out.layout = layout;
    out.tiles.resize(std::size_t(layout.tileCount()));
    out.entries.resize(surfaceTiles);
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
                          {&nodes, out.nodes.data(), out.nodes.size() * sizeof(voxel::Node)},
                          {&leafIndirections, out.leafIndirections.data(),
                           out.leafIndirections.size() * sizeof(voxel::LeafIndirection)},
                          {&leafData, out.leafData.data(), out.leafData.size() * sizeof(voxel::LeafData)},
                          {&vertices, out.vertices.data(), out.vertices.size() * sizeof(voxel::Vertex)},
                          {&tapes, out.tapes.data(), out.tapes.size() * 4}};
    std::size_t total = 0;
    for (const Part& p : parts) total += p.bytes;
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

std::size_t GpuVoxelizer::Pools::bytes() const
{
    return nodes * sizeof(voxel::Node) + leafIndirections * sizeof(voxel::LeafIndirection) +
           leafData * sizeof(voxel::LeafData) + vertices * sizeof(voxel::Vertex) + 2 * jobs * kJobBytes;
}

GpuVoxelizer::GpuVoxelizer(const Context& ctx) : ctx_(ctx)
{
    VkDevice dev = ctx.device();
    module_ = makeShaderModule(dev, kVoxelizeComp, sizeof(kVoxelizeComp), "vkCreateShaderModule (voxelize.comp)");
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(VoxelizePush)};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &range;
    VkPipelineLayout pl;
    check(vkCreatePipelineLayout(dev, &plci, nullptr, &pl), "vkCreatePipelineLayout (voxelizer)");
    layout_ = PipelineLayout(dev, pl);
    VkComputePipelineCreateInfo cpci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = module_;
    cpci.stage.pName = "main";
    cpci.layout = layout_;
    VkPipeline p;
    check(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &cpci, nullptr, &p), "vkCreateComputePipelines (voxelizer)");
    pipeline_ = Pipeline(dev, p);
}

GpuVoxelizer::~GpuVoxelizer() = default;

GpuVoxelizer::Pools GpuVoxelizer::firstGuess(std::size_t surfaceTiles, int levels) const
{
    // A plane through a tile of n x n x n voxels populates about n^2 of them;
    // most surface tiles hold far less (furniture: 5 to 10 %). What the
    // last build at this depth needed wins over the guess.
    const double n = std::pow(4.0, levels);
    const double perTile = voxelsPerTile_[std::size_t(levels)] > 0.0 ? 1.25 * voxelsPerTile_[std::size_t(levels)]
                                                                       : 0.1 * n * n;
    const double voxels = std::max(65536.0, perTile * double(surfaceTiles));
    Pools p;
    const auto records = [](double v) { return std::size_t(std::min(v, double(kMaxRecords))); };
    p.leafData = records(voxels);
    p.vertices = records(3.2 * voxels);                                 // the chair: 2.9 per voxel
    p.leafIndirections = records(voxels / 4.0);                         // about 16 voxels per leaf
    p.nodes = records(voxels / 2.0 + double(surfaceTiles));            // leaves, empty leaves and inner nodes
    p.jobs = std::max<std::size_t>(p.nodes, surfaceTiles);             // the widest level at most
    return p;
}

std::optional<GpuVoxels> GpuVoxelizer::build(const Tape& tape, const GridLayout& layout,
                                             const GpuVoxelizeOptions& options, GpuVoxelizeReport* report)
{
    GpuVoxelizeReport local;
    GpuVoxelizeReport& r = report ? *report : local;
    r = {};
    const int levels = std::clamp(options.levels > 0 ? options.levels : layout.levels, 1, voxel::kMaxLevels);

    // The host's share: tile intervals in double, exactly as the CPU voxelizer.
    const auto prepareStart = Clock::now();
    std::vector<TilePlan> plans(std::size_t(layout.tileCount()));
    {
        const BlockTapes blocks(tape, layout);
        tbb::enumerable_thread_specific<std::pair<IntervalEvaluator, Tape>> scratch;
        tbb::enumerable_thread_specific<TileBuildScratch> builders;
        tbb::task_arena arena = workerArena(options.threads);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<long>(0, layout.tileCount(), 16), [&](const tbb::blocked_range<long>& range) {
                auto& [intervals, simple] = scratch.local();
                for (long i = range.begin(); i != range.end(); ++i) {
                    const glm::ivec3 t = layout.tileCoord(i);
                    const Aabb box = layout.tileBox(t);
                    const Interval iv = intervals.simplify(
                        blocks.forTile(t), box.grown(layout.tileSize * kIntervalBoxHair), simple);
                    TilePlan& plan = plans[std::size_t(i)];
                    if (iv.lo > 0.0) continue;
                    if (iv.hi < 0.0) {
                        plan.state = TileState::Full;
                        continue;
                    }
                    plan.state = TileState::Surface;
                    plan.tape = voxel::encodeTileTape(simple.rebased(box.min));
                    if (plan.tape.empty()) {
                        // Beyond the shaders' stack or length: the CPU's builder does this tile.
                        plan.built = buildTile(blocks.forTile(t), layout, t, levels, builders.local());
                        if (plan.built) plan.state = plan.built->state;
                    }
                }
            });
        });
    }
    HostData host;
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
        TileEntry e;
        e.node = std::uint32_t(host.entries.size()); // the roots are the first nodes
        e.levels = std::uint32_t(levels);
        e.tape = std::uint32_t(host.tapes.size());
        host.tapes.insert(host.tapes.end(), plan.tape.begin(), plan.tape.end());
        host.entryTiles.push_back(std::uint32_t(i));
        host.roots.insert(host.roots.end(), {std::uint32_t(host.entries.size()), std::uint32_t(host.entries.size()), 0u, 0u, 0u});
        host.entries.push_back(e);
    }
    const std::size_t surface = host.entries.size(); // built by the device
    for (const std::size_t i : hostBuilt) {
        const TileData& t = *plans[i].built;
        TileEntry e;
        e.node = std::uint32_t(surface + host.nodes.size());
        e.leafIndirection = std::uint32_t(host.leafIndirections.size());
        e.leafData = std::uint32_t(host.leafData.size());
        e.vertex = std::uint32_t(host.vertices.size());
        e.levels = std::uint32_t(t.levels);
        host.tiles[i] = std::uint32_t(host.entries.size());
        host.entries.push_back(e);
        host.nodes.insert(host.nodes.end(), t.nodes.begin(), t.nodes.end());
        host.leafIndirections.insert(host.leafIndirections.end(), t.leafIndirections.begin(), t.leafIndirections.end());
        host.leafData.insert(host.leafData.end(), t.leafData.begin(), t.leafData.end());
        host.vertices.insert(host.vertices.end(), t.vertices.begin(), t.vertices.end());
    }
    r.hostBuiltTiles = hostBuilt.size();
    r.prepareMilliseconds = millisecondsSince(prepareStart);

    GpuVoxels out;
    out.layout = layout;
    out.levels = levels;
    out.surfaceTiles = host.entries.size();
    constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                            VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    out.tiles = GpuBuffer(ctx_, host.tiles.size() * 4, kStorage, GpuBuffer::Kind::DeviceLocal, "tiles");
    out.entries = GpuBuffer(ctx_, host.entries.size() * sizeof(TileEntry), kStorage, GpuBuffer::Kind::DeviceLocal,
                            "entries");
    out.tapes = GpuBuffer(ctx_, host.tapes.size() * 4, kStorage, GpuBuffer::Kind::DeviceLocal, "tapes");

    const std::size_t budget = options.memoryBudget > 0 ? options.memoryBudget : deviceLocalHeapBytes(ctx_) / 2;
    const std::size_t perBuffer = ctx_.maxAllocationBytes();
    const std::uint32_t row = std::min<std::uint32_t>(ctx_.properties().limits.maxComputeWorkGroupCount[0], 65535u);
    const GpuBuffer entryTiles = GpuBuffer(ctx_, surface * 4, kStorage, GpuBuffer::Kind::DeviceLocal, "entry tiles");
    const GpuBuffer entryVoxels = GpuBuffer(ctx_, surface * 4, kStorage, GpuBuffer::Kind::DeviceLocal, "entry voxels");
    const GpuBuffer counters(ctx_, KERF_COUNT_WORDS * 4, kStorage, GpuBuffer::Kind::DeviceLocal, "counters");
    const GpuBuffer indirect(ctx_, 16, kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, GpuBuffer::Kind::DeviceLocal,
                             "indirect");
    const GpuBuffer params(ctx_, sizeof(gpu::VoxelizeParams), kStorage, GpuBuffer::Kind::DeviceLocal, "params");
    const GpuBuffer countsBack(ctx_, KERF_COUNT_WORDS * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GpuBuffer::Kind::Readback,
                               "counters read-back");

    Pools pools = firstGuess(surface, levels);
    for (int attempt = 1;; ++attempt) {
        r.attempts = attempt;
        pools.jobs = std::max(pools.jobs, surface);
        // The host's tiles take the first records of each pool.
        pools.nodes = std::max(pools.nodes, surface + host.nodes.size() + 1);
        pools.leafIndirections = std::max(pools.leafIndirections, host.leafIndirections.size() + 1);
        pools.leafData = std::max(pools.leafData, host.leafData.size() + 1);
        pools.vertices = std::max(pools.vertices, host.vertices.size() + 1);
        r.poolBytes = pools.bytes();
        const std::size_t largest = std::max({pools.nodes * sizeof(voxel::Node), pools.vertices * sizeof(voxel::Vertex),
                                              pools.leafData * sizeof(voxel::LeafData), pools.jobs * kJobBytes});
        if (pools.bytes() > budget || largest > perBuffer) {
            r.whyNot = "the voxels need about " + megabytes(pools.bytes()) + " of device memory (the budget is " +
                       megabytes(budget) + ", one buffer at most " + megabytes(perBuffer) + ")";
            return std::nullopt;
        }
        out.nodes = GpuBuffer(ctx_, pools.nodes * sizeof(voxel::Node), kStorage, GpuBuffer::Kind::DeviceLocal, "nodes");
        out.leafIndirections = GpuBuffer(ctx_, pools.leafIndirections * sizeof(voxel::LeafIndirection), kStorage,
                                         GpuBuffer::Kind::DeviceLocal, "leaf indirections");
        out.leafData = GpuBuffer(ctx_, pools.leafData * sizeof(voxel::LeafData), kStorage,
                                 GpuBuffer::Kind::DeviceLocal, "leaf data");
        out.vertices = GpuBuffer(ctx_, pools.vertices * sizeof(voxel::Vertex), kStorage, GpuBuffer::Kind::DeviceLocal,
                                 "vertices");
        const GpuBuffer jobs0(ctx_, pools.jobs * kJobBytes, kStorage, GpuBuffer::Kind::DeviceLocal, "jobs 0");
        const GpuBuffer jobs1(ctx_, pools.jobs * kJobBytes, kStorage, GpuBuffer::Kind::DeviceLocal, "jobs 1");

        gpu::VoxelizeParams p{};
        p.tapes = out.tapes.address();
        p.entries = out.entries.address();
        p.entryTiles = entryTiles.address();
        p.entryVoxels = entryVoxels.address();
        p.tiles = out.tiles.address();
        p.nodes = out.nodes.address();
        p.leafIndirections = out.leafIndirections.address();
        p.leafData = out.leafData.address();
        p.vertices = out.vertices.address();
        p.jobs0 = jobs0.address();
        p.jobs1 = jobs1.address();
        p.counters = counters.address();
        p.indirect = indirect.address();
        p.capacity = {std::uint32_t(pools.nodes), std::uint32_t(pools.leafIndirections), std::uint32_t(pools.leafData),
                      std::uint32_t(pools.vertices)};
        p.limits = {std::uint32_t(pools.jobs), std::uint32_t(surface), std::uint32_t(levels), row};
        const double voxelMm = layout.tileSize / std::pow(4.0, levels);
        int exponent = 0;
        const double fraction = std::frexp(voxelMm, &exponent);
        p.voxelMantissa = std::uint64_t(std::llround(std::ldexp(fraction, 40)));
        // The interval boxes grow by a hair so that float corners never cut them short.
        p.sizes = {float(voxelMm), float(layout.tileSize), float(layout.tileSize * kIntervalBoxHair),
                   float(exponent - 40)};
        std::uint32_t count[KERF_COUNT_WORDS] = {};
        count[KERF_COUNT_NODES] = std::uint32_t(surface + host.nodes.size());
        count[KERF_COUNT_LEAF_INDIRECTIONS] = std::uint32_t(host.leafIndirections.size());
        count[KERF_COUNT_LEAF_DATA] = std::uint32_t(host.leafData.size());
        count[KERF_COUNT_VERTICES] = std::uint32_t(host.vertices.size());
        count[KERF_COUNT_JOBS] = std::uint32_t(surface);
        const std::uint32_t firstGroups[4] = {std::min<std::uint32_t>(std::uint32_t(surface), row),
                                              (std::uint32_t(surface) + row - 1) / row, 1, 0};

        // One staging buffer, one submission: copies, then the passes.
        struct Upload {
            const void* data;
            std::size_t bytes;
            const GpuBuffer* to;
            std::size_t at = 0; // bytes into `to`
        };
        const Upload uploads[] = {{host.tiles.data(), host.tiles.size() * 4, &out.tiles},
                                  {host.entries.data(), host.entries.size() * sizeof(TileEntry), &out.entries},
                                  {host.nodes.data(), host.nodes.size() * sizeof(voxel::Node), &out.nodes,
                                   surface * sizeof(voxel::Node)},
                                  {host.leafIndirections.data(),
                                   host.leafIndirections.size() * sizeof(voxel::LeafIndirection), &out.leafIndirections},
                                  {host.leafData.data(), host.leafData.size() * sizeof(voxel::LeafData), &out.leafData},
                                  {host.vertices.data(), host.vertices.size() * sizeof(voxel::Vertex), &out.vertices},
                                  {host.tapes.data(), host.tapes.size() * 4, &out.tapes},
                                  {host.entryTiles.data(), surface * 4, &entryTiles},
                                  {host.roots.data(), host.roots.size() * 4, &jobs0},
                                  {count, sizeof count, &counters},
                                  {firstGroups, sizeof firstGroups, &indirect},
                                  {&p, sizeof p, &params}};
        const auto uploadStart = Clock::now();
        std::size_t total = 0;
        for (const Upload& u : uploads) total += u.bytes;
        const GpuBuffer staging(ctx_, total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GpuBuffer::Kind::HostVisible,
                                "voxelizer staging");
        {
            std::size_t at = 0;
            for (const Upload& u : uploads) {
                if (u.bytes > 0) std::memcpy(static_cast<char*>(staging.mapped()) + at, u.data, u.bytes);
                at += u.bytes;
            }
        }
        r.uploadMilliseconds += millisecondsSince(uploadStart);

        const auto deviceStart = Clock::now();
        ctx_.submitAndWait([&](VkCommandBuffer cb) {
            std::size_t at = 0;
            for (const Upload& u : uploads) {
                if (u.bytes == 0) continue;
                const VkBufferCopy region{at, u.at, u.bytes};
                vkCmdCopyBuffer(cb, staging.buffer(), u.to->buffer(), 1, &region);
                at += u.bytes;
            }
            vkCmdFillBuffer(cb, entryVoxels.buffer(), 0, VK_WHOLE_SIZE, 0);
            computeBarrier(cb);
            vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
            const auto push = [&](std::uint32_t pass, int level) {
                const VoxelizePush pc{params.address(), pass, std::uint32_t(level), std::uint32_t(level & 1), 0};
                vkCmdPushConstants(cb, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
            };
            for (int level = 0; level < levels && surface > 0; ++level) {
                const bool leaf = level == levels - 1;
                push(leaf ? KERF_PASS_LEAF : KERF_PASS_INNER, level);
                vkCmdDispatchIndirect(cb, indirect.buffer(), 0);
                computeBarrier(cb);
                if (leaf) break;
                push(KERF_PASS_PREPARE, level);
                vkCmdDispatch(cb, 1, 1, 1);
                computeBarrier(cb);
            }
            if (surface > 0) {
                push(KERF_PASS_FINISH, 0);
                vkCmdDispatch(cb, std::uint32_t((surface + KERF_VOXELIZE_GROUP - 1) / KERF_VOXELIZE_GROUP), 1, 1);
                computeBarrier(cb);
            }
            const VkBufferCopy region{0, 0, KERF_COUNT_WORDS * 4};
            vkCmdCopyBuffer(cb, counters.buffer(), countsBack.buffer(), 1, &region);
            VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0,
                                 nullptr, 0, nullptr);
        });
        r.deviceMilliseconds += millisecondsSince(deviceStart);

        std::uint32_t back[KERF_COUNT_WORDS];
        std::memcpy(back, countsBack.mapped(), sizeof back);
        const std::uint32_t overflow = back[KERF_COUNT_OVERFLOW];
        if (overflow == 0) {
            out.nodeCount = back[KERF_COUNT_NODES];
            out.leafCount = back[KERF_COUNT_LEAF_INDIRECTIONS];
            out.populatedVoxels = back[KERF_COUNT_LEAF_DATA];
            out.vertexCount = back[KERF_COUNT_VERTICES];
            if (surface > 0)
                voxelsPerTile_[std::size_t(levels)] =
                    double(out.populatedVoxels - host.leafData.size()) / double(surface);
            return out;
        }
        // A pool ran out at some level: the levels below it were cut short,
        // so their counts say little. Grow what overflowed to what it was
        // asked for and everything below by the same factor, at least twice.
        const auto grown = [](std::size_t capacity, std::uint32_t asked) {
            return std::max<std::size_t>(2 * capacity, std::size_t(1.25 * double(asked)));
        };
        double factor = 2.0;
        if (overflow & (1u << KERF_COUNT_NODES))
            factor = std::max(factor, 1.25 * double(back[KERF_COUNT_NODES]) / double(pools.nodes));
        if (overflow & (1u << KERF_COUNT_JOBS)) factor = std::max(factor, 4.0);
        if (overflow & (1u << KERF_COUNT_LEAF_DATA))
            factor = std::max(factor, 1.25 * double(back[KERF_COUNT_LEAF_DATA]) / double(pools.leafData));
        pools.nodes = std::min(kMaxRecords, std::max(grown(pools.nodes, back[KERF_COUNT_NODES]),
                                                     std::size_t(double(pools.nodes) * factor)));
        pools.jobs = std::min(kMaxRecords, std::size_t(double(pools.jobs) * factor));
        pools.leafIndirections =
            std::min(kMaxRecords, std::max(grown(pools.leafIndirections, back[KERF_COUNT_LEAF_INDIRECTIONS]),
                                           std::size_t(double(pools.leafIndirections) * factor)));
        pools.leafData = std::min(kMaxRecords, std::max(grown(pools.leafData, back[KERF_COUNT_LEAF_DATA]),
                                                        std::size_t(double(pools.leafData) * factor)));
        pools.vertices = std::min(kMaxRecords, std::max(grown(pools.vertices, back[KERF_COUNT_VERTICES]),
                                                        std::size_t(double(pools.vertices) * factor)));
        if (attempt >= 8) {
            r.whyNot = "the voxel pools kept overflowing after " + std::to_string(attempt) + " attempts";
            return std::nullopt;
        }
    }
}

} // namespace kerf::vk

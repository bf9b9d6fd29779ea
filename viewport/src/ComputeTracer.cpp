#include "kerf/viewport/ComputeTracer.hpp"

#include "kerf/tracer/ExactRefinement.h"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/viewport/ShaderModules.hpp"
#include "kerf/viewport/VulkanError.hpp"

#include "TraceShared.h"
#include "trace.comp.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstring>

namespace kerf::vk {

VoxelAddresses VoxelAddresses::of(const ResidentSet& r)
{
    VoxelAddresses a;
    a.grid = r.layout;
    a.tiles = r.tiles;
    a.entries = r.entries;
    a.nodes = a.leafIndirections = a.leafData = a.vertices = a.tapes = r.heap;
    a.version = r.snapshotVersion;
    return a;
}

struct ComputeTracer::Impl {
    const Context& ctx;
    ShaderModule module;
    PipelineLayout layout;
    Pipeline voxelPipeline;  // trace.comp without the hybrid refinement's code
    Pipeline hybridPipeline; // with it, every ray (ExactEverywhere); made when first asked for
    // TraceQuality::Exact's four passes (trace.comp, kPass), made when first asked for.
    Pipeline voxelPassPipeline, checkPipeline, listedPipeline, finishPipeline;
    QueryPool timestamps;
    GridLayout grid;
    GpuBuffer tiles, entries, nodes, leafIndirections, leafData, vertices, tapes;
    std::size_t resident = 0;
    std::uint64_t uploads = 0; // setVoxels() calls: the version of its voxels
    TraceTargets targets;
    GpuBuffer voxelPass, refineList, checkList; // per pixel, for TraceQuality::Exact
    GpuBuffer refineArgs;            // the refinement's indirect dispatch and count
    GpuBuffer refineArgsRead;        // its copy the host reads (lastTiming)
    bool lastWasExact = false;
    // TraceQuality::Exact's listed pass traces each ray with this many lanes
    // of one subgroup (trace.comp, exactCrossingLanes): as many as the
    // subgroup holds, up to KERF_EDGE_REFINE_MAX_LANES. 0: a device whose
    // subgroups hold fewer than KERF_EDGE_REFINE_LANES refines every ray
    // instead (ExactEverywhere: the same picture within the refinement's
    // accuracy, slower).
    int refineLanes = 0;
    GpuBuffer params;

    explicit Impl(const Context& c) : ctx(c) {}
    void ensureTargets(int w, int h);
    Pipeline makePipeline(bool hybrid, int pass) const;
    void recordExactPasses(VkCommandBuffer cb, int w, int h);
};

// trace.comp's kPass values.
constexpr int kTraceAll = 0, kTraceVoxels = 1, kCheckHits = 2, kTraceListed = 3, kFinishListed = 4;

void ComputeTracer::Impl::ensureTargets(int w, int h)
{
    if (targets.width == w && targets.height == h) return;
    const std::size_t pixels = std::size_t(w) * std::size_t(h);
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    targets.depth = GpuBuffer(ctx, pixels * sizeof(float), usage, GpuBuffer::Kind::DeviceLocal, "trace depth");
    targets.normal = GpuBuffer(ctx, pixels * 16, usage, GpuBuffer::Kind::DeviceLocal, "trace normal");
    targets.feature = GpuBuffer(ctx, pixels * sizeof(std::uint32_t), usage, GpuBuffer::Kind::DeviceLocal, "trace feature");
    voxelPass = GpuBuffer(ctx, pixels * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GpuBuffer::Kind::DeviceLocal,
                          "trace voxel pass");
    refineList = GpuBuffer(ctx, pixels * sizeof(std::uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                           GpuBuffer::Kind::DeviceLocal, "refinement list");
    checkList = GpuBuffer(ctx, pixels * sizeof(std::uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                          GpuBuffer::Kind::DeviceLocal, "check list");
    targets.width = w;
    targets.height = h;
}

Pipeline ComputeTracer::Impl::makePipeline(bool hybrid, int pass) const
{
    // trace.comp's specialization constants 0, kHybrid, 1, kPass, and 2, kRefineLanes.
    struct {
        VkBool32 hybrid;
        std::int32_t pass;
        std::int32_t lanes;
    } values{hybrid ? VK_TRUE : VK_FALSE, pass, std::max(refineLanes, KERF_EDGE_REFINE_LANES)};
    const VkSpecializationMapEntry entries[3] = {{0, offsetof(decltype(values), hybrid), sizeof(VkBool32)},
                                                 {1, offsetof(decltype(values), pass), sizeof(std::int32_t)},
                                                 {2, offsetof(decltype(values), lanes), sizeof(std::int32_t)}};
    VkSpecializationInfo special{};
    special.mapEntryCount = 3;
    special.pMapEntries = entries;
    special.dataSize = sizeof values;
    special.pData = &values;
    VkComputePipelineCreateInfo cpci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = module;
    cpci.stage.pName = "main";
    cpci.stage.pSpecializationInfo = &special;
    cpci.layout = layout;
    if (ctx.capturesPipelineStatistics()) cpci.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
    VkPipeline p;
    check(vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &cpci, nullptr, &p),
          hybrid ? "vkCreateComputePipelines (trace, hybrid)" : "vkCreateComputePipelines (trace)");
    return Pipeline(ctx.device(), p);
}

// trace.comp's RefineArgs before the check lists a pixel: the listed pass's
// indirect dispatch (groups, y, z), the count listed, how many from the
// list's front and its back, the finishing pass's dispatch, the check's
// dispatch and the count of voxel hits listed for it.
constexpr std::uint32_t kNoneListed[13] = {0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 1, 1, 0};
constexpr VkDeviceSize kFinishArgsOffset = 6 * sizeof(std::uint32_t);
constexpr VkDeviceSize kCheckArgsOffset = 9 * sizeof(std::uint32_t);

// TraceQuality::Exact: the voxels everywhere, the check of the voxel hits
// they listed on the exact field, the refinement of the pixels listed by
// either, and the exact normals of the refined (indirect dispatches sized by
// the lists: no lane idles on a pixel that has nothing to do there).
void ComputeTracer::Impl::recordExactPasses(VkCommandBuffer cb, int w, int h)
{
    if (!voxelPassPipeline) {
        voxelPassPipeline = makePipeline(false, kTraceVoxels);
        checkPipeline = makePipeline(false, kCheckHits);
        listedPipeline = makePipeline(true, kTraceListed);
        finishPipeline = makePipeline(true, kFinishListed);
    }
    const std::uint32_t g = KERF_TRACE_LOCAL_SIZE;
    const auto computeToCompute = [&](VkAccessFlags dstAccess, VkPipelineStageFlags dstStage) {
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        mb.dstAccessMask = dstAccess;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, dstStage, 0, 1, &mb, 0, nullptr, 0, nullptr);
    };
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, voxelPassPipeline);
    vkCmdDispatch(cb, (std::uint32_t(w) + g - 1) / g, (std::uint32_t(h) + g - 1) / g, 1);
    computeToCompute(VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT);
    vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, timestamps, 2);
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, checkPipeline);
    vkCmdDispatchIndirect(cb, refineArgs.buffer(), kCheckArgsOffset);
    computeToCompute(VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT |
                         VK_ACCESS_TRANSFER_READ_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                         VK_PIPELINE_STAGE_TRANSFER_BIT);
    vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, timestamps, 3);
    const VkBufferCopy args{0, 0, 4 * sizeof(std::uint32_t)};
    vkCmdCopyBuffer(cb, refineArgs.buffer(), refineArgsRead.buffer(), 1, &args);
    VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    toHost.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0,
                         nullptr);
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, listedPipeline);
    vkCmdDispatchIndirect(cb, refineArgs.buffer(), 0);
    computeToCompute(VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, finishPipeline);
    vkCmdDispatchIndirect(cb, refineArgs.buffer(), kFinishArgsOffset);
}

ComputeTracer::ComputeTracer(const Context& ctx) : impl_(std::make_unique<Impl>(ctx))
{
    VkPhysicalDeviceSubgroupProperties subgroups{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &subgroups;
    vkGetPhysicalDeviceProperties2(ctx.physicalDevice(), &properties);
    const VkSubgroupFeatureFlags needed = VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_SHUFFLE_BIT;
    const std::uint32_t size = subgroups.subgroupSize;
    if ((subgroups.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) && (subgroups.supportedOperations & needed) == needed &&
        size >= KERF_EDGE_REFINE_LANES && (size & (size - 1)) == 0 &&
        (KERF_TRACE_LOCAL_SIZE * KERF_TRACE_LOCAL_SIZE) % size == 0)
        impl_->refineLanes = int(std::min<std::uint32_t>(size, KERF_EDGE_REFINE_MAX_LANES));
    VkDevice dev = ctx.device();
    impl_->module = makeShaderModule(dev, kTraceComp, sizeof(kTraceComp), "vkCreateShaderModule (trace.comp)");

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(std::uint64_t)};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &range;
    VkPipelineLayout pl;
    check(vkCreatePipelineLayout(dev, &plci, nullptr, &pl), "vkCreatePipelineLayout");
    impl_->layout = PipelineLayout(dev, pl);

    impl_->voxelPipeline = impl_->makePipeline(false, kTraceAll);

    VkQueryPoolCreateInfo qpci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qpci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qpci.queryCount = 4; // start, end, and between TraceQuality::Exact's passes
    VkQueryPool qp;
    check(vkCreateQueryPool(dev, &qpci, nullptr, &qp), "vkCreateQueryPool");
    impl_->timestamps = QueryPool(dev, qp);
    // Written by vkCmdUpdateBuffer inside the frame's commands, so that a
    // frame in flight never sees the next frame's parameters.
    impl_->params = GpuBuffer(ctx, sizeof(gpu::TraceParams),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              GpuBuffer::Kind::DeviceLocal, "trace params");
    impl_->refineArgs = GpuBuffer(ctx, sizeof kNoneListed,
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                      VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                  GpuBuffer::Kind::DeviceLocal, "refinement dispatch");
    impl_->refineArgsRead = GpuBuffer(ctx, 4 * sizeof(std::uint32_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      GpuBuffer::Kind::Readback, "refinement dispatch, read back");
}

ComputeTracer::~ComputeTracer() = default;

std::size_t ComputeTracer::residentBytes() const { return impl_->resident; }
const TraceTargets& ComputeTracer::targets() const { return impl_->targets; }

void ComputeTracer::setVoxels(const FlatVoxelBuffers& b)
{
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    auto up = [&](const auto& v, const char* name) {
        return uploadBuffer(impl_->ctx, v.data(), v.size() * sizeof(v[0]), usage, name);
    };
    impl_->tiles = up(b.tiles, "tiles");
    impl_->entries = up(b.entries, "tile entries");
    impl_->nodes = up(b.nodes, "nodes");
    impl_->leafIndirections = up(b.leafIndirections, "leaf indirections");
    impl_->leafData = up(b.leafData, "leaf data");
    impl_->vertices = up(b.vertices, "vertices");
    impl_->tapes = up(b.tapes, "tile tapes");
    impl_->grid = b.layout;
    impl_->resident = b.bytes();
    ++impl_->uploads;
}

VoxelAddresses ComputeTracer::voxels() const
{
    VoxelAddresses a;
    if (!impl_->tiles.buffer()) return a;
    a.grid = impl_->grid;
    a.tiles = impl_->tiles.address();
    a.entries = impl_->entries.address();
    a.nodes = impl_->nodes.address();
    a.leafIndirections = impl_->leafIndirections.address();
    a.leafData = impl_->leafData.address();
    a.vertices = impl_->vertices.address();
    a.tapes = impl_->tapes.address();
    a.version = impl_->uploads;
    return a;
}

void ComputeTracer::record(VkCommandBuffer cb, const Camera& camera, const VoxelAddresses& addr,
                           const Section& section, TraceQuality quality)
{
    const int w = camera.width(), h = camera.height();
    impl_->ensureTargets(w, h);
    const TraceTargets& t = impl_->targets;
    gpu::TraceParams p{};
    p.tiles = addr.tiles;
    p.entries = addr.entries;
    p.nodes = addr.nodes;
    p.leafIndirections = addr.leafIndirections;
    p.leafData = addr.leafData;
    p.vertices = addr.vertices;
    p.tapes = addr.tapes;
    p.outDepth = t.depth.address();
    p.outNormal = t.normal.address();
    p.outFeature = t.feature.address();
    // The eye relative to the grid origin, subtracted in double: float only
    // ever sees small, grid-local numbers.
    const glm::dvec3 eye = camera.eye() - addr.grid.origin;
    const bool ortho = camera.projection() == Projection::Orthographic;
    const double halfHeight = camera.halfHeight();
    p.eye = {float(eye.x), float(eye.y), float(eye.z), float(addr.grid.tileSize)};
    p.forward = {float(camera.forward().x), float(camera.forward().y), float(camera.forward().z), ortho ? 1.0f : 0.0f};
    p.right = {float(camera.right().x), float(camera.right().y), float(camera.right().z), float(halfHeight)};
    p.up = {float(camera.up().x), float(camera.up().y), float(camera.up().z), float(addr.grid.voxelSize)};
    // With nothing resident the grid is empty: every ray misses.
    p.dims = {addr.tiles ? addr.grid.dims.x : 0, addr.tiles ? addr.grid.dims.y : 0, addr.tiles ? addr.grid.dims.z : 0, 0};
    p.image = {std::uint32_t(w), std::uint32_t(h), 0, 0};
    const glm::vec4 plane = localPlane(addr.grid, section);
    p.section = {plane.x, plane.y, plane.z, plane.w};
    p.outVoxelPass = impl_->voxelPass.address();
    p.refineList = impl_->refineList.address();
    p.checkList = impl_->checkList.address();
    p.refineArgs = impl_->refineArgs.address();
    // Without tapes (none built, none uploaded) the hybrid has nothing to refine with.
    const bool refine = quality != TraceQuality::Voxels && addr.tapes;
    p.options = {refine ? 1u : 0u, 0, 0, 0};
    // The previous frame in this command buffer may still read the
    // parameters and the indirect dispatch being rewritten.
    VkMemoryBarrier reuse{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    // (The transfer stage too: the last frame's copy of the dispatch's count.)
    vkCmdPipelineBarrier(cb,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                             VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &reuse, 0, nullptr, 0, nullptr);
    vkCmdUpdateBuffer(cb, impl_->params.buffer(), 0, sizeof p, &p);
    vkCmdUpdateBuffer(cb, impl_->refineArgs.buffer(), 0, sizeof kNoneListed, kNoneListed);
    VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    before.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    before.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &before, 0, nullptr, 0, nullptr);

    const std::uint64_t address = impl_->params.address();
    vkCmdResetQueryPool(cb, impl_->timestamps, 0, 4);
    vkCmdPushConstants(cb, impl_->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof address, &address);
    vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, impl_->timestamps, 0);
    const std::uint32_t g = KERF_TRACE_LOCAL_SIZE;
    impl_->lastWasExact = refine && quality == TraceQuality::Exact && impl_->refineLanes > 0;
    if (impl_->lastWasExact) {
        impl_->recordExactPasses(cb, w, h);
    } else {
        if (refine && !impl_->hybridPipeline) impl_->hybridPipeline = impl_->makePipeline(true, kTraceAll);
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, refine ? impl_->hybridPipeline : impl_->voxelPipeline);
        vkCmdDispatch(cb, (std::uint32_t(w) + g - 1) / g, (std::uint32_t(h) + g - 1) / g, 1);
    }
    vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, impl_->timestamps, 1);
    VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    after.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    after.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &after, 0, nullptr,
                         0, nullptr);
}

int ComputeTracer::refineLanes() const { return impl_->refineLanes; }

std::vector<std::pair<std::string, std::vector<std::string>>> ComputeTracer::pipelineStatistics() const
{
    std::vector<std::pair<std::string, std::vector<std::string>>> out;
    const auto add = [&](const char* name, const Pipeline& p) {
        if (p) out.emplace_back(name, impl_->ctx.pipelineStatistics(p));
    };
    add("voxels", impl_->voxelPipeline);
    add("exact-everywhere", impl_->hybridPipeline);
    add("exact: voxel pass", impl_->voxelPassPipeline);
    add("exact: check", impl_->checkPipeline);
    add("exact: listed rays", impl_->listedPipeline);
    add("exact: finishing the listed", impl_->finishPipeline);
    return out;
}

TraceTiming ComputeTracer::lastTiming() const
{
    std::uint64_t stamps[2] = {0, 0};
    check(vkGetQueryPoolResults(impl_->ctx.device(), impl_->timestamps, 0, 2, sizeof stamps, stamps,
                                sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    const double period = double(impl_->ctx.properties().limits.timestampPeriod) * 1e-6;
    TraceTiming t;
    t.gpuMilliseconds = double(stamps[1] - stamps[0]) * period;
    if (impl_->lastWasExact) {
        std::uint64_t between[2] = {0, 0};
        check(vkGetQueryPoolResults(impl_->ctx.device(), impl_->timestamps, 2, 2, sizeof between, between,
                                    sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
              "vkGetQueryPoolResults");
        t.voxelPassMilliseconds = double(between[0] - stamps[0]) * period;
        t.checkMilliseconds = double(between[1] - between[0]) * period;
        t.refineMilliseconds = double(stamps[1] - between[1]) * period;
        t.refinedPixels = static_cast<const std::uint32_t*>(impl_->refineArgsRead.mapped())[3];
    }
    return t;
}

TraceImage ComputeTracer::trace(const Camera& camera, TraceTiming* timing, const Section& section,
                                TraceQuality quality)
{
    return trace(camera, ResidentSet{}, timing, section, quality);
}

TraceImage ComputeTracer::trace(const Camera& camera, const ResidentSet& voxels, TraceTiming* timing,
                                const Section& section, TraceQuality quality)
{
    return trace(camera, voxels.valid() ? VoxelAddresses::of(voxels) : this->voxels(), timing, section, quality);
}

TraceImage readTargets(const Context& ctx, const TraceTargets& t, const std::function<void(VkCommandBuffer)>& draw)
{
    const std::size_t pixels = std::size_t(t.width) * std::size_t(t.height);
    GpuBuffer depth(ctx, pixels * sizeof(float), VK_BUFFER_USAGE_TRANSFER_DST_BIT, GpuBuffer::Kind::Readback, "depth");
    GpuBuffer normal(ctx, pixels * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GpuBuffer::Kind::Readback, "normal");
    GpuBuffer feature(ctx, pixels * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GpuBuffer::Kind::Readback, "feature");
    ctx.submitAndWait([&](VkCommandBuffer cb) {
        draw(cb);
        VkBufferCopy d{0, 0, pixels * sizeof(float)}, n{0, 0, pixels * 16}, f{0, 0, pixels * 4};
        vkCmdCopyBuffer(cb, t.depth.buffer(), depth.buffer(), 1, &d);
        vkCmdCopyBuffer(cb, t.normal.buffer(), normal.buffer(), 1, &n);
        vkCmdCopyBuffer(cb, t.feature.buffer(), feature.buffer(), 1, &f);
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0,
                             nullptr);
    });
    TraceImage image(t.width, t.height);
    std::memcpy(image.depth.data(), depth.mapped(), pixels * sizeof(float));
    std::memcpy(image.feature.data(), feature.mapped(), pixels * 4);
    const float* nrm = static_cast<const float*>(normal.mapped());
    for (std::size_t i = 0; i < pixels; ++i) image.normal[i] = {nrm[4 * i], nrm[4 * i + 1], nrm[4 * i + 2]};
    return image;
}

TraceImage ComputeTracer::trace(const Camera& camera, const VoxelAddresses& addr, TraceTiming* timing,
                                const Section& section, TraceQuality quality)
{
    impl_->ensureTargets(camera.width(), camera.height());
    TraceImage image = readTargets(impl_->ctx, impl_->targets,
                                   [&](VkCommandBuffer cb) { record(cb, camera, addr, section, quality); });
    if (timing) *timing = lastTiming();
    return image;
}

double ComputeTracer::sustainedMilliseconds(const Camera& camera, int frames, TraceQuality quality,
                                             const Section& section)
{
    frames = std::max(frames, 1);
    const VoxelAddresses addr = voxels();
    const auto batch = [&] {
        const auto t0 = std::chrono::steady_clock::now();
        impl_->ctx.submitAndWait([&](VkCommandBuffer cb) {
            for (int f = 0; f < frames; ++f) record(cb, camera, addr, section, quality);
        });
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
    // Warm-up: a GPU raises its clocks only after a few hundred milliseconds
    // of load (an H100 traced the same frame 2.5 ms cold, 0.6 ms warm).
    double warm = 0.0;
    for (int i = 0; i < 50 && warm < 300.0; ++i) warm += batch();
    return batch() / frames;
}

} // namespace kerf::vk

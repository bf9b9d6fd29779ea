#include "kerf/viewport/ComputeTracer.hpp"

#include "kerf/viewport/VulkanError.hpp"

#include "TraceShared.h"
#include "trace.comp.h"

#include <cstring>

namespace kerf::vk {

struct ComputeTracer::Impl {
    const Context& ctx;
    ShaderModule module;
    PipelineLayout layout;
    Pipeline pipeline;
    QueryPool timestamps;
    GridLayout grid;
    GpuBuffer tiles, entries, nodes, leafIndirections, leafData, vertices;
    std::size_t resident = 0;

    // Where a dispatch finds the voxels: separate arrays (setVoxels) or one
    // heap for all four record kinds (a streamed ResidentSet).
    struct Addresses {
        GridLayout grid;
        VkDeviceAddress tiles = 0, entries = 0, nodes = 0, leafIndirections = 0, leafData = 0, vertices = 0;
    };
    TraceImage dispatch(const Camera& camera, const Addresses& a, TraceTiming* timing);

    explicit Impl(const Context& c) : ctx(c) {}
};

ComputeTracer::ComputeTracer(const Context& ctx) : impl_(std::make_unique<Impl>(ctx))
{
    VkDevice dev = ctx.device();
    VkShaderModuleCreateInfo smci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smci.codeSize = sizeof(kTraceComp);
    smci.pCode = kTraceComp;
    VkShaderModule sm;
    check(vkCreateShaderModule(dev, &smci, nullptr, &sm), "vkCreateShaderModule (trace.comp)");
    impl_->module = ShaderModule(dev, sm);

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(std::uint64_t)};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &range;
    VkPipelineLayout pl;
    check(vkCreatePipelineLayout(dev, &plci, nullptr, &pl), "vkCreatePipelineLayout");
    impl_->layout = PipelineLayout(dev, pl);

    VkComputePipelineCreateInfo cpci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = sm;
    cpci.stage.pName = "main";
    cpci.layout = pl;
    VkPipeline p;
    check(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &cpci, nullptr, &p), "vkCreateComputePipelines (trace)");
    impl_->pipeline = Pipeline(dev, p);

    VkQueryPoolCreateInfo qpci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qpci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qpci.queryCount = 2;
    VkQueryPool qp;
    check(vkCreateQueryPool(dev, &qpci, nullptr, &qp), "vkCreateQueryPool");
    impl_->timestamps = QueryPool(dev, qp);
}

ComputeTracer::~ComputeTracer() = default;

std::size_t ComputeTracer::residentBytes() const { return impl_->resident; }

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
    impl_->grid = b.layout;
    impl_->resident = b.bytes();
}

TraceImage ComputeTracer::trace(const Camera& camera, TraceTiming* timing)
{
    Impl::Addresses a;
    a.grid = impl_->grid;
    a.tiles = impl_->tiles.address();
    a.entries = impl_->entries.address();
    a.nodes = impl_->nodes.address();
    a.leafIndirections = impl_->leafIndirections.address();
    a.leafData = impl_->leafData.address();
    a.vertices = impl_->vertices.address();
    return impl_->dispatch(camera, a, timing);
}

TraceImage ComputeTracer::trace(const Camera& camera, const ResidentSet& voxels, TraceTiming* timing)
{
    Impl::Addresses a;
    a.grid = voxels.layout;
    a.tiles = voxels.tiles;
    a.entries = voxels.entries;
    a.nodes = a.leafIndirections = a.leafData = a.vertices = voxels.heap;
    return impl_->dispatch(camera, a, timing);
}

TraceImage ComputeTracer::Impl::dispatch(const Camera& camera, const Addresses& addr, TraceTiming* timing)
{
    if (addr.tiles == 0 || addr.grid.empty()) return TraceImage(camera.width(), camera.height()); // nothing resident
    const int w = camera.width(), h = camera.height();
    const std::size_t pixels = std::size_t(w) * std::size_t(h);
    GpuBuffer depth(ctx, pixels * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GpuBuffer::Kind::Readback, "depth");
    GpuBuffer normal(ctx, pixels * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GpuBuffer::Kind::Readback, "normal");
    GpuBuffer feature(ctx, pixels * sizeof(std::uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      GpuBuffer::Kind::Readback, "feature");
    GpuBuffer params(ctx, sizeof(gpu::TraceParams), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GpuBuffer::Kind::HostVisible,
                     "trace params");

    gpu::TraceParams p{};
    p.tiles = addr.tiles;
    p.entries = addr.entries;
    p.nodes = addr.nodes;
    p.leafIndirections = addr.leafIndirections;
    p.leafData = addr.leafData;
    p.vertices = addr.vertices;
    p.outDepth = depth.address();
    p.outNormal = normal.address();
    p.outFeature = feature.address();
    // The eye relative to the grid origin, subtracted in double: float only
    // ever sees small, grid-local numbers.
    const glm::dvec3 eye = camera.eye() - addr.grid.origin;
    const bool ortho = camera.projection() == Projection::Orthographic;
    const double halfHeight = ortho ? 0.5 * camera.orthoHeight()
                                    : std::tan(0.5 * camera.fovYDegrees() * 3.14159265358979323846 / 180.0);
    p.eye = {float(eye.x), float(eye.y), float(eye.z), float(addr.grid.tileSize)};
    p.forward = {float(camera.forward().x), float(camera.forward().y), float(camera.forward().z), ortho ? 1.0f : 0.0f};
    p.right = {float(camera.right().x), float(camera.right().y), float(camera.right().z), float(halfHeight)};
    p.up = {float(camera.up().x), float(camera.up().y), float(camera.up().z), 0.0f};
    p.dims = {addr.grid.dims.x, addr.grid.dims.y, addr.grid.dims.z, 0};
    p.image = {std::uint32_t(w), std::uint32_t(h), 0, 0};
    std::memcpy(params.mapped(), &p, sizeof p);

    const std::uint64_t address = params.address();
    ctx.submitAndWait([&](VkCommandBuffer cb) {
        vkCmdResetQueryPool(cb, timestamps, 0, 2);
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
        vkCmdPushConstants(cb, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof address, &address);
        vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps, 0);
        const std::uint32_t groups = KERF_TRACE_LOCAL_SIZE;
        vkCmdDispatch(cb, (std::uint32_t(w) + groups - 1) / groups, (std::uint32_t(h) + groups - 1) / groups, 1);
        vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps, 1);
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr,
                             0, nullptr);
    });
    if (timing) {
        std::uint64_t stamps[2] = {0, 0};
        check(vkGetQueryPoolResults(ctx.device(), timestamps, 0, 2, sizeof stamps, stamps, sizeof(std::uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
              "vkGetQueryPoolResults");
        timing->gpuMilliseconds = double(stamps[1] - stamps[0]) * double(ctx.properties().limits.timestampPeriod) * 1e-6;
    }

    TraceImage image(w, h);
    std::memcpy(image.depth.data(), depth.mapped(), pixels * sizeof(float));
    std::memcpy(image.feature.data(), feature.mapped(), pixels * sizeof(std::uint32_t));
    const float* n = static_cast<const float*>(normal.mapped());
    for (std::size_t i = 0; i < pixels; ++i) image.normal[i] = {n[4 * i], n[4 * i + 1], n[4 * i + 2]};
    return image;
}

} // namespace kerf::vk

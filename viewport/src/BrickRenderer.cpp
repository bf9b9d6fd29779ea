#include "kerf/viewport/BrickRenderer.hpp"

#include "kerf/viewport/ClipFromWorld.hpp"
#include "kerf/viewport/DeviceImage.hpp"
#include "kerf/viewport/GraphicsPipeline.hpp"
#include "kerf/viewport/ShaderModules.hpp"
#include "kerf/viewport/VulkanError.hpp"

#include "BrickShared.h"
#include "brick.frag.h"
#include "brick.vert.h"

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <numeric>
#include <optional>
#include <string>

namespace kerf::vk {

namespace {

constexpr VkFormat kDistanceFormat = VK_FORMAT_R16_SNORM;
constexpr VkFormat kNormalFormat = VK_FORMAT_R8G8B8A8_SNORM;
constexpr VkFormat kFeatureFormat = VK_FORMAT_R16_UINT;
// The render targets: depth along the ray, normal, feature (copied to the
// TraceTargets buffers), and the depth test's own buffer.
constexpr VkFormat kRayDepthFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kNormalTargetFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kFeatureTargetFormat = VK_FORMAT_R32_UINT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
// The staging copies are cut into pieces of this many bytes for the cores.
constexpr std::size_t kCopyPiece = std::size_t(1) << 20;


Sampler makeSampler(VkDevice dev, VkFilter filter)
{
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = filter;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sci.maxLod = 0.0f;
    VkSampler s;
    check(vkCreateSampler(dev, &sci, nullptr, &s), "vkCreateSampler");
    return Sampler(dev, s);
}

} // namespace

struct BrickRenderer::Impl {
    const Context& ctx;
    DescriptorSetLayout setLayout;
    DescriptorPool pool;
    VkDescriptorSet set = VK_NULL_HANDLE;
    PipelineLayout layout;
    RenderPass renderPass;
    Pipeline pipeline;
    Sampler linear, nearest;
    QueryPool timestamps;

    // The bricks: where they are (host), their samples (atlases).
    std::vector<Brick> bricks;
    Aabb bounds;
    DeviceImage distance, normal, feature;
    glm::uvec3 atlasTexels{0}, atlasSlots{0};
    GpuBuffer instances; // host-visible, rewritten when the eye moves
    std::optional<glm::dvec3> sortedFor;
    std::uint64_t uploads = 0;
    double sortMilliseconds = 0.0;

    // Bricks being copied in (stage, recordUpload), drawn once all of them
    // are on the device; and the host side of the copies.
    struct Staged {
        std::vector<Brick> bricks;
        BrickAtlas atlas;
        DeviceImage distance, normal, feature;
        GpuBuffer instances; // made beforehand (prepare), or empty
        std::size_t rowsDone = 0;
    };
    std::optional<Staged> staged;
    // Kept from one upload to the next (allocating it took a frame tens of
    // milliseconds on an H200); setBricks() releases it.
    GpuBuffer staging;
    std::uint64_t frameAllocations = 0; // recordUpload()'s, for want of prepared memory

    // Targets.
    int width = 0, height = 0;
    DeviceImage rayDepth, normalTarget, featureTarget, depthBuffer;
    Framebuffer framebuffer;
    TraceTargets targets;

    // Memory the frames are done with, being freed on a thread of its own
    // (adoptStaged); waited for at the next upload and when the renderer
    // goes (the last member: destroyed first).
    std::future<void> releasing;

    explicit Impl(const Context& c) : ctx(c) {}
    void ensureTargets(int w, int h);
    void sortInstances(const glm::dvec3& eye);
    void adoptStaged();
};

BrickRenderer::BrickRenderer(const Context& ctx) : impl_(std::make_unique<Impl>(ctx))
{
    VkDevice dev = ctx.device();
    VkDescriptorSetLayoutBinding bindings[3]{};
    for (std::uint32_t i = 0; i < 3; ++i) {
        bindings[i].binding = i;
        bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        bindings[i].descriptorCount = 1;
        bindings[i].stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
    }
    VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dl.bindingCount = 3;
    dl.pBindings = bindings;
    VkDescriptorSetLayout sl;
    check(vkCreateDescriptorSetLayout(dev, &dl, nullptr, &sl), "vkCreateDescriptorSetLayout (bricks)");
    impl_->setLayout = DescriptorSetLayout(dev, sl);
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 3};
    VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dp.maxSets = 1;
    dp.poolSizeCount = 1;
    dp.pPoolSizes = &size;
    VkDescriptorPool pool;
    check(vkCreateDescriptorPool(dev, &dp, nullptr, &pool), "vkCreateDescriptorPool (bricks)");
    impl_->pool = DescriptorPool(dev, pool);
    VkDescriptorSetAllocateInfo da{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    da.descriptorPool = impl_->pool;
    da.descriptorSetCount = 1;
    VkDescriptorSetLayout layouts[1] = {impl_->setLayout};
    da.pSetLayouts = layouts;
    check(vkAllocateDescriptorSets(dev, &da, &impl_->set), "vkAllocateDescriptorSets (bricks)");

    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(gpu::BrickPush)};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.setLayoutCount = 1;
    plci.pSetLayouts = layouts;
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &range;
    VkPipelineLayout pl;
    check(vkCreatePipelineLayout(dev, &plci, nullptr, &pl), "vkCreatePipelineLayout (bricks)");
    impl_->layout = PipelineLayout(dev, pl);

    // Three colour targets (cleared to "nothing hit"), copied into the trace
    // buffers after the pass, and depth.
    const VkFormat colours[3] = {kRayDepthFormat, kNormalTargetFormat, kFeatureTargetFormat};
    impl_->renderPass = makeCopiedRenderPass(dev, colours, kDepthFormat, "vkCreateRenderPass (bricks)");

    const ShaderModule vs = makeShaderModule(dev, kBrickVert, sizeof kBrickVert, "shader brick.vert");
    const ShaderModule fs = makeShaderModule(dev, kBrickFrag, sizeof kBrickFrag, "shader brick.frag");
    GraphicsPipelineStyle style;
    style.depthCompare = VK_COMPARE_OP_LESS;
    style.colorAttachments = 3;
    // The cubes' far faces: the faces wind counter-clockwise seen from
    // outside, and so they look on screen (the projection turns y upright),
    // which Vulkan calls counter-clockwise; clockwise as the front culls the
    // near faces. A far face is in front of an eye inside its brick (zoomed in
    // on a surface), and its depth orders the bricks along a ray as their hits
    // do (brick.frag).
    style.cullMode = VK_CULL_MODE_BACK_BIT;
    style.frontFace = VK_FRONT_FACE_CLOCKWISE;
    impl_->pipeline = makeGraphicsPipeline(dev, impl_->renderPass, impl_->layout, vs, fs, style,
                                           "vkCreateGraphicsPipelines (bricks)");

    impl_->linear = makeSampler(dev, VK_FILTER_LINEAR);
    impl_->nearest = makeSampler(dev, VK_FILTER_NEAREST);
    VkQueryPoolCreateInfo qp{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qp.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qp.queryCount = 2;
    VkQueryPool q;
    check(vkCreateQueryPool(dev, &qp, nullptr, &q), "vkCreateQueryPool (bricks)");
    impl_->timestamps = QueryPool(dev, q);
}

BrickRenderer::~BrickRenderer() = default;

void BrickRenderer::setBricks(const BrickLeaves& leaves)
{
    stage(leaves.bricks, BrickAtlas::pack(leaves, maxImageDimension3D()));
    impl_->ctx.submitAndWait(
        [&](VkCommandBuffer cb) { recordUpload(cb, std::numeric_limits<std::size_t>::max(), true); });
    impl_->staging = {};
}

std::uint32_t BrickRenderer::maxImageDimension3D() const
{
    return impl_->ctx.properties().limits.maxImageDimension3D;
}

namespace {
// The host-visible records of `count` bricks, rewritten when the eye moves.
GpuBuffer makeInstanceBuffer(const Context& ctx, std::size_t count)
{
    return GpuBuffer(ctx, count * sizeof(gpu::BrickInstance), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                     GpuBuffer::Kind::HostVisible, "brick instances");
}

// The staging memory recordUpload() needs for `rows` rows of `atlas`: each
// atlas's texels of up to three boxes (the rest of a slice, whole slices,
// the start of one), each at a 16-byte boundary.
std::size_t stagingBytesFor(const BrickAtlas& atlas, std::size_t rows)
{
    return rows * atlas.rowBytes() + 3 * 3 * 16;
}
} // namespace

PreparedBricks BrickRenderer::prepare(const Context& ctx, std::vector<Brick> bricks, BrickAtlas atlas,
                                      std::size_t budgetBytes)
{
    PreparedBricks p;
    p.bricks_ = std::move(bricks);
    p.atlas_ = std::move(atlas);
    if (p.bricks_.empty()) return p;
    const BrickAtlas& a = p.atlas_;
    const VkExtent3D extent{a.texels.x, a.texels.y, a.texels.z};
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    p.distance_ = makeDeviceImage(ctx, extent, kDistanceFormat, usage, VK_IMAGE_ASPECT_COLOR_BIT);
    p.normal_ = makeDeviceImage(ctx, extent, kNormalFormat, usage, VK_IMAGE_ASPECT_COLOR_BIT);
    p.feature_ = makeDeviceImage(ctx, extent, kFeatureFormat, usage, VK_IMAGE_ASPECT_COLOR_BIT);
    if (budgetBytes == 0) return p;
    // The instance records too (otherwise made in the upload's last frame;
    // 9.5 MB for the chair at 0.25 mm).
    p.instances_ = makeInstanceBuffer(ctx, p.bricks_.size());
    if (a.rows() > 0) {
        // As many rows as recordUpload() copies within the budget, one at least.
        const std::size_t rows = std::clamp<std::size_t>(budgetBytes / a.rowBytes(), 1, a.rows());
        p.staging_ = GpuBuffer(ctx, stagingBytesFor(a, rows), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               GpuBuffer::Kind::HostVisible, "brick atlas staging");
    }
    return p;
}

void BrickRenderer::stage(std::vector<Brick> bricks, BrickAtlas atlas)
{
    stage(prepare(impl_->ctx, std::move(bricks), std::move(atlas), 0));
}

void BrickRenderer::stage(PreparedBricks prepared)
{
    Impl& m = *impl_;
    m.staged.reset(); // its copies have finished (recordUpload's contract)
    Impl::Staged s;
    s.bricks = std::move(prepared.bricks_);
    s.atlas = std::move(prepared.atlas_);
    s.distance = std::move(prepared.distance_);
    s.normal = std::move(prepared.normal_);
    s.feature = std::move(prepared.feature_);
    s.instances = std::move(prepared.instances_);
    if (prepared.staging_.size() > m.staging.size()) m.staging = std::move(prepared.staging_);
    m.staged = std::move(s);
}

std::uint64_t BrickRenderer::frameAllocations() const { return impl_->frameAllocations; }

bool BrickRenderer::uploading() const { return impl_->staged.has_value(); }

BrickUpload BrickRenderer::recordUpload(VkCommandBuffer cb, std::size_t budgetBytes, bool atLeastOneRow)
{
    Impl& m = *impl_;
    BrickUpload up;
    if (!m.staged) return up;
    Impl::Staged& s = *m.staged;
    const BrickAtlas& a = s.atlas;
    const std::size_t total = a.rows();
    if (total > 0) {
        std::size_t rows = std::min(total - s.rowsDone, budgetBytes / a.rowBytes());
        if (rows == 0 && atLeastOneRow) rows = 1;
        if (rows == 0) {
            up.rowsLeft = total - s.rowsDone;
            return up;
        }
        const std::size_t first = s.rowsDone, last = first + rows;
        const std::uint32_t width = a.texels.x, height = a.texels.y;
        // The rows as boxes of the image: the rest of a slice, whole
        // slices, the start of a slice.
        struct Box {
            std::size_t row, rows;
            VkOffset3D offset;
            VkExtent3D extent;
        };
        std::vector<Box> boxes;
        for (std::size_t r = first; r < last;) {
            const std::uint32_t y = std::uint32_t(r % height), z = std::uint32_t(r / height);
            if (y == 0 && last - r >= height) {
                const std::size_t slices = (last - r) / height;
                boxes.push_back({r, slices * height, {0, 0, std::int32_t(z)}, {width, height, std::uint32_t(slices)}});
                r += slices * height;
            } else {
                const std::size_t n = std::min<std::size_t>(height - y, last - r);
                boxes.push_back({r, n, {0, std::int32_t(y), std::int32_t(z)}, {width, std::uint32_t(n), 1}});
                r += n;
            }
        }
        // Each box's texels of each atlas at a 16-byte boundary of the
        // staging buffer (a copy's offset must be a multiple of its texel).
        struct Source {
            const void* data;
            std::size_t texelBytes;
            VkImage image;
        };
        const Source sources[3] = {{a.distance.data(), sizeof(std::int16_t), s.distance.image.get()},
                                   {a.normal.data(), sizeof(std::uint32_t), s.normal.image.get()},
                                   {a.feature.data(), sizeof(std::uint16_t), s.feature.image.get()}};
        auto aligned = [](std::size_t bytes) { return (bytes + 15) & ~std::size_t(15); };
        std::size_t need = 0;
        for (const Source& src : sources)
            for (const Box& b : boxes) need += aligned(b.rows * width * src.texelBytes);
        // Made for the most any frame of this many rows needs (their boxes,
        // and so their padding, vary: sized to each frame's own need, an
        // upload in equal pieces allocated again on two of its later frames).
        if (m.staging.size() < need) {
            m.staging = GpuBuffer(m.ctx, std::max(need, stagingBytesFor(a, rows)), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                  GpuBuffer::Kind::HostVisible, "brick atlas staging");
            ++m.frameAllocations;
        }
        auto* ring = static_cast<std::uint8_t*>(m.staging.mapped());
        struct Piece {
            std::uint8_t* to;
            const std::uint8_t* from;
            std::size_t bytes;
        };
        std::vector<Piece> pieces;
        std::size_t at = 0;
        for (const Source& src : sources) {
            if (first == 0)
                imageBarrier(cb, src.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                             VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT);
            std::vector<VkBufferImageCopy> regions;
            for (const Box& b : boxes) {
                const std::size_t bytes = b.rows * width * src.texelBytes;
                const auto* from = static_cast<const std::uint8_t*>(src.data) + b.row * width * src.texelBytes;
                for (std::size_t k = 0; k < bytes; k += kCopyPiece)
                    pieces.push_back({ring + at + k, from + k, std::min(kCopyPiece, bytes - k)});
                VkBufferImageCopy region{};
                region.bufferOffset = at;
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.imageOffset = b.offset;
                region.imageExtent = b.extent;
                regions.push_back(region);
                at += aligned(bytes);
            }
            vkCmdCopyBufferToImage(cb, m.staging.buffer(), src.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                   std::uint32_t(regions.size()), regions.data());
            if (last == total)
                imageBarrier(cb, src.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                             VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
        }
        // The copies into the staging memory are the frame's CPU cost (one
        // thread wrote 32 MiB into an H200's in 11 ms): spread over the
        // cores, isolated so that this thread does not pick up a voxelizer
        // task while it waits.
        tbb::this_task_arena::isolate([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces.size()), [&](const auto& range) {
                for (std::size_t i = range.begin(); i != range.end(); ++i)
                    std::memcpy(pieces[i].to, pieces[i].from, pieces[i].bytes);
            });
        });
        s.rowsDone = last;
        up.bytes = rows * a.rowBytes();
        up.rowsLeft = total - last;
        if (last < total) return up;
    }
    m.adoptStaged();
    up.completed = true;
    return up;
}

void BrickRenderer::Impl::adoptStaged()
{
    Staged& s = *staged;
    bricks = std::move(s.bricks);
    bounds = Aabb{};
    for (const Brick& b : bricks)
        bounds = bounds.merged(Aabb{b.min, b.min + b.voxelMm * double(b.cells)});
    sortedFor.reset();
    ++uploads;
    atlasSlots = s.atlas.slotCount;
    atlasTexels = s.atlas.texels;
    // What the frames no longer need goes on a thread of its own: the host
    // copy of the atlases just copied (freeing the chair's at 0.25 mm, 1.8
    // GB, made the upload's last frame the longest, 60 to 110 ms on an H200
    // host) and the atlases drawn before (the frames that read them have
    // finished; freeing device memory is safe on any thread).
    if (releasing.valid()) releasing.wait();
    releasing = std::async(std::launch::async,
                           [atlas = std::move(s.atlas), old = std::array{std::move(distance), std::move(normal),
                                                                          std::move(feature)}]() mutable {
                               BrickAtlas host = std::move(atlas);
                               auto device = std::move(old);
                           });
    distance = std::move(s.distance);
    normal = std::move(s.normal);
    feature = std::move(s.feature);
    if (bricks.empty()) {
        // Nothing to draw: record() draws nothing, so the descriptor set's
        // stale views are never read.
        instances = {};
        staged.reset();
        return;
    }
    VkDescriptorImageInfo infos[3] = {{linear, distance.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                                      {linear, normal.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                                      {nearest, feature.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
    VkWriteDescriptorSet writes[3]{};
    for (std::uint32_t i = 0; i < 3; ++i) {
        writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        writes[i].dstSet = set;
        writes[i].dstBinding = i;
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        writes[i].pImageInfo = &infos[i];
    }
    vkUpdateDescriptorSets(ctx.device(), 3, writes, 0, nullptr);
    if (s.instances.size() > 0) {
        instances = std::move(s.instances);
    } else {
        instances = makeInstanceBuffer(ctx, bricks.size());
        ++frameAllocations;
    }
    staged.reset();
}

std::size_t BrickRenderer::brickCount() const { return impl_->bricks.size(); }

Aabb BrickRenderer::bounds() const { return impl_->bounds; }

std::uint64_t BrickRenderer::version() const { return impl_->uploads; }

std::size_t BrickRenderer::residentBytes() const
{
    const Impl& m = *impl_;
    std::size_t bytes = m.distance.bytes + m.normal.bytes + m.feature.bytes + m.bricks.size() * sizeof(gpu::BrickInstance);
    if (m.staged) bytes += m.staged->distance.bytes + m.staged->normal.bytes + m.staged->feature.bytes;
    return bytes;
}

void BrickRenderer::Impl::sortInstances(const glm::dvec3& eye)
{
    const auto t0 = std::chrono::steady_clock::now();
    // Front to back by the distance of each brick's centre: the nearer
    // hits are drawn first and the depth test drops what they hide.
    std::vector<std::pair<float, std::uint32_t>> order(bricks.size());
    for (std::uint32_t b = 0; b < bricks.size(); ++b) {
        const Brick& brick = bricks[b];
        const glm::dvec3 centre = brick.min + 0.5 * brick.voxelMm * double(brick.cells);
        order[b] = {float(glm::length(centre - eye)), b};
    }
    std::sort(order.begin(), order.end());
    auto* out = static_cast<gpu::BrickInstance*>(instances.mapped());
    const std::uint32_t side = atlasSlots.x;
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::uint32_t b = order[i].second;
        const Brick& brick = bricks[b];
        const glm::dvec3 rel = brick.min - eye;
        const glm::uvec3 slot = BrickAtlas::slotOf(b, side) * std::uint32_t(kBrickSamples);
        out[i].minEdge = {float(rel.x), float(rel.y), float(rel.z), float(brick.voxelMm)};
        out[i].slot = {slot.x, slot.y, slot.z, std::uint32_t(brick.cells)};
    }
    sortedFor = eye;
    sortMilliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void BrickRenderer::Impl::ensureTargets(int w, int h)
{
    if (w == width && h == height) return;
    const VkExtent3D extent{std::uint32_t(w), std::uint32_t(h), 1};
    const VkImageUsageFlags colour = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    rayDepth = makeDeviceImage(ctx, extent, kRayDepthFormat, colour, VK_IMAGE_ASPECT_COLOR_BIT);
    normalTarget = makeDeviceImage(ctx, extent, kNormalTargetFormat, colour, VK_IMAGE_ASPECT_COLOR_BIT);
    featureTarget = makeDeviceImage(ctx, extent, kFeatureTargetFormat, colour, VK_IMAGE_ASPECT_COLOR_BIT);
    depthBuffer = makeDeviceImage(ctx, extent, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                  VK_IMAGE_ASPECT_DEPTH_BIT);
    VkImageView views[4] = {rayDepth.view, normalTarget.view, featureTarget.view, depthBuffer.view};
    VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fci.renderPass = renderPass;
    fci.attachmentCount = 4;
    fci.pAttachments = views;
    fci.width = std::uint32_t(w);
    fci.height = std::uint32_t(h);
    fci.layers = 1;
    VkFramebuffer fb;
    check(vkCreateFramebuffer(ctx.device(), &fci, nullptr, &fb), "vkCreateFramebuffer (bricks)");
    framebuffer = Framebuffer(ctx.device(), fb);
    const std::size_t pixels = std::size_t(w) * std::size_t(h);
    const VkBufferUsageFlags usage =
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    targets.depth = GpuBuffer(ctx, pixels * sizeof(float), usage, GpuBuffer::Kind::DeviceLocal, "brick depth");
    targets.normal = GpuBuffer(ctx, pixels * 16, usage, GpuBuffer::Kind::DeviceLocal, "brick normal");
    targets.feature = GpuBuffer(ctx, pixels * sizeof(std::uint32_t), usage, GpuBuffer::Kind::DeviceLocal, "brick feature");
    targets.width = width = w;
    targets.height = height = h;
}

void BrickRenderer::record(VkCommandBuffer cb, const Camera& camera, const Section& section)
{
    Impl& m = *impl_;
    const int w = camera.width(), h = camera.height();
    m.ensureTargets(w, h);
    m.sortMilliseconds = 0.0;
    if (!m.bricks.empty() && m.sortedFor != camera.eye()) m.sortInstances(camera.eye());

    vkCmdResetQueryPool(cb, m.timestamps, 0, 2);
    vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m.timestamps, 0);
    VkClearValue clears[4];
    clears[0].color.float32[0] = std::numeric_limits<float>::infinity();
    clears[1].color = {{0.0f, 0.0f, 0.0f, 0.0f}};
    clears[2].color.uint32[0] = kNoFeature;
    clears[3].depthStencil = {1.0f, 0};
    VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rbi.renderPass = m.renderPass;
    rbi.framebuffer = m.framebuffer;
    rbi.renderArea = {{0, 0}, {std::uint32_t(w), std::uint32_t(h)}};
    rbi.clearValueCount = 4;
    rbi.pClearValues = clears;
    vkCmdBeginRenderPass(cb, &rbi, VK_SUBPASS_CONTENTS_INLINE);
    if (!m.bricks.empty()) {
        VkViewport viewport{0.0f, 0.0f, float(w), float(h), 0.0f, 1.0f};
        VkRect2D scissor{{0, 0}, {std::uint32_t(w), std::uint32_t(h)}};
        vkCmdSetViewport(cb, 0, 1, &viewport);
        vkCmdSetScissor(cb, 0, 1, &scissor);
        gpu::BrickPush push{};
        const glm::mat4 clip(clipFromWorld(camera, camera.eye(), depthPlanesAround(camera, m.bounds)));
        std::memcpy(push.clipFromEye.m, &clip[0][0], sizeof push.clipFromEye.m);
        const glm::dvec3 f = camera.forward();
        push.forward = {float(f.x), float(f.y), float(f.z), camera.projection() == Projection::Orthographic ? 1.0f : 0.0f};
        push.atlasScale = {1.0f / float(m.atlasTexels.x), 1.0f / float(m.atlasTexels.y), 1.0f / float(m.atlasTexels.z), 0.0f};
        push.instances = m.instances.address();
        if (section.enabled) {
            // Relative to the eye, as the instances are: dot(n, eye + r) = offset.
            const glm::dvec3 n = section.normal;
            const double offset = section.offset - glm::dot(n, camera.eye());
            push.section = {float(n.x), float(n.y), float(n.z), float(offset)};
        }
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, m.pipeline);
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, m.layout, 0, 1, &m.set, 0, nullptr);
        vkCmdPushConstants(cb, m.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push, &push);
        vkCmdDraw(cb, 36, std::uint32_t(m.bricks.size()), 0, 0);
    }
    vkCmdEndRenderPass(cb);
    // Into the trace buffers, as the compute tracer leaves them.
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {std::uint32_t(w), std::uint32_t(h), 1};
    vkCmdCopyImageToBuffer(cb, m.rayDepth.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, m.targets.depth.buffer(), 1, &region);
    vkCmdCopyImageToBuffer(cb, m.normalTarget.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, m.targets.normal.buffer(), 1,
                           &region);
    vkCmdCopyImageToBuffer(cb, m.featureTarget.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, m.targets.feature.buffer(), 1,
                           &region);
    vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m.timestamps, 1);
    VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    after.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    after.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &after, 0, nullptr,
                         0, nullptr);
}

const TraceTargets& BrickRenderer::targets() const { return impl_->targets; }

double BrickRenderer::lastGpuMilliseconds() const
{
    std::uint64_t stamps[2] = {0, 0};
    check(vkGetQueryPoolResults(impl_->ctx.device(), impl_->timestamps, 0, 2, sizeof stamps, stamps,
                                sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults (bricks)");
    return double(stamps[1] - stamps[0]) * double(impl_->ctx.properties().limits.timestampPeriod) * 1e-6;
}

double BrickRenderer::lastSortMilliseconds() const { return impl_->sortMilliseconds; }

TraceImage BrickRenderer::render(const Camera& camera, double* gpuMilliseconds, const Section& section)
{
    impl_->ensureTargets(camera.width(), camera.height());
    TraceImage image =
        readTargets(impl_->ctx, impl_->targets, [&](VkCommandBuffer cb) { record(cb, camera, section); });
    if (gpuMilliseconds) *gpuMilliseconds = lastGpuMilliseconds();
    return image;
}

double BrickRenderer::sustainedMilliseconds(const Camera& camera, int frames, const Section& section)
{
    frames = std::max(frames, 1);
    const auto batch = [&] {
        const auto t0 = std::chrono::steady_clock::now();
        impl_->ctx.submitAndWait([&](VkCommandBuffer cb) {
            for (int f = 0; f < frames; ++f) record(cb, camera, section);
        });
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
    double warm = 0.0;
    for (int i = 0; i < 50 && warm < 300.0; ++i) warm += batch();
    return batch() / frames;
}

} // namespace kerf::vk

#include "kerf/viewport/SceneRenderer.hpp"

#include "kerf/viewport/ClipFromWorld.hpp"
#include "kerf/viewport/DeviceImage.hpp"
#include "kerf/viewport/GraphicsPipeline.hpp"
#include "kerf/viewport/ShaderModules.hpp"
#include "kerf/viewport/VulkanError.hpp"

#include "RenderShared.h"
#include "fullscreen.vert.h"
#include "gizmo.frag.h"
#include "grid.frag.h"
#include "mesh.frag.h"
#include "mesh.vert.h"
#include "part.frag.h"

#include <glm/glm.hpp>

#include <cstring>
#include <functional>
#include <limits>
#include <optional>

namespace kerf::vk {

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

gpu::RVec4 vec4(const glm::vec3& v, float w) { return {v.x, v.y, v.z, w}; }

float toLinear(std::uint8_t c)
{
    const float s = float(c) / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

} // namespace


struct SceneRenderer::Impl {
    const Context& ctx;
    RenderPass renderPass;
    PipelineLayout partLayout, meshLayout, gizmoLayout;
    Pipeline partPipeline, meshPipeline, markerPipeline, ghostPipeline, gridPipeline, gizmoPipeline;
    GpuBuffer shade;
    int width = 0, height = 0;
    DeviceImage color, depth;
    Framebuffer framebuffer;

    struct MeshBuffer {
        GpuBuffer vertices; // float x, y, z, nx, ny, nz per vertex, relative to meshOrigin
        std::uint32_t count = 0;
        glm::vec3 color;
        float opacity = 1.0f;
    };
    std::vector<MeshBuffer> meshes, markers, ghosts;
    glm::dvec3 meshOrigin{0.0};
    GpuBuffer frameColors; // this frame's feature colours and flags (one frame in flight)

    // What the tracer's targets hold: traced again only when this changes.
    struct TraceKey {
        const void* source = nullptr; // the ComputeTracer or BrickRenderer that traced
        VkDeviceAddress tiles = 0, entries = 0, nodes = 0;
        std::uint64_t voxelVersion = 0;
        glm::dvec3 eye{0.0}, forward{0.0}, up{0.0};
        double halfHeight = 0.0;
        int width = 0, height = 0;
        bool ortho = false;
        Section section;
        TraceQuality quality = TraceQuality::Voxels;
        bool operator==(const TraceKey&) const = default;
    };
    std::optional<TraceKey> traced;
    bool lastTraced = false;
    Aabb meshBounds;

    explicit Impl(const Context& c) : ctx(c) {}
    void ensureTargets(int w, int h);
    // The frame: `trace` records the trace into the targets `targets`
    // returns, when `key` differs from the last frame's; `part` bounds it.
    void recordFrame(VkCommandBuffer cb, const Camera& camera, const std::vector<Feature>& features,
                     const SceneOptions& options, const Section& section, const Aabb& part, const TraceKey& key,
                     const std::function<void(VkCommandBuffer)>& trace, const TraceTargets& targets);
    Pipeline makePipeline(VkPipelineLayout layout, const ShaderModule& vs, const ShaderModule& fs,
                          const GraphicsPipelineStyle& style);
    std::vector<MeshBuffer> upload(const std::vector<PlacedMesh>& placed) const;
    void drawMeshes(VkCommandBuffer cb, const std::vector<MeshBuffer>& list, VkPipeline pipeline,
                    const glm::mat4& clip, std::uint64_t shadeAddress) const;
};

void SceneRenderer::Impl::ensureTargets(int w, int h)
{
    if (w == width && h == height) return;
    color = makeDeviceImage(ctx, {std::uint32_t(w), std::uint32_t(h), 1}, kColorFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                       VK_IMAGE_ASPECT_COLOR_BIT);
    depth = makeDeviceImage(ctx, {std::uint32_t(w), std::uint32_t(h), 1}, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
    VkImageView views[2] = {color.view, depth.view};
    VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fci.renderPass = renderPass;
    fci.attachmentCount = 2;
    fci.pAttachments = views;
    fci.width = std::uint32_t(w);
    fci.height = std::uint32_t(h);
    fci.layers = 1;
    VkFramebuffer fb;
    check(vkCreateFramebuffer(ctx.device(), &fci, nullptr, &fb), "vkCreateFramebuffer");
    framebuffer = Framebuffer(ctx.device(), fb);
    width = w;
    height = h;
}

Pipeline SceneRenderer::Impl::makePipeline(VkPipelineLayout layout, const ShaderModule& vs, const ShaderModule& fs,
                                           const GraphicsPipelineStyle& style)
{
    return makeGraphicsPipeline(ctx.device(), renderPass, layout, vs, fs, style, "vkCreateGraphicsPipelines (scene)");
}

SceneRenderer::SceneRenderer(const Context& ctx) : impl_(std::make_unique<Impl>(ctx))
{
    VkDevice dev = ctx.device();
    const VkFormat colour[1] = {kColorFormat};
    impl_->renderPass = makeCopiedRenderPass(dev, colour, kDepthFormat, "vkCreateRenderPass (scene)");

    VkPushConstantRange partRange{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(std::uint64_t)};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &partRange;
    VkPipelineLayout pl;
    check(vkCreatePipelineLayout(dev, &plci, nullptr, &pl), "vkCreatePipelineLayout (part)");
    impl_->partLayout = PipelineLayout(dev, pl);
    VkPushConstantRange meshRange{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(gpu::MeshPush)};
    plci.pPushConstantRanges = &meshRange;
    check(vkCreatePipelineLayout(dev, &plci, nullptr, &pl), "vkCreatePipelineLayout (mesh)");
    impl_->meshLayout = PipelineLayout(dev, pl);

    VkPushConstantRange gizmoRange{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(gpu::GizmoPush)};
    plci.pPushConstantRanges = &gizmoRange;
    check(vkCreatePipelineLayout(dev, &plci, nullptr, &pl), "vkCreatePipelineLayout (gizmo)");
    impl_->gizmoLayout = PipelineLayout(dev, pl);

    const ShaderModule fullscreen = makeShaderModule(dev, kFullscreenVert, sizeof kFullscreenVert, "shader fullscreen.vert");
    const ShaderModule part = makeShaderModule(dev, kPartFrag, sizeof kPartFrag, "shader part.frag");
    const ShaderModule meshVert = makeShaderModule(dev, kMeshVert, sizeof kMeshVert, "shader mesh.vert");
    const ShaderModule meshFrag = makeShaderModule(dev, kMeshFrag, sizeof kMeshFrag, "shader mesh.frag");
    const ShaderModule grid = makeShaderModule(dev, kGridFrag, sizeof kGridFrag, "shader grid.frag");
    const ShaderModule gizmo = makeShaderModule(dev, kGizmoFrag, sizeof kGizmoFrag, "shader gizmo.frag");
    // The part pass writes the traced depth everywhere; meshes test against
    // it; the grid tests without writing and blends; markers and the gizmo
    // are drawn over everything.
    impl_->partPipeline = impl_->makePipeline(impl_->partLayout, fullscreen, part, {});
    impl_->meshPipeline =
        impl_->makePipeline(impl_->meshLayout, meshVert, meshFrag, {true, VK_COMPARE_OP_LESS_OR_EQUAL, true, false});
    impl_->markerPipeline =
        impl_->makePipeline(impl_->meshLayout, meshVert, meshFrag, {true, VK_COMPARE_OP_ALWAYS, false, false});
    impl_->ghostPipeline =
        impl_->makePipeline(impl_->meshLayout, meshVert, meshFrag, {true, VK_COMPARE_OP_ALWAYS, false, true});
    impl_->gridPipeline =
        impl_->makePipeline(impl_->partLayout, fullscreen, grid, {false, VK_COMPARE_OP_LESS_OR_EQUAL, false, true});
    impl_->gizmoPipeline =
        impl_->makePipeline(impl_->gizmoLayout, fullscreen, gizmo, {false, VK_COMPARE_OP_ALWAYS, false, true});
    impl_->shade = GpuBuffer(ctx, sizeof(gpu::ShadeParams),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             GpuBuffer::Kind::DeviceLocal, "shade params");
}

SceneRenderer::~SceneRenderer() = default;

bool SceneRenderer::lastFrameTraced() const { return impl_->lastTraced; }

std::vector<SceneRenderer::Impl::MeshBuffer> SceneRenderer::Impl::upload(const std::vector<PlacedMesh>& placed) const
{
    std::vector<MeshBuffer> out;
    for (const auto& m : placed) {
        if (m.mesh.positions.empty()) continue;
        std::vector<float> v;
        v.reserve(m.mesh.positions.size() * 6);
        for (std::size_t i = 0; i < m.mesh.positions.size(); ++i) {
            const glm::dvec3 p = m.worldFromLocal.apply(m.mesh.positions[i]) - meshOrigin;
            const glm::vec3 n = glm::normalize(glm::vec3(m.worldFromLocal.applyLinear(glm::dvec3(m.mesh.normals[i]))));
            v.insert(v.end(), {float(p.x), float(p.y), float(p.z), n.x, n.y, n.z});
        }
        MeshBuffer b;
        b.vertices = uploadBuffer(ctx, v.data(), v.size() * sizeof(float), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                  "mesh vertices");
        b.count = std::uint32_t(m.mesh.positions.size());
        b.color = m.color;
        b.opacity = m.opacity;
        out.push_back(std::move(b));
    }
    return out;
}

void SceneRenderer::Impl::drawMeshes(VkCommandBuffer cb, const std::vector<MeshBuffer>& list, VkPipeline pipeline,
                                     const glm::mat4& clip, std::uint64_t shadeAddress) const
{
    if (list.empty()) return;
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    for (const auto& m : list) {
        gpu::MeshPush push{};
        std::memcpy(push.clipFromWorld.m, &clip[0][0], sizeof push.clipFromWorld.m);
        push.color = vec4(m.color, m.opacity);
        push.shade = shadeAddress;
        vkCmdPushConstants(cb, meshLayout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push,
                           &push);
        const VkDeviceSize offset = 0;
        const VkBuffer vb = m.vertices.buffer();
        vkCmdBindVertexBuffers(cb, 0, 1, &vb, &offset);
        vkCmdDraw(cb, m.count, 1, 0, 0);
    }
}

void SceneRenderer::setMeshes(const std::vector<PlacedMesh>& meshes)
{
    // The origin is chosen once per mesh set; markers are placed relative
    // to the same origin.
    impl_->meshBounds = Aabb::empty();
    for (const auto& m : meshes) impl_->meshBounds = impl_->meshBounds.merged(m.worldBounds());
    // Vertices relative to the meshes' centre: float keeps its precision.
    impl_->meshOrigin = impl_->meshBounds.isEmpty() ? glm::dvec3(0.0) : impl_->meshBounds.center();
    impl_->meshes = impl_->upload(meshes);
}

void SceneRenderer::setMarkers(const std::vector<PlacedMesh>& markers) { impl_->markers = impl_->upload(markers); }

void SceneRenderer::setGhosts(const std::vector<PlacedMesh>& ghosts) { impl_->ghosts = impl_->upload(ghosts); }

VkImage SceneRenderer::colorImage() const { return impl_->color.image; }

RgbaImage SceneRenderer::render(ComputeTracer& tracer, const VoxelAddresses& voxels, const Camera& camera,
                                const std::vector<Feature>& features, const SceneOptions& options, const Section& section)
{
    impl_->ctx.submitAndWait(
        [&](VkCommandBuffer cb) { record(cb, tracer, voxels, camera, features, options, section); });
    return readPicture();
}

RgbaImage SceneRenderer::readPicture() const
{
    const Context& ctx = impl_->ctx;
    RgbaImage out;
    const int w = impl_->width, h = impl_->height;
    if (w == 0 || h == 0) return out;
    GpuBuffer readback(ctx, std::size_t(w) * std::size_t(h) * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       GpuBuffer::Kind::Readback, "colour readback");
    ctx.submitAndWait([&](VkCommandBuffer cb) {
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {std::uint32_t(w), std::uint32_t(h), 1};
        vkCmdCopyImageToBuffer(cb, impl_->color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer(), 1,
                               &region);
        VkMemoryBarrier host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &host, 0, nullptr, 0,
                             nullptr);
    });
    out.width = w;
    out.height = h;
    out.pixels.resize(std::size_t(w) * std::size_t(h) * 4);
    std::memcpy(out.pixels.data(), readback.mapped(), out.pixels.size());
    return out;
}

void SceneRenderer::record(VkCommandBuffer cb, ComputeTracer& tracer, const VoxelAddresses& voxels,
                           const Camera& camera, const std::vector<Feature>& features, const SceneOptions& options,
                           const Section& section)
{
    const Impl::TraceKey key{&tracer,      voxels.tiles,     voxels.entries, voxels.nodes, voxels.version,
                             camera.eye(), camera.forward(), camera.up(),    camera.halfHeight(),
                             camera.width(), camera.height(), camera.projection() == Projection::Orthographic, section,
                             options.quality};
    impl_->recordFrame(cb, camera, features, options, section, voxels.tiles ? voxels.grid.bounds() : Aabb{}, key,
                       [&](VkCommandBuffer c) { tracer.record(c, camera, voxels, section, options.quality); },
                       tracer.targets());
}

void SceneRenderer::record(VkCommandBuffer cb, BrickRenderer& bricks, const Camera& camera,
                           const std::vector<Feature>& features, const SceneOptions& options, const Section& section)
{
    const Impl::TraceKey key{&bricks,      0,                0,              0,            bricks.version(),
                             camera.eye(), camera.forward(), camera.up(),    camera.halfHeight(),
                             camera.width(), camera.height(), camera.projection() == Projection::Orthographic, section,
                             TraceQuality::Voxels};
    impl_->recordFrame(cb, camera, features, options, section, bricks.bounds(), key,
                       [&](VkCommandBuffer c) { bricks.record(c, camera, section); }, bricks.targets());
}

RgbaImage SceneRenderer::render(BrickRenderer& bricks, const Camera& camera, const std::vector<Feature>& features,
                                const SceneOptions& options, const Section& section)
{
    impl_->ctx.submitAndWait([&](VkCommandBuffer cb) { record(cb, bricks, camera, features, options, section); });
    return readPicture();
}

void SceneRenderer::Impl::recordFrame(VkCommandBuffer cb, const Camera& camera, const std::vector<Feature>& features,
                                      const SceneOptions& options, const Section& section, const Aabb& part,
                                      const TraceKey& key, const std::function<void(VkCommandBuffer)>& trace,
                                      const TraceTargets& targets)
{
    const int w = camera.width(), h = camera.height();
    ensureTargets(w, h);
    const bool ortho = camera.projection() == Projection::Orthographic;
    const double halfHeight = camera.halfHeight();

    // Near and far planes around everything drawn (the grid's visible reach too).
    Aabb scene = meshBounds;
    if (!part.isEmpty()) scene = scene.merged(part);
    const double sceneSize = scene.isEmpty() ? 1000.0 : std::max(glm::length(scene.size()), 1.0);
    const double gridReach = 4.0 * sceneSize;
    if (options.grid) {
        const glm::dvec3 c = scene.isEmpty() ? glm::dvec3(0.0) : scene.center();
        scene = scene.merged(Aabb{{c.x - gridReach, c.y - gridReach, 0.0}, {c.x + gridReach, c.y + gridReach, 0.0}});
    }
    const DepthPlanes planes = depthPlanesAround(camera, scene);
    const double near = planes.near, far = planes.far;

    // Feature colours and flags, this frame's.
    std::vector<float> colors;
    colors.reserve(features.size() * 4 + 4);
    for (const auto& f : features) {
        if (f.hasColor)
            colors.insert(colors.end(), {toLinear(f.color.r), toLinear(f.color.g), toLinear(f.color.b),
                                         float(KERF_FEATURE_HAS_COLOR)});
        else
            colors.insert(colors.end(), {0, 0, 0, 0});
    }
    for (std::uint32_t sel : options.selectedFeatures)
        if (sel < features.size()) colors[4 * sel + 3] += float(KERF_FEATURE_SELECTED);
    if (colors.empty()) colors.assign(4, 0.0f);
    frameColors = GpuBuffer(ctx, colors.size() * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                   GpuBuffer::Kind::HostVisible, "feature colours");
    std::memcpy(frameColors.mapped(), colors.data(), colors.size() * sizeof(float));

    lastTraced = !(traced && *traced == key);
    if (lastTraced) trace(cb);
    traced = key;

    gpu::ShadeParams s{};
    s.depth = targets.depth.address();
    s.normal = targets.normal.address();
    s.feature = targets.feature.address();
    s.featureColors = frameColors.address();
    s.featureCount = std::uint32_t(features.size());
    s.width = std::uint32_t(w);
    s.height = std::uint32_t(h);
    s.flags = (ortho ? KERF_SHADE_ORTHO : 0u) | (options.edges ? KERF_SHADE_EDGES : 0u);
    s.forward = vec4(glm::vec3(camera.forward()), float(near));
    s.right = vec4(glm::vec3(camera.right()), float(far));
    s.up = vec4(glm::vec3(camera.up()), float(halfHeight));
    s.light = vec4(glm::normalize(options.lights.lightDirection), options.lights.keyStrength);
    s.view = vec4(glm::normalize(options.lights.viewDirection), options.lights.headlightStrength);
    s.sky = vec4(options.lights.sky, 0.25f);
    s.ground = vec4(options.lights.ground, 48.0f);
    s.backgroundTop = {0.52f, 0.56f, 0.62f, 1.0f};
    s.backgroundBottom = {0.20f, 0.21f, 0.23f, 1.0f};
    s.defaultColor = vec4(options.defaultColor, options.edgeDarkening);
    s.highlight = vec4(options.highlight, options.highlightStrength);
    s.eye = vec4(glm::vec3(camera.eye()), 0.0f);
    // Grid lines: minor spacing a power of ten near 1/40 of the view's
    // height at the part, major ten times that.
    const double viewHeight = ortho ? 2.0 * halfHeight
                                    : 2.0 * halfHeight * std::max(glm::dot(scene.center() - camera.eye(), camera.forward()), 1.0);
    const double minor = std::pow(10.0, std::floor(std::log10(std::max(viewHeight / 40.0, 1e-3))));
    s.grid = {float(minor), float(10.0 * minor), float(gridReach), options.grid ? 1.0f : 0.0f};
    s.section = vec4(glm::vec3(section.normal), float(section.offset));
    s.capColor = vec4(options.capColor, 6.0f);
    vkCmdUpdateBuffer(cb, shade.buffer(), 0, sizeof s, &s);
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT, 0, 1, &mb, 0,
                         nullptr, 0, nullptr);

    VkClearValue clears[2];
    clears[0].color = {{0.0f, 0.0f, 0.0f, 1.0f}};
    clears[1].depthStencil = {1.0f, 0};
    VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rbi.renderPass = renderPass;
    rbi.framebuffer = framebuffer;
    rbi.renderArea = {{0, 0}, {std::uint32_t(w), std::uint32_t(h)}};
    rbi.clearValueCount = 2;
    rbi.pClearValues = clears;
    vkCmdBeginRenderPass(cb, &rbi, VK_SUBPASS_CONTENTS_INLINE);
    VkViewport viewport{0.0f, 0.0f, float(w), float(h), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, {std::uint32_t(w), std::uint32_t(h)}};
    vkCmdSetViewport(cb, 0, 1, &viewport);
    vkCmdSetScissor(cb, 0, 1, &scissor);

    const std::uint64_t shadeAddress = shade.address();
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, partPipeline);
    vkCmdPushConstants(cb, partLayout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof shadeAddress, &shadeAddress);
    vkCmdDraw(cb, 3, 1, 0, 0);

    if (!meshes.empty() || !markers.empty()) {
        const glm::mat4 clip(clipFromWorld(camera, meshOrigin, planes));
        drawMeshes(cb, meshes, meshPipeline, clip, shadeAddress);
        if (options.grid) {
            vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, gridPipeline);
            vkCmdPushConstants(cb, partLayout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof shadeAddress,
                               &shadeAddress);
            vkCmdDraw(cb, 3, 1, 0, 0);
        }
        drawMeshes(cb, ghosts, ghostPipeline, clip, shadeAddress);
        drawMeshes(cb, markers, markerPipeline, clip, shadeAddress);
    } else if (options.grid) {
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, gridPipeline);
        vkCmdPushConstants(cb, partLayout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof shadeAddress, &shadeAddress);
        vkCmdDraw(cb, 3, 1, 0, 0);
    }

    if (options.axes) {
        const float size = float(std::min({96, w, h}));
        const float x = 8.0f, y = float(h) - size - 8.0f;
        VkViewport gv{x, y, size, size, 0.0f, 1.0f};
        VkRect2D gs{{std::int32_t(x), std::int32_t(y)}, {std::uint32_t(size), std::uint32_t(size)}};
        if (x >= 0.0f && y >= 0.0f) {
            vkCmdSetViewport(cb, 0, 1, &gv);
            vkCmdSetScissor(cb, 0, 1, &gs);
            gpu::GizmoPush push{};
            push.shade = shadeAddress;
            push.rect = {x, y, size, 0.0f};
            vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, gizmoPipeline);
            vkCmdPushConstants(cb, gizmoLayout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push, &push);
            vkCmdDraw(cb, 3, 1, 0, 0);
        }
    }
    vkCmdEndRenderPass(cb);
}

} // namespace kerf::vk

#include "kerf/viewport/ViewportRenderer.hpp"

#include "kerf/viewport/DeviceImage.hpp"
#include "kerf/viewport/VulkanError.hpp"

#include <algorithm>
#include <chrono>
#include <future>
#include <cmath>
#include <cstring>

namespace kerf::vk {

namespace {

Semaphore makeSemaphore(VkDevice dev)
{
    VkSemaphoreCreateInfo ci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore s;
    check(vkCreateSemaphore(dev, &ci, nullptr, &s), "vkCreateSemaphore");
    return Semaphore(dev, s);
}


} // namespace

struct ViewportRenderer::Impl {
    const Context& ctx;
    Swapchain swapchain;
    ComputeTracer tracer;
    SceneRenderer scene;
    VoxelStreamer streamer;
    CommandPool pool;
    VkCommandBuffer cb = VK_NULL_HANDLE;
    Fence fence;
    Semaphore acquired;
    std::vector<Semaphore> rendered; // one per swapchain image: presentation may still wait on the last one
    std::shared_ptr<const VoxelSnapshot> target;
    std::shared_ptr<const std::vector<PlacedMesh>> meshes, markers, ghosts;
    GpuBuffer depthReadback; // the trace's depth, for the occlusion picture
    // The GPU voxelizer, made on the first request.
    std::function<void()> wake;
    std::unique_ptr<GpuVoxelWorker> worker;
    std::shared_ptr<const GpuVoxelRequest> gpuRequest;
    std::unique_ptr<GpuVoxelResult> gpuShown;
    // The brick renderer: the snapshot whose bricks it draws, the one whose
    // bricks it is copying in (under the frame's upload budget), and the
    // bricks of another being made and packed on a thread of their own.
    BrickRenderer bricks;
    std::shared_ptr<const VoxelSnapshot> bricksOf, uploadingBricksOf, makingBricksOf;
    std::future<PreparedBricks> makingBricks;
    StreamingOptions streamingOptions;

    Impl(const Context& c, VkSurfaceKHR surface, StreamingOptions streaming, std::function<void()> w)
        : ctx(c), swapchain(c, surface), tracer(c), scene(c), streamer(c, streaming), wake(std::move(w)), bricks(c),
          streamingOptions(streaming)
    {
        VkDevice dev = c.device();
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = c.queueFamily();
        VkCommandPool p;
        check(vkCreateCommandPool(dev, &pci, nullptr, &p), "vkCreateCommandPool (viewport)");
        pool = CommandPool(dev, p);
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = pool;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 1;
        check(vkAllocateCommandBuffers(dev, &ai, &cb), "vkAllocateCommandBuffers (viewport)");
        VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence f;
        check(vkCreateFence(dev, &fi, nullptr, &f), "vkCreateFence (viewport)");
        fence = Fence(dev, f);
        acquired = makeSemaphore(dev);
    }
};

ViewportRenderer::ViewportRenderer(const Context& ctx, VkSurfaceKHR surface, StreamingOptions streaming,
                                   std::function<void()> wake)
    : impl_(std::make_unique<Impl>(ctx, surface, streaming, std::move(wake)))
{
}

ViewportRenderer::~ViewportRenderer()
{
    if (!impl_) return;
    impl_->worker.reset(); // stops its build before the device goes idle
    const auto queueLock = impl_->ctx.lockQueue();
    vkDeviceWaitIdle(impl_->ctx.device());
}

void ViewportRenderer::releaseSurface()
{
    {
        const auto queueLock = impl_->ctx.lockQueue();
        vkDeviceWaitIdle(impl_->ctx.device());
    }
    impl_->swapchain.release();
    impl_->rendered.clear();
}

FrameStats ViewportRenderer::drawFrame(const ViewportScene& scene, int width, int height)
{
    const auto start = std::chrono::steady_clock::now();
    Impl& m = *impl_;
    FrameStats st;
    if (scene.snapshot != m.target) {
        m.target = scene.snapshot;
        m.streamer.setTarget(m.target);
    }
    // Markers and ghosts are uploaded relative to the meshes' origin: new
    // meshes move it, so they go up again too.
    const bool newOrigin = scene.meshes != m.meshes;
    if (newOrigin) {
        m.meshes = scene.meshes;
        m.scene.setMeshes(m.meshes ? *m.meshes : std::vector<PlacedMesh>{});
    }
    if (newOrigin || scene.markers != m.markers) {
        m.markers = scene.markers;
        m.scene.setMarkers(m.markers ? *m.markers : std::vector<PlacedMesh>{});
    }
    if (newOrigin || scene.ghosts != m.ghosts) {
        m.ghosts = scene.ghosts;
        m.scene.setGhosts(m.ghosts ? *m.ghosts : std::vector<PlacedMesh>{});
    }
    // The GPU voxelizer: a new request to it, and its newest build on screen.
    if (scene.gpuVoxels != m.gpuRequest) {
        m.gpuRequest = scene.gpuVoxels;
        if (m.gpuRequest) {
            if (!m.worker) m.worker = std::make_unique<GpuVoxelWorker>(m.ctx, m.wake);
            m.worker->request(*m.gpuRequest);
        } else if (m.worker) {
            m.worker->cancel();
        }
    }
    if (m.worker) {
        if (auto built = m.worker->take()) {
            // The last frame, which read the build on screen, has finished.
            m.worker->recycle(std::move(m.gpuShown));
            m.gpuShown = std::move(built);
        }
        // Back on the CPU's snapshots: the GPU's build stays until they are on the device.
        if (!m.gpuRequest && m.gpuShown && m.streamer.resident().valid() && m.streamer.upToDate())
            m.worker->recycle(std::move(m.gpuShown));
    }
    if (!m.swapchain.ensure(width, height)) return st;
    std::optional<std::uint32_t> index = m.swapchain.acquire(m.acquired);
    if (!index) {
        if (!m.swapchain.ensure(width, height)) return st;
        index = m.swapchain.acquire(m.acquired);
        if (!index) return st;
    }
    while (m.rendered.size() <= *index)
        m.rendered.push_back(makeSemaphore(m.ctx.device()));
    const int w = m.swapchain.width(), h = m.swapchain.height();
    const double scale = std::clamp(scene.resolutionScale, 0.05, 1.0);
    const int tw = std::max(1, int(std::lround(w * scale))), th = std::max(1, int(std::lround(h * scale)));

    check(vkResetCommandBuffer(m.cb, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(m.cb, &bi), "vkBeginCommandBuffer (viewport)");
    st.upload = m.streamer.recordFrame(m.cb);

    const ResidentSet& resident = m.streamer.resident();
    const auto& shown = m.streamer.residentSnapshot();
    const GpuVoxelResult* gpu = m.gpuShown.get();
    static const std::vector<Feature> kNoFeatures;
    const std::vector<Feature>& features = gpu                        ? (gpu->features ? *gpu->features : kNoFeatures)
                                           : shown && shown->features ? *shown->features
                                                                      : kNoFeatures;
    const Aabb bounds = gpu ? (gpu->voxels->entryCount() > 0 ? gpu->voxels->layout.bounds() : Aabb::empty())
                        : resident.valid() ? resident.layout.bounds()
                                           : Aabb::empty();
    const Camera camera = scene.view.camera(tw, th, bounds);
    SceneOptions options;
    options.lights = ShadeOptions::forCamera(camera);
    options.grid = scene.grid;
    options.axes = scene.axes;
    options.edges = scene.edges;
    options.quality = scene.quality;
    if (scene.selectedFeatureNodes && !scene.selectedFeatureNodes->empty())
        for (std::uint32_t i = 0; i < features.size(); ++i)
            if (scene.selectedFeatureNodes->count(features[i].nodeId)) options.selectedFeatures.push_back(i);
    // GPU builds count their versions from the top of the range, apart from the snapshots'.
    const VoxelAddresses voxels = gpu                ? gpu->voxels->addresses(~std::uint64_t(0) - gpu->version)
                                  : resident.valid() ? VoxelAddresses::of(resident)
                                                     : VoxelAddresses{};
    // The brick renderer, where it can draw this frame: the bricks of the
    // snapshot on screen, once made (on a thread of their own).
    const bool bricksCanDraw = scene.bricks && !gpu && shown && resident.valid() && scene.quality == TraceQuality::Voxels;
    if (!scene.bricks) {
        // Off: the atlases go (the last frame that read them has finished),
        // and so do bricks made or copied for nothing.
        if (m.bricksOf || m.bricks.uploading()) {
            m.bricks.setBricks(BrickLeaves{});
            m.bricksOf.reset();
            m.uploadingBricksOf.reset();
        }
        if (m.makingBricks.valid() && m.makingBricks.wait_for(std::chrono::seconds(0)) == std::future_status::ready)
            m.makingBricks.get();
    }
    if (bricksCanDraw && m.bricksOf != shown && m.uploadingBricksOf != shown) {
        if (m.makingBricks.valid() &&
            m.makingBricks.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
            PreparedBricks made = m.makingBricks.get();
            if (m.makingBricksOf == shown) {
                m.bricks.stage(std::move(made));
                m.uploadingBricksOf = shown;
            }
        }
        if (m.uploadingBricksOf != shown && !m.makingBricks.valid()) {
            m.makingBricksOf = shown;
            // No wake from the task: the owner may be tearing the renderer
            // down (and hold what wake takes) while this future's destructor
            // waits for it. Frames go on instead while it works (upToDate).
            // The atlases and the staging memory are made there too: a frame
            // allocates nothing for them (BrickRenderer::prepare).
            m.makingBricks = std::async(std::launch::async, [snapshot = shown, side = m.bricks.maxImageDimension3D(),
                                                             &ctx = m.ctx,
                                                             budget = m.streamingOptions.budgetBytesPerFrame] {
                BrickLeaves leaves = BrickLeaves::fromVoxels(FlatVoxelBuffers::flatten(*snapshot));
                BrickAtlas atlas = BrickAtlas::pack(leaves, side);
                return BrickRenderer::prepare(ctx, std::move(leaves.bricks), std::move(atlas), budget);
            });
        }
    }
    // The atlases go up in rows within what the voxels' streaming left of
    // the frame's budget (a row at least when it left all of it); the bricks
    // drawn before, or the tracer, draw until the last row is there.
    if (scene.bricks) {
        const std::size_t budget = m.streamingOptions.budgetBytesPerFrame;
        const BrickUpload up = m.bricks.recordUpload(m.cb, budget - std::min(budget, st.upload.bytes),
                                                     st.upload.bytes == 0);
        st.upload.bytes += up.bytes;
        st.brickBytes = up.bytes;
        st.brickRowsPending = up.rowsLeft;
        if (up.completed) {
            m.bricksOf = m.uploadingBricksOf;
            m.uploadingBricksOf.reset();
        }
    }
    st.drewBricks = bricksCanDraw && m.bricksOf == shown;
    if (st.drewBricks)
        m.scene.record(m.cb, m.bricks, camera, features, options, scene.section);
    else
        m.scene.record(m.cb, m.tracer, voxels, camera, features, options, scene.section);
    st.traced = m.scene.lastFrameTraced();
    // The voxelizer's occlusion picture: only a full-resolution trace of the
    // very view it plans for (the record's barrier makes the depth readable).
    const bool readDepth = st.traced && tw == w && th == h && scene.occlusionView &&
                           viewRequirement(camera, scene.occlusionView->pixelsPerVoxel) == *scene.occlusionView;
    const std::size_t depthBytes = std::size_t(tw) * std::size_t(th) * sizeof(float);
    if (readDepth) {
        if (m.depthReadback.size() < depthBytes)
            m.depthReadback = GpuBuffer(m.ctx, depthBytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GpuBuffer::Kind::Readback,
                                        "occlusion depth");
        const VkBufferCopy region{0, 0, depthBytes};
        const TraceTargets& traced = st.drewBricks ? m.bricks.targets() : m.tracer.targets();
        vkCmdCopyBuffer(m.cb, traced.depth.buffer(), m.depthReadback.buffer(), 1, &region);
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(m.cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0,
                             nullptr);
    }

    // Copy (and scale) the picture into the window's image.
    const VkImage target = m.swapchain.image(*index);
    imageBarrier(m.cb, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                 VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkImageBlit blit{};
    blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.srcOffsets[1] = {tw, th, 1};
    blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.dstOffsets[1] = {w, h, 1};
    vkCmdBlitImage(m.cb, m.scene.colorImage(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit,
                   tw == w && th == h ? VK_FILTER_NEAREST : VK_FILTER_LINEAR);
    imageBarrier(m.cb, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                 VK_ACCESS_TRANSFER_WRITE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    check(vkEndCommandBuffer(m.cb), "vkEndCommandBuffer (viewport)");

    const VkSemaphore wait = m.acquired, signal = m.rendered[*index];
    const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &wait;
    si.pWaitDstStageMask = &waitStage;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &m.cb;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &signal;
    const VkFence f = m.fence;
    {
        const auto queueLock = m.ctx.lockQueue();
        check(vkQueueSubmit(m.ctx.queue(), 1, &si, f), "vkQueueSubmit (viewport)");
    }
    st.presented = m.swapchain.present(*index, signal);
    check(vkWaitForFences(m.ctx.device(), 1, &f, VK_TRUE, UINT64_MAX), "vkWaitForFences (viewport)");
    check(vkResetFences(m.ctx.device(), 1, &f), "vkResetFences (viewport)");

    if (st.traced) st.traceGpuMs = st.drewBricks ? m.bricks.lastGpuMilliseconds() : m.tracer.lastTiming().gpuMilliseconds;
    if (readDepth)
        st.picture = std::make_shared<const OcclusionMap>(
            OcclusionMap::fromDepths(*scene.occlusionView, tw, th,
                                     std::span<const float>(static_cast<const float*>(m.depthReadback.mapped()),
                                                            std::size_t(tw) * std::size_t(th))));
    if (gpu) {
        st.gpuVoxels = true;
        // The worker wakes the owner when it has more; back on the CPU's
        // snapshots, frames go on until they are on the device and replace it.
        st.upToDate = m.gpuRequest != nullptr;
        st.shownVersion = gpu->version;
        st.shownRevision = gpu->revision;
        st.shownComplete = gpu->complete;
        st.residentBytes = gpu->voxels->bytes();
        st.heapBytes = gpu->report.poolBytes;
        st.gpuBuildMs = gpu->requestMilliseconds;
    } else {
        // Bricks still being made or copied for the snapshot on screen: not there yet.
        st.upToDate = m.streamer.upToDate() && !(bricksCanDraw && !st.drewBricks);
        st.shownVersion = shown ? shown->version : 0;
        st.shownRevision = shown ? shown->documentRevision : 0;
        st.shownComplete = shown && shown->complete;
        // The bricks drawn are device memory too (about three times the
        // voxels'), outside the voxel budget.
        st.residentBytes = resident.bytes + (m.bricksOf ? m.bricks.residentBytes() : 0);
        st.heapBytes = m.streamer.heapCapacity();
    }
    if (m.worker) {
        st.gpuBusy = m.gpuRequest && m.worker->busy();
        st.gpuRefusal = m.worker->refusal();
        st.gpuRefusedRevision = m.worker->refusedRevision();
    }
    st.width = w;
    st.height = h;
    st.traceWidth = tw;
    st.traceHeight = th;
    st.frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return st;
}

RgbaImage ViewportRenderer::lastPicture() { return impl_->scene.readPicture(); }

} // namespace kerf::vk

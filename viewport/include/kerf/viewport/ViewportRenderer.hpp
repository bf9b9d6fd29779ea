#pragma once
// The frames of a viewport in a window: each frame streams the newest voxel
// snapshot a step further under the upload budget, traces when the view,
// the size, the section or the resident voxels changed, shades, draws the
// meshes, the grid and the gizmo, and copies the picture to the window's
// swapchain. Until a snapshot is wholly resident the previous one stays on
// screen (VoxelStreamer), so a frame never waits for voxelization or for a
// large upload: at most one budget's worth of copying per frame (the voxels'
// tiles first, then the brick renderer's atlases in what they leave).
//
// The voxels come from the CPU voxelizer's snapshots (streamed as above) or,
// when the scene carries a GPU request, from the GPU voxelizer working in
// the background (GpuVoxelWorker): its preview, then its full-depth build,
// each traced in place the frame after it is done; the build on screen
// stays until the next one is complete, and goes back to the voxelizer's
// pools when no frame reads it.
//
// While the camera moves on a slow device the trace can run at a fraction
// of the window's resolution (ViewportScene::resolutionScale), scaled up by
// the copy to the window; still frames are traced at full resolution.
//
// With ViewportScene::bricks the part is drawn by the brick renderer
// (BrickRenderer.hpp) instead of the compute tracer: the bricks of the
// snapshot on screen are made on a thread of their own and go up in one
// copy when done; until then (the frame is not up to date, so frames go on)
// and wherever the bricks cannot draw (exact edges, voxels the GPU built),
// the tracer draws the part. A section plane the bricks draw themselves.
//
// Threading: one thread (the render thread) uses a renderer; the scene is a
// value copied in for every frame. One frame in flight: drawFrame() waits
// for its own frame's commands before it returns.

#include "kerf/tracer/Section.hpp"
#include "kerf/tracer/ViewController.hpp"
#include "kerf/viewport/BrickRenderer.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/GpuVoxelWorker.hpp"
#include "kerf/viewport/SceneRenderer.hpp"
#include "kerf/viewport/Swapchain.hpp"
#include "kerf/viewport/VoxelStreamer.hpp"
#include "kerf/voxelizer/OcclusionMap.hpp"

#include <memory>
#include <string>
#include <unordered_set>

namespace kerf::vk {

/// What a frame shows. Cheap to copy: the heavy parts are shared.
struct ViewportScene {
    ViewController view;
    std::shared_ptr<const VoxelSnapshot> snapshot; // the newest publication, streamed towards
    /// Voxelize on the GPU: the newest document to build (a new pointer is a
    /// new request); null: show the CPU voxelizer's snapshots.
    std::shared_ptr<const GpuVoxelRequest> gpuVoxels;
    Section section;
    /// Features whose node ids are here are drawn as selected.
    std::shared_ptr<const std::unordered_set<std::string>> selectedFeatureNodes;
    bool grid = true;
    bool axes = true;
    bool edges = true;
    /// Voxels, or the hybrid refinement on the exact field (TraceQuality.hpp).
    TraceQuality quality = TraceQuality::Voxels;
    /// Draw the part with the brick renderer where it can (View > Brick
    /// Renderer): measured slower than the tracer (docs/benchmarks.md).
    bool bricks = false;
    /// Fraction of the window's resolution the part is traced at (0 < s <= 1).
    double resolutionScale = 1.0;
    /// The view the voxelizer was given: a full-resolution trace of exactly
    /// this view is read back as the voxelizer's occlusion picture.
    std::optional<ViewRequirement> occlusionView;
    /// Reference meshes and markers: replaced when their version changes.
    std::shared_ptr<const std::vector<PlacedMesh>> meshes;
    std::shared_ptr<const std::vector<PlacedMesh>> markers;
    std::shared_ptr<const std::vector<PlacedMesh>> ghosts;
};

struct FrameStats {
    bool presented = false;       // a picture reached the window
    bool traced = false;          // the part was traced (else the last trace was reshaded)
    bool drewBricks = false;      // the brick renderer drew the part (ViewportScene::bricks)
    double traceGpuMs = -1.0;     // the trace dispatch, from GPU timestamps (when traced)
    double frameMs = 0.0;         // wall time of the frame on the render thread
    FrameUpload upload;           // this frame's streaming (its bytes include the bricks')
    std::size_t brickBytes = 0;   // of which the brick atlases' rows
    std::size_t brickRowsPending = 0; // atlas rows of the staged bricks still to copy
    bool upToDate = true;         // the newest snapshot is wholly resident
    std::uint64_t shownVersion = 0;   // the snapshot version on screen
    std::uint64_t shownRevision = 0;  // the document revision it describes
    bool shownComplete = false;       // ... at full depth everywhere
    std::size_t residentBytes = 0;    // voxel bytes of the resident set
    std::size_t heapBytes = 0;        // device memory held for voxels
    bool gpuVoxels = false;           // the voxels shown were built by the GPU voxelizer
    bool gpuBusy = false;             // ... which is still building a newer request
    double gpuBuildMs = -1.0;         // the shown GPU build: from its request to its result
    std::string gpuRefusal;           // why the GPU voxelizer could not build the last request ("" if it could)
    std::uint64_t gpuRefusedRevision = 0;
    int width = 0, height = 0;        // window pixels
    int traceWidth = 0, traceHeight = 0;
    /// This frame's trace as an occlusion picture (when it traced
    /// scene.occlusionView at full resolution), else null.
    std::shared_ptr<const OcclusionMap> picture;
};

class ViewportRenderer {
public:
    /// Throws VulkanError when the device cannot present to `surface`.
    /// `wake` is called (on the GPU voxelizer's thread) when a GPU build is
    /// ready or the voxelizer goes idle: the owner should draw a frame.
    ViewportRenderer(const Context& ctx, VkSurfaceKHR surface, StreamingOptions streaming = {},
                     std::function<void()> wake = {});
    ~ViewportRenderer();
    ViewportRenderer(const ViewportRenderer&) = delete;
    ViewportRenderer& operator=(const ViewportRenderer&) = delete;

    /// Draws and presents one frame at the window's size (pixels).
    FrameStats drawFrame(const ViewportScene& scene, int width, int height);
    /// The last frame's picture (at the trace's resolution), read back.
    RgbaImage lastPicture();
    /// Lets go of the swapchain before the window system destroys the surface.
    void releaseSurface();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace kerf::vk

#pragma once
// The brick renderer (../shared/seeds/hierarchical-evaluator-and-brick-renderer.md):
// the brick leaves' samples in three 3D texture atlases (distance and
// normal filtered trilinearly by the texture unit, feature fetched), one
// instanced cube per brick (its far faces) rasterized front to back, and a
// fragment shader (shaders/brick.frag) that marches the brick's samples
// along the pixel's ray. It writes what the compute tracer writes
// (TraceTargets: depth along the ray, unit normal, feature per pixel), so
// whatever reads a trace reads it. The fragments write no depth: the depth
// test keeps the brick whose far face is nearest, the first along the ray
// that found the surface, and drops the bricks behind it before their
// shader runs.
//
// In a viewport the atlases go up in pieces (stage, recordUpload): rows of
// texels within the frame's upload budget, the bricks drawn before drawn
// until the last row is there, as the voxel streamer does for tiles. What
// the copies need on the device (the atlases, hundreds of MB, and the
// staging memory a frame's rows pass through) is made beforehand on the
// thread that makes the bricks (prepare), so that no frame allocates.
//
// A section plane clips each brick's march to the kept side, and the cap is
// decided as the compute tracer decides it: a ray that starts on the plane
// inside the solid meets the solid's samples (below zero) where it enters
// its first brick, since the field changes sign only in populated voxels,
// which bricks cover; that brick then reports the cap at the plane. So the
// full tiles and full nodes, which have no bricks, need none for the cap.
//
// Not yet: the exact-edges refinement (the compute tracer's; the viewport
// hands such frames to the tracer). Measured 18 to 32 times slower than the
// compute tracer on an H200 (docs/benchmarks.md), so it is offered only on
// request.
//
// Threading: one thread, except prepare(), which may run on any (it makes
// new device objects only); memory the frames are done with is freed on a
// thread of the renderer's own. One frame in flight. The context must
// outlive it.

#include "kerf/tracer/Camera.hpp"
#include "kerf/viewport/BrickAtlas.hpp"
#include "kerf/viewport/DeviceImage.hpp"
#include "kerf/viewport/GpuBuffer.hpp"
#include "kerf/tracer/Image.hpp"
#include "kerf/tracer/Section.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/voxelizer/BrickLeaves.hpp"

#include <memory>

namespace kerf::vk {

/// What one recordUpload() copied.
struct BrickUpload {
    std::size_t bytes = 0;     // staged and copied by this command buffer (whole rows, within the budget)
    std::size_t rowsLeft = 0;  // atlas rows still to copy after it
    bool completed = false;    // the staged bricks became the ones drawn
};

/// Bricks ready to be staged (BrickRenderer::prepare): their atlases and
/// instance records made on the device, and the staging memory for a
/// frame's rows of them.
class PreparedBricks {
public:
    std::size_t brickCount() const { return bricks_.size(); }
    /// Bytes of the staging memory made for the copies (0: none made).
    std::size_t stagingBytes() const { return staging_.size(); }

private:
    friend class BrickRenderer;
    std::vector<Brick> bricks_;
    BrickAtlas atlas_;
    DeviceImage distance_, normal_, feature_;
    GpuBuffer instances_, staging_;
};

class BrickRenderer {
public:
    explicit BrickRenderer(const Context& ctx);
    ~BrickRenderer();

    /// Uploads `bricks` into the atlases (waits for the copy). Throws
    /// VulkanError when they do not fit one atlas of the device's largest 3D
    /// image.
    void setBricks(const BrickLeaves& bricks);

    /// The upload in pieces, for a viewport's frames: `bricks` laid out as
    /// `atlas` (BrickAtlas::pack with maxImageDimension3D(), on any thread)
    /// replace the bricks drawn once recordUpload() has copied all of it;
    /// until then the bricks drawn before stay. Their atlases are made now
    /// (VulkanError when the device has no room). A new stage() drops one
    /// still being copied.
    void stage(std::vector<Brick> bricks, BrickAtlas atlas);
    /// The same for bricks prepared beforehand: nothing is allocated here,
    /// nor by the recordUpload() calls of at most the budget they were
    /// prepared for (their staging memory becomes the renderer's, unless
    /// the renderer's is as large already).
    void stage(PreparedBricks bricks);
    /// `bricks` laid out as `atlas` made ready for stage(): the atlases
    /// made on the device, and for a budget above 0 the instance records
    /// and staging memory for the rows that recordUpload() copies within
    /// `budgetBytes` (a row at least; with a budget of 0 the upload makes
    /// those itself, as the stage() of bricks and atlas does). Safe on any
    /// thread while renderers of `ctx` draw: it makes new device objects
    /// only. VulkanError when the device has no room.
    static PreparedBricks prepare(const Context& ctx, std::vector<Brick> bricks, BrickAtlas atlas,
                                  std::size_t budgetBytes);
    bool uploading() const;
    /// Records the copy of the staged atlases' next rows, at most
    /// `budgetBytes` of them (one row over it when `atLeastOneRow`, so that
    /// a budget smaller than a row still ends). When these were the last,
    /// the staged bricks are the ones drawn from here on, this command
    /// buffer's draws included. The staging memory it copies through stays
    /// for the next upload (setBricks() releases it). The previous
    /// submission of such commands must have finished.
    BrickUpload recordUpload(VkCommandBuffer cb, std::size_t budgetBytes, bool atLeastOneRow = false);
    /// The largest 3D image of the device, in texels a side (for BrickAtlas::pack).
    std::uint32_t maxImageDimension3D() const;
    std::size_t brickCount() const;
    /// The bricks' bounds (world mm); empty without bricks.
    Aabb bounds() const;
    /// Changes with every setBricks().
    std::uint64_t version() const;
    /// Bytes on the device: the atlases (staged ones too) and the instance records.
    std::size_t residentBytes() const;
    /// How many times recordUpload() made device memory in a frame, for want
    /// of prepared memory: staging memory as large as its rows needed, the
    /// instance records of the bricks it completed.
    std::uint64_t frameAllocations() const;

    /// Records the drawing of `camera`'s image into the targets, which are
    /// then readable by shaders and transfers. The instances are sorted front
    /// to back (on the host) when the eye moved since the last frame.
    /// `section`, when enabled, cuts the part as the compute tracer does
    /// (the cap reported with kSectionCap and the plane's normal).
    void record(VkCommandBuffer cb, const Camera& camera, const Section& section = {});
    const TraceTargets& targets() const;
    /// The last frame's draw on the device, from timestamps.
    double lastGpuMilliseconds() const;
    /// Host milliseconds of the last front-to-back sort (0 when none was needed).
    double lastSortMilliseconds() const;

    /// Draws and reads the image back.
    TraceImage render(const Camera& camera, double* gpuMilliseconds = nullptr, const Section& section = {});
    /// Milliseconds per frame of `frames` draws back to back in one
    /// submission, after a warm-up (as ComputeTracer::sustainedMilliseconds).
    double sustainedMilliseconds(const Camera& camera, int frames, const Section& section = {});

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace kerf::vk

#pragma once
// The Vulkan compute tracer: the voxel buffers live on the device (reached by
// buffer device address), and a dispatch of shaders/trace.comp, the port of
// the CPU reference tracer, casts one ray per pixel through them into
// device-local depth, normal and feature buffers (TraceTargets), which the
// shading pass reads in place or trace() reads back.
//
// The hybrid refinement runs in other pipelines of the same shader, made
// when first asked for; the voxel-only pipeline is compiled without its
// code (a specialization constant), so it keeps its speed. ExactEverywhere
// refines every ray in one dispatch; Exact traces the voxels, checks their
// hits on the exact field and refines the pixels the check lists, in an
// indirect dispatch (tracer/include/kerf/tracer/VoxelHitCheck.hpp).
//
// Threading: one thread at a time. The context must outlive the tracer.

#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/Image.hpp"
#include "kerf/tracer/Section.hpp"
#include "kerf/tracer/TraceQuality.hpp"
#include "kerf/viewport/GpuBuffer.hpp"
#include "kerf/viewport/VoxelStreamer.hpp"
#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace kerf::vk {

struct TraceTiming {
    double gpuMilliseconds = 0.0; // the dispatch alone, from timestamps
    // TraceQuality::Exact's passes, from timestamps between them (else 0):
    // the voxels, the check of their hits, the refinement of the pixels listed.
    double voxelPassMilliseconds = 0.0, checkMilliseconds = 0.0, refineMilliseconds = 0.0;
    std::uint32_t refinedPixels = 0; // pixels the check listed for the refinement
};

/// Where a dispatch finds the voxels: separate arrays (setVoxels) or one heap
/// for all five record kinds (a streamed ResidentSet).
struct VoxelAddresses {
    GridLayout grid;
    VkDeviceAddress tiles = 0, entries = 0, nodes = 0, leafIndirections = 0, leafData = 0, vertices = 0, tapes = 0;
    /// Changes whenever the data behind the addresses does (a new upload may
    /// reuse the addresses of freed buffers).
    std::uint64_t version = 0;
    static VoxelAddresses of(const ResidentSet& r);
};

/// The tracer's per-pixel outputs, device-local.
struct TraceTargets {
    int width = 0, height = 0;
    GpuBuffer depth, normal, feature;
};

/// Runs `draw` (which fills `targets`) and reads the targets back as an
/// image (waits for the device): what the compute tracer's and the brick
/// renderer's trace() return.
TraceImage readTargets(const Context& ctx, const TraceTargets& targets,
                       const std::function<void(VkCommandBuffer)>& draw);

class ComputeTracer {
public:
    explicit ComputeTracer(const Context& ctx);
    ~ComputeTracer();

    /// Makes `buffers` the tracer's own voxel data (uploads all of it,
    /// waiting for the copy); voxels() then points at it.
    void setVoxels(const FlatVoxelBuffers& buffers);
    VoxelAddresses voxels() const;
    /// Bytes of voxel data uploaded by setVoxels().
    std::size_t residentBytes() const;

    /// Records the trace of `camera`'s image into the targets (resized as
    /// needed), followed by a barrier making them readable by fragment
    /// shaders and transfers. Writes the timestamps read by lastTiming().
    /// `quality` Exact or ExactEverywhere turns the hybrid refinement on (TraceQuality.hpp).
    void record(VkCommandBuffer cb, const Camera& camera, const VoxelAddresses& voxels, const Section& section = {},
                TraceQuality quality = TraceQuality::Voxels);
    const TraceTargets& targets() const;
    TraceTiming lastTiming() const;
    /// The lanes that refine one of TraceQuality::Exact's listed rays
    /// together (ExactRefinement.h), for the CPU reference to match; 0 where
    /// this device's subgroups cannot hold them (Exact refines every ray).
    int refineLanes() const;

    /// Traces and reads the image back (waits for the device).
    TraceImage trace(const Camera& camera, TraceTiming* timing = nullptr, const Section& section = {},
                     TraceQuality quality = TraceQuality::Voxels);
    TraceImage trace(const Camera& camera, const ResidentSet& voxels, TraceTiming* timing = nullptr,
                     const Section& section = {}, TraceQuality quality = TraceQuality::Voxels);
    /// Traces voxels wherever they live on the device (a GpuVoxels build, for one).
    TraceImage trace(const Camera& camera, const VoxelAddresses& voxels, TraceTiming* timing = nullptr,
                     const Section& section = {}, TraceQuality quality = TraceQuality::Voxels);

    /// Milliseconds per frame of `frames` traces of the resident voxels
    /// recorded back to back in one submission (no read-back), timed on the
    /// host, after at least 300 ms of the same work that brings the clocks up.
    /// What a viewport drawing continuously sees; a single frame followed by
    /// a wait (lastTiming()) lets the GPU idle and clock down, and its time
    /// swings several-fold from run to run on a discrete GPU.
    double sustainedMilliseconds(const Camera& camera, int frames, TraceQuality quality = TraceQuality::Voxels,
                                 const Section& section = {});

    /// The compiler's statistics of each trace pipeline made so far (its
    /// name, then Context::pipelineStatistics): empty lists unless the
    /// context captures them.
    std::vector<std::pair<std::string, std::vector<std::string>>> pipelineStatistics() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace kerf::vk

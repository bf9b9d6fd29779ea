#pragma once
// The Vulkan compute tracer: the voxel buffers live on the device (reached by
// buffer device address), and trace() casts one ray per pixel through them
// with shaders/trace.comp, the port of the CPU reference tracer.
//
// Threading: one thread at a time. The context must outlive the tracer.

#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/Image.hpp"
#include "kerf/viewport/GpuBuffer.hpp"
#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/viewport/VoxelStreamer.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <memory>

namespace kerf::vk {

struct TraceTiming {
    double gpuMilliseconds = 0.0; // the dispatch alone, from timestamps
};

class ComputeTracer {
public:
    explicit ComputeTracer(const Context& ctx);
    ~ComputeTracer();

    /// Makes `buffers` the resident voxel data (uploads all of it, waiting
    /// for the copy). The viewport's streamed path uploads tile by tile.
    void setVoxels(const FlatVoxelBuffers& buffers);
    /// Bytes of voxel data resident on the device.
    std::size_t residentBytes() const;

    /// Traces `camera`'s image through the voxels given to setVoxels() and
    /// reads it back.
    TraceImage trace(const Camera& camera, TraceTiming* timing = nullptr);
    /// Traces through a streamed resident set instead (VoxelStreamer).
    TraceImage trace(const Camera& camera, const ResidentSet& voxels, TraceTiming* timing = nullptr);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace kerf::vk

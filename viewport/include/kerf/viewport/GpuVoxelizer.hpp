#pragma once
// The GPU voxelizer (the f-rep-voxel-rendering seed, after Keeter's
// "Massively Parallel Rendering of Complex Closed-Form Implicit Surfaces"):
// the surface tiles of a grid built by compute shaders (shaders/voxelize.comp)
// level by level, every ambiguous node's 64 children tested in interval
// arithmetic with its tile's tape, node ranges claimed with atomics, leaves
// sampled at their 125 corners with exact normals. The result is the flat
// buffers of docs/voxel-format.md, left on the device where the compute
// tracer reads them (no round trip through the host).
//
// The host's share: each tile's tape simplified for its box and its interval
// (the same double-precision test as the CPU voxelizer: empty, full or
// surface), in parallel with oneTBB; a surface tile whose tape the shaders
// cannot hold (more than 8 stack slots or 256 instructions: a coarse tile
// over many shelf-pin holes) is built there by the CPU's TileBuilder and
// sent with the rest. The CPU voxelizer (voxelize(), TileBuilder) stays the
// reference and the fallback: build() says why when it cannot build a part
// here (pools beyond the memory budget).
//
// Memory: the pools (nodes, leaves, voxels, vertices, job lists) are sized
// from the surface tiles and the depth, grown and the build retried when a
// level overflows them (the shaders never write past a pool's end); their
// total is checked against the budget before anything is allocated.
//
// Threading: one thread at a time. The context must outlive the voxelizer
// and every GpuVoxels it made.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/GpuBuffer.hpp"
#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/viewport/VulkanHandle.hpp"
#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace kerf::vk {

/// A voxelization built on the device, in the flat layout: tile entries
/// carry their root node's index (node pointers are relative to it) and 0
/// as the other bases (leaf, voxel and vertex pointers are absolute).
struct GpuVoxels {
    GridLayout layout;
    int levels = 0;
    GpuBuffer tiles, entries, nodes, leafIndirections, leafData, vertices, tapes;
    std::size_t surfaceTiles = 0;    // tiles with an entry (some may turn out empty or full)
    std::size_t nodeCount = 0;       // nodes written, leaves included
    std::size_t leafCount = 0;       // leaves holding populated voxels
    std::size_t populatedVoxels = 0;
    std::size_t vertexCount = 0;

    /// Bytes of voxel data in use (not the pools' spare room).
    std::size_t bytes() const;
    /// Where the tracer finds them; `version` tells it the data changed.
    VoxelAddresses addresses(std::uint64_t version) const;
    /// Copies everything back (waits for the device): tests, and anything
    /// on the host that must read what the GPU built.
    FlatVoxelBuffers readBack(const Context& ctx) const;
};

struct GpuVoxelizeOptions {
    int levels = -1;              // contree depth; -1: the layout's
    std::size_t memoryBudget = 0; // bytes the pools may take; 0: half the largest allocation the device allows, times 4
    int threads = 0;              // host threads preparing tapes; 0: every core
};

struct GpuVoxelizeReport {
    double prepareMilliseconds = 0.0; // the host's tile tapes and intervals
    double uploadMilliseconds = 0.0;  // tapes, entries and first jobs to the device
    double deviceMilliseconds = 0.0;  // the passes, from submission to completion (all attempts)
    int attempts = 0;                 // 1 unless a pool overflowed
    std::size_t hostBuiltTiles = 0;   // surface tiles whose tape the shaders cannot hold: built by the CPU's builder
    std::size_t poolBytes = 0;        // what the last attempt allocated
    std::string whyNot;               // set when build() returns nothing
};

class GpuVoxelizer {
public:
    explicit GpuVoxelizer(const Context& ctx);
    ~GpuVoxelizer();

    /// Builds every tile of `layout` from `tape` (world coordinates) at the
    /// given depth. Returns nothing when this device cannot (report->whyNot
    /// says why, in words): the caller falls back to the CPU voxelizer.
    std::optional<GpuVoxels> build(const Tape& tape, const GridLayout& layout, const GpuVoxelizeOptions& options = {},
                                   GpuVoxelizeReport* report = nullptr);

private:
    struct Pools {
        std::size_t nodes = 0, leafIndirections = 0, leafData = 0, vertices = 0, jobs = 0;
        std::size_t bytes() const;
    };
    Pools firstGuess(std::size_t surfaceTiles, int levels) const;

    const Context& ctx_;
    ShaderModule module_;
    PipelineLayout layout_;
    Pipeline pipeline_;
    /// Per surface tile and depth, what the last build needed: a rebuild of
    /// the same part (an edit) sizes its pools right the first time.
    std::array<double, 12> voxelsPerTile_{};
};

} // namespace kerf::vk

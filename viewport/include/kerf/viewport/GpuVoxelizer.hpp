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
// Memory: one submission per level, and the host reads the counters after
// each. The pools (nodes, leaves, voxels, vertices, job lists) are sized for
// the level about to run (the next level's nodes about 16 times this one's;
// a leaf's voxels and vertices as the last build had them); a level that
// asks for more (the shaders write nothing past a pool's end, but every
// claim counts) gets pools of exactly what it asked, contents kept, and runs
// again. Every pool is checked against the budget before it is made.
//
// Threading: one thread at a time. The context must outlive the voxelizer
// and every GpuVoxels it made.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/GpuBuffer.hpp"
#include "kerf/viewport/ShaderModules.hpp"
#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/viewport/VulkanHandle.hpp"
#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace kerf::vk {

/// A voxelization built on the device, in the flat layout: tile entries
/// carry their root node's index (node pointers are relative to it) and 0
/// as the other bases (leaf, voxel and vertex pointers are absolute).
///
/// An update (GpuVoxelizer::update) appends the records of the tiles it
/// rebuilds to its base's pools, which the two then share (the base stays
/// valid and readable); the records it replaced stay in them, unreachable,
/// until a whole build: the counts below are of records written.
struct GpuVoxels {
    GridLayout layout;
    int levels = 0;
    GpuBuffer tiles, entries, tapes;
    std::shared_ptr<GpuBuffer> nodes, leafIndirections, leafData, vertices; // the pools
    std::size_t surfaceTiles = 0; // tiles this build gave an entry (some may turn out empty or full)
    std::size_t nodeCount = 0;    // nodes written, leaves included
    std::size_t leafCount = 0;    // leaves holding populated voxels
    std::size_t populatedVoxels = 0;
    std::size_t vertexCount = 0;
    std::size_t wholeBuildNodes = 0; // nodes of the last whole build in these pools
    std::size_t entryCount() const { return entries.size() / sizeof(TileEntry); }

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
    std::size_t memoryBudget = 0; // bytes the pools may take; 0: half the device-local memory
    int threads = 0;              // host threads preparing tapes; 0: every core
    /// Scales the pools' first guesses down (tests: levels then outgrow
    /// their pools and run again); 1 in use.
    double poolGuessScale = 1.0;
    /// Each surface tile evaluated with the part's tape simplified for its
    /// box (as the CPU voxelizer does); false: the whole tape everywhere
    /// (benchmarks: what the simplification buys). The voxels are the same.
    bool simplifyTileTapes = true;
    /// Each node's tape pruned further for its own box on the device
    /// (voxelize.comp, "Tapes pruned per node"); false: every node of a
    /// tile evaluates the tile's tape (benchmarks). The voxels are the same.
    bool pruneNodeTapes = true;
    /// Checked before every level: when it reads true the build stops and
    /// returns nothing (report->cancelled), its pools kept as spares.
    const std::atomic<bool>* cancel = nullptr;
};

struct GpuVoxelizeReport {
    double prepareMilliseconds = 0.0;  // the host's tile tapes and intervals
    double allocateMilliseconds = 0.0; // device buffers made before the first level
    double poolAllocateMilliseconds = 0.0; // pools made (not taken from the spares), first ones and grown alike
    double uploadMilliseconds = 0.0;   // tapes, entries and first jobs into the staging buffer
    double deviceMilliseconds = 0.0;   // the submissions, from recording to completion (one per level)
    std::vector<double> submissionMilliseconds; // each of them, in order (a level run again: twice; the finish pass last)
    std::vector<std::uint32_t> levelJobs;       // the nodes each level processed (the roots', then each level's children)
    int levelReruns = 0;               // levels run twice because they asked for more than a pool held
    std::size_t hostBuiltTiles = 0;    // surface tiles whose tape the shaders cannot hold: built by the CPU's builder
    std::size_t poolBytes = 0;         // the pools' device memory at the end
    std::size_t prunedLeafJobs = 0;    // leaf nodes whose tape was pruned for their box (pruneNodeTapes)
    bool cancelled = false;            // stopped by GpuVoxelizeOptions::cancel
    std::size_t updatedTiles = 0;      // an update: the tiles rebuilt (0: a whole build)
    std::string whyNot;                // set when build() returns nothing
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
    /// `base` (built by this voxelizer, on screen perhaps) with `dirtyTiles`
    /// rebuilt from `tape`: the other tiles' records are kept as they are
    /// and the new ones appended in the same pools (an edit's tiles cost
    /// what they cost, not the part). A whole build instead when the depth
    /// differs, when a quarter of the tiles or more are dirty, or when
    /// replaced records fill the pools to twice a whole build's.
    std::optional<GpuVoxels> update(const GpuVoxels& base, const Tape& tape, const std::vector<long>& dirtyTiles,
                                    const GpuVoxelizeOptions& options = {}, GpuVoxelizeReport* report = nullptr);

    /// Hands back a build nobody reads any more (the one before the one on
    /// screen): its pools serve the next build instead of new allocations,
    /// which on a discrete GPU cost about as much as the build itself.
    void recycle(GpuVoxels&& old);
    /// Lets go of the spare pools (the viewport went back to the CPU).
    void releaseSpares()
    {
        spare_.clear();
        scratch_ = {};
    }

private:
    std::optional<GpuVoxels> make(const Tape& tape, const GridLayout& layout, const GpuVoxelizeOptions& options,
                                  GpuVoxelizeReport* report, const GpuVoxels* base, const std::vector<long>* dirty);
    static constexpr std::size_t kSpareBuffers = 8;
    void giveSpare(GpuBuffer&& buffer);
    GpuBuffer takeSpare(std::size_t bytes); // an empty buffer when no spare fits
    const Context& ctx_;
    ComputePipeline inner_, leaf_; // voxelize.comp's two compilations
    std::string unsupported_; // why this device cannot run the shaders (empty: it can)
    /// What the last build had per leaf node and per voxel: the next one
    /// sizes its pools from them (an edit's rebuild then runs every level once).
    double voxelsPerLeafJob_ = 0.0;
    double verticesPerVoxel_ = 0.0;
    /// Per level, the children an ambiguous node had in the last build.
    std::array<double, voxel::kMaxLevels + 1> childrenPerNode_{};
    std::vector<GpuBuffer> spare_; // largest first
    /// Buffers every build uses and none keeps: made once, grown when too small.
    struct Scratch {
        GpuBuffer entryTiles, entryVoxels, counters, params, countsBack, staging;
    } scratch_;
    const GpuBuffer& scratch(GpuBuffer& buffer, std::size_t bytes, VkBufferUsageFlags usage, GpuBuffer::Kind kind);
};

} // namespace kerf::vk

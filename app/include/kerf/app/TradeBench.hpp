#pragma once
// The measurements behind `kerf bench`: for each feature size, what the
// voxels cost (cold voxelization, re-voxelization after a typical edit, GPU
// memory, trace time per frame) and how far the picture and the exported mesh
// lie from the exact part. Qt-free, so that a headless program (the GPU
// machine has no Qt) runs exactly the same measurements.
//
// What each figure is:
//  - voxelizeMs: voxelize() of the whole part plus flattening to the GPU
//    layout, every core (the cold build `kerf render` does).
//  - revoxelize: the background Voxelizer (every core) after the typical
//    edit (TypicalEdit.hpp), the median of three edits (+d, -d, +d): the time
//    to the coarse publication and to the complete one, and the tiles rebuilt.
//  - gpuBytes: FlatVoxelBuffers::bytes(), what the tracer uploads.
//  - gpuVoxelize (Vulkan only): the same voxels built on the device by the
//    GPU voxelizer (GpuVoxelizer.hpp): cold (a fresh voxelizer, its pools
//    made and sized as it goes) and warm (a rebuild of the same part, as
//    after an edit that dirties every tile), with its populated voxels,
//    which should be the CPU's.
//  - traceMs: per frame, `frames` traces back to back after a warm-up
//    (ComputeTracer::sustainedMilliseconds, Vulkan) or the median of
//    `frames` traces after one warm-up on the wall clock (the CPU reference
//    tracer); `device` says which.
//  - exactEdges (when asked for): the same voxels traced with the hybrid
//    refinement (TraceQuality::Exact: each hit checked on the exact field,
//    refined where the check cannot confirm it, what
//    `kerf render --quality exact` and the viewport's Exact Edges draw),
//    its trace time and picture error measured the same way.
//  - picture: the traced image (as read back from the device) against the
//    exact sphere trace of the same camera (ImageError.hpp).
//  - export: meshTape() at the feature size (the mesh `kerf export` writes;
//    the time excludes checking and writing the STL), its distance to the
//    exact surface (SurfaceDistance.hpp) and its volume against the exact
//    field's integral (ExactVolume.hpp, cells of the smallest feature size
//    measured).

#include "kerf/accuracy/ExactVolume.hpp"
#include "kerf/accuracy/ImageError.hpp"
#include "kerf/accuracy/SurfaceDistance.hpp"
#include "kerf/app/TypicalEdit.hpp"
#include "kerf/document/Document.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace kerf {

struct TradeBenchOptions {
    std::vector<double> featureSizes; // mm, measured in the order given
    int width = 1280, height = 960;
    std::string view = "iso";
    int frames = 5;
    bool cpu = false;       // trace with the CPU reference tracer even when Vulkan works
    bool traceOnly = false; // leave out the export measurements (mesh, distance, volume)
    bool exactEdges = false; // also trace with the hybrid refinement
    bool bricks = false;     // also draw with the brick renderer (Vulkan only)
    /// Told what is being measured, one short phrase at a time (for a
    /// progress line); called on the calling thread.
    std::function<void(const std::string&)> progress;
};

struct ExportFigures {
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    double meshMs = 0.0;
    bool watertight = false;
    double volume = 0.0;        // mm^3, of the mesh
    std::uint64_t stlBytes = 0; // the binary STL's size: 84 + 50 per triangle
    SurfaceDistance distance;
    double distanceMs = 0.0; // the measurement's own time (not part of the export)
};

struct RevoxelizeFigures {
    double coarseMs = 0.0;
    double finalMs = 0.0;
    std::size_t dirtyTiles = 0;
    std::size_t tiles = 0;
};

/// A trace of the voxels at one quality: its time per frame and its error.
struct PictureFigures {
    double traceMs = 0.0;
    ImageError picture;
};

/// The same voxels drawn by the brick renderer (BrickRenderer.hpp).
struct BrickFigures {
    PictureFigures drawn;       // frame time (sustained, as the tracer's) and error
    std::size_t bricks = 0;
    std::size_t deviceBytes = 0; // its atlases and instances
    double buildMs = 0.0;        // the bricks made from the voxels (host)
    double uploadMs = 0.0;       // packed and copied to the device in one piece (kerf render's way)
    int uploadFrames = 0;        // ... in rows within the viewport's per-frame budget: submissions
    double uploadFrameMaxMs = 0.0; // ... and the longest of them (host copy, submission, wait)
    double uploadFramesMs = 0.0;   // ... all of them
    double uploadRecordMs = 0.0;   // ... of which recording (the copies into the staging memory)
    double uploadFirstFrameMs = 0.0; // ... the first of them
    int uploadLongestFrame = 0;      // ... which of them was the longest (0: the first)
    double prepareMs = 0.0; // the atlases and staging memory made beforehand (BrickRenderer::prepare, off the frames)
};

struct GpuVoxelizeFigures {
    double coldMs = 0.0, warmMs = 0.0;
    std::size_t populatedVoxels = 0;
    std::string whyNot; // set when the device could not build it (the times are then 0)
};

struct TradeRow {
    double featureSize = 0.0; // mm, as asked
    double voxelSize = 0.0;   // mm, as built (larger only when the grid had to coarsen)
    std::string note;         // why voxelSize differs, if it does
    double voxelizeMs = 0.0;
    std::size_t populatedVoxels = 0;
    std::size_t gpuBytes = 0;
    std::optional<RevoxelizeFigures> revoxelize; // none when the part has no feature to move
    std::optional<GpuVoxelizeFigures> gpuVoxelize; // Vulkan only
    double uploadMs = 0.0;                       // Vulkan only: the whole buffers through staging, waiting
    double traceMs = 0.0;
    ImageError picture;
    std::optional<PictureFigures> exactEdges; // only when asked for
    std::optional<BrickFigures> bricks;       // only when asked for, on Vulkan
    std::optional<ExportFigures> exported;    // none with traceOnly
};

struct TradeReport {
    std::string device; // what traced: the Vulkan device's description or the CPU tracer
    bool vulkan = false;
    std::string vulkanProblem; // why Vulkan was not used, when it was wanted
    int width = 0, height = 0;
    std::string view;
    int frames = 0;
    unsigned threads = 0; // CPU threads the voxelizer and mesher used
    std::optional<TypicalEdit> edit;
    double referenceEpsilon = 0.0; // mm: the exact sphere tracer's hit distance
    double referenceMs = 0.0;
    std::size_t referencePixelsHit = 0;
    std::optional<VolumeEstimate> volumeReference; // none with traceOnly
    double volumeReferenceMs = 0.0;
    std::vector<TradeRow> rows;
};

/// Runs every measurement. Throws std::invalid_argument for an empty or
/// unbounded part or a bad view, std::runtime_error when work fails.
TradeReport runTradeBench(const Document& doc, const TradeBenchOptions& options);

/// The report as JSON (field names in snake case, lengths in mm, times in ms).
nlohmann::ordered_json tradeReportJson(const TradeReport& report);

} // namespace kerf

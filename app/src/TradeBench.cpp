#include "kerf/app/TradeBench.hpp"

#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/viewport/BrickRenderer.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/voxelizer/BrickLeaves.hpp"
#include "kerf/viewport/GpuVoxelizer.hpp"
#include "kerf/viewport/VoxelStreamer.hpp"
#include "kerf/viewport/VulkanError.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "kerf/voxelizer/Voxelizer.hpp"

#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>

namespace kerf {

namespace {

// The exact reference's hit distance: far below any voxel's error, so the
// picture error measures the voxels, not the reference.
constexpr double kReferenceEpsilonMm = 1e-4;
constexpr int kEdits = 3;
constexpr auto kWaitLimit = std::chrono::hours(1);

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

double median(std::vector<double> v)
{
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

std::string mmText(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// The GPU voxelizer on the same grid: a fresh one (cold), then a rebuild
// with the first build still alive, as a viewport would hold it (warm).
GpuVoxelizeFigures gpuVoxelizeFigures(const vk::Context& context, const Tape& tape, const GridLayout& layout)
{
    GpuVoxelizeFigures f;
    vk::GpuVoxelizer voxelizer(context);
    vk::GpuVoxelizeReport report;
    auto t0 = Clock::now();
    std::optional<vk::GpuVoxels> first = voxelizer.build(tape, layout, {}, &report);
    f.coldMs = msSince(t0);
    if (!first) {
        f.whyNot = report.whyNot;
        f.coldMs = 0.0;
        return f;
    }
    t0 = Clock::now();
    const std::optional<vk::GpuVoxels> second = voxelizer.build(tape, layout, {}, &report);
    f.warmMs = msSince(t0);
    if (!second) {
        f.whyNot = report.whyNot;
        return f;
    }
    f.populatedVoxels = second->populatedVoxels;
    return f;
}

// Re-voxelization after the typical edit, with the background voxelizer
// warmed up by the document itself.
RevoxelizeFigures revoxelize(const Document& doc, const TypicalEdit& edit, double featureSize)
{
    VoxelizerOptions options;
    options.featureSize = featureSize;
    Voxelizer voxelizer(options);
    if (!voxelizer.waitFor(voxelizer.setDocument(doc), true, kWaitLimit))
        throw std::runtime_error("the background voxelizer did not finish within an hour");
    std::vector<double> coarse, final;
    RevoxelizeFigures f;
    for (int i = 0; i < kEdits; ++i) {
        const Document edited = applyTypicalEdit(doc, edit, i % 2 == 0 ? kTypicalEditMm : 0.0);
        if (!voxelizer.waitFor(voxelizer.setDocument(edited), true, kWaitLimit))
            throw std::runtime_error("the background voxelizer did not finish within an hour");
        const VoxelizerStats s = voxelizer.lastStats();
        coarse.push_back(s.coarseMs);
        final.push_back(s.fineMs);
        f.dirtyTiles = s.dirtyTiles;
        f.tiles = s.tilesInGrid;
    }
    f.coarseMs = median(coarse);
    f.finalMs = median(final);
    return f;
}

ExportFigures exportFigures(const Tape& tape, double featureSize)
{
    ExportFigures f;
    MeshOptions options;
    options.featureSize = featureSize;
    const auto t0 = Clock::now();
    std::optional<Mesh> mesh = meshTape(tape, options);
    f.meshMs = msSince(t0);
    if (!mesh) throw std::runtime_error("meshing was cancelled");
    const MeshReport report = checkMesh(*mesh);
    f.triangles = report.triangles;
    f.vertices = report.vertices;
    f.watertight = report.watertight();
    f.volume = report.volume;
    f.stlBytes = 84 + 50 * std::uint64_t(report.triangles);
    const auto t1 = Clock::now();
    f.distance = measureSurfaceDistance(*mesh, tape);
    f.distanceMs = msSince(t1);
    return f;
}

} // namespace

TradeReport runTradeBench(const Document& doc, const TradeBenchOptions& options)
{
    auto progress = [&](const std::string& what) {
        if (options.progress) options.progress(what);
    };
    const Tape tape = compileTape(doc);
    if (tape.empty() || tape.bounds().isEmpty()) throw std::invalid_argument("the part is empty (nothing visible)");
    if (!tape.bounds().isBounded())
        throw std::invalid_argument("the part is unbounded (a halfspace nothing clips); it has no size to measure");
    const Camera camera = Camera::standardView(tape.bounds(), options.view, options.width, options.height);

    TradeReport report;
    report.width = options.width;
    report.height = options.height;
    report.view = options.view;
    report.frames = options.frames;
    report.threads = unsigned(tbb::info::default_concurrency());
    report.edit = chooseTypicalEdit(doc);
    report.referenceEpsilon = kReferenceEpsilonMm;

    progress("tracing the exact reference image");
    auto t0 = Clock::now();
    const TraceImage reference = traceExact(tape, camera, kReferenceEpsilonMm);
    report.referenceMs = msSince(t0);
    for (std::size_t i = 0; i < reference.depth.size(); ++i)
        report.referencePixelsHit += reference.hit(i);

    std::unique_ptr<vk::Context> context;
    std::unique_ptr<vk::ComputeTracer> tracer;
    if (!options.cpu) {
        try {
            context = std::make_unique<vk::Context>();
            tracer = std::make_unique<vk::ComputeTracer>(*context);
            report.device = context->deviceDescription();
            report.vulkan = true;
        } catch (const vk::VulkanError& e) {
            tracer.reset();
            context.reset();
            report.vulkanProblem = e.what();
        }
    }
    if (!report.vulkan) report.device = "CPU reference tracer (" + std::to_string(report.threads) + " threads)";

    for (double featureSize : options.featureSizes) {
        const std::string at = " at " + mmText(featureSize) + " mm";
        TradeRow row;
        row.featureSize = featureSize;
        {
            progress("voxelizing" + at);
            t0 = Clock::now();
            const GridLayout layout = GridLayout::choose(tape.bounds(), featureSize);
            const VoxelSnapshot snapshot = voxelize(tape, layout);
            const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(snapshot);
            row.voxelizeMs = msSince(t0);
            row.voxelSize = layout.voxelSize;
            row.note = layout.note;
            row.populatedVoxels = snapshot.populatedVoxels();
            row.gpuBytes = buffers.bytes();

            if (report.vulkan) {
                progress("voxelizing on the GPU" + at);
                row.gpuVoxelize = gpuVoxelizeFigures(*context, tape, layout);
            }
            progress("tracing" + at);
            if (report.vulkan) {
                t0 = Clock::now();
                tracer->setVoxels(buffers);
                row.uploadMs = msSince(t0);
            }
            const auto measure = [&](TraceQuality quality) {
                PictureFigures figures;
                TraceImage image;
                if (report.vulkan) {
                    image = tracer->trace(camera, nullptr, {}, quality);
                    // Back to back, as a viewport draws: a frame followed by
                    // a wait lets a discrete GPU clock down.
                    figures.traceMs = tracer->sustainedMilliseconds(camera, options.frames, quality);
                } else {
                    std::vector<double> frameMs;
                    for (int f = 0; f <= options.frames; ++f) {
                        t0 = Clock::now();
                        image = traceVoxels(buffers, camera, 0, {}, quality);
                        if (f > 0) frameMs.push_back(msSince(t0)); // the first is a warm-up
                    }
                    figures.traceMs = median(frameMs);
                }
                figures.picture = compareImages(image, reference);
                return figures;
            };
            const PictureFigures voxels = measure(TraceQuality::Voxels);
            row.traceMs = voxels.traceMs;
            row.picture = voxels.picture;
            if (options.exactEdges) {
                progress("tracing with exact edges" + at);
                row.exactEdges = measure(TraceQuality::Exact);
            }
            if (options.bricks && report.vulkan) {
                progress("drawing with the brick renderer" + at);
                BrickFigures b;
                t0 = Clock::now();
                const BrickLeaves leaves = BrickLeaves::fromVoxels(buffers);
                b.buildMs = msSince(t0);
                vk::BrickRenderer bricks(*context);
                // The viewport's way first: the atlases and the staging
                // memory made beforehand (its brick-making thread's work),
                // then rows within its per-frame upload budget, a submission
                // each (as its frames); then the atlases go and come back in
                // one piece (kerf render's way).
                const std::size_t budget = vk::StreamingOptions{}.budgetBytesPerFrame;
                vk::BrickAtlas atlas = vk::BrickAtlas::pack(leaves, bricks.maxImageDimension3D());
                t0 = Clock::now();
                vk::PreparedBricks prepared = vk::BrickRenderer::prepare(*context, leaves.bricks, std::move(atlas), budget);
                b.prepareMs = msSince(t0);
                bricks.stage(std::move(prepared));
                for (bool done = false; !done;) {
                    const auto f0 = Clock::now();
                    context->submitAndWait([&](VkCommandBuffer cb) {
                        const auto r0 = Clock::now();
                        done = bricks.recordUpload(cb, budget, true).completed;
                        b.uploadRecordMs += msSince(r0);
                    });
                    const double frameMs = msSince(f0);
                    if (b.uploadFrames == 0) b.uploadFirstFrameMs = frameMs;
                    if (frameMs > b.uploadFrameMaxMs) {
                        b.uploadFrameMaxMs = frameMs;
                        b.uploadLongestFrame = b.uploadFrames;
                    }
                    ++b.uploadFrames;
                    b.uploadFramesMs += frameMs;
                }
                bricks.setBricks(BrickLeaves{});
                t0 = Clock::now();
                bricks.setBricks(leaves);
                b.uploadMs = msSince(t0);
                b.bricks = leaves.bricks.size();
                b.deviceBytes = bricks.residentBytes();
                b.drawn.picture = compareImages(bricks.render(camera), reference);
                b.drawn.traceMs = bricks.sustainedMilliseconds(camera, options.frames);
                row.bricks = b;
            }
        }
        if (report.edit) {
            progress("re-voxelizing after moving '" + report.edit->nodeId + "'" + at);
            row.revoxelize = revoxelize(doc, *report.edit, featureSize);
        }
        if (!options.traceOnly) {
            progress("meshing and measuring the mesh" + at);
            row.exported = exportFigures(tape, featureSize);
        }
        report.rows.push_back(std::move(row));
    }
    if (!options.traceOnly && !options.featureSizes.empty()) {
        const double cell = *std::min_element(options.featureSizes.begin(), options.featureSizes.end());
        progress("integrating the exact volume with " + mmText(cell) + " mm cells");
        t0 = Clock::now();
        report.volumeReference = integrateVolume(tape, cell);
        report.volumeReferenceMs = msSince(t0);
    }
    return report;
}

nlohmann::ordered_json tradeReportJson(const TradeReport& r)
{
    using J = nlohmann::ordered_json;
    auto stats = [](const ErrorStats& s) { return J{{"mean", s.mean}, {"p99", s.p99}, {"max", s.max}}; };
    J j;
    j["device"] = r.device;
    j["vulkan"] = r.vulkan;
    if (!r.vulkanProblem.empty()) j["vulkan_problem"] = r.vulkanProblem;
    j["threads"] = r.threads;
    j["image"] = {{"width", r.width}, {"height", r.height}, {"view", r.view}, {"frames", r.frames}};
    if (r.edit)
        j["edit"] = {{"node", r.edit->nodeId},
                     {"type", std::string(nodeTypeName(r.edit->type))},
                     {"instances", r.edit->instances},
                     {"move_mm", {kTypicalEditMm, 0.0, 0.0}},
                     {"frame", "parent"}};
    else
        j["edit"] = nullptr;
    j["reference_image"] = {{"method", "exact sphere tracing"},
                            {"epsilon_mm", r.referenceEpsilon},
                            {"pixels_hit", r.referencePixelsHit},
                            {"ms", r.referenceMs}};
    if (r.volumeReference) {
        const VolumeEstimate& v = *r.volumeReference;
        j["reference_volume"] = {{"method", "exact field integrated: interval-proven cells plus stratified samples"},
                                 {"volume_mm3", v.volume},
                                 {"uncertainty_mm3", v.uncertainty},
                                 {"confidence", "two standard errors"},
                                 {"cell_mm", v.cellSize},
                                 {"sampled_cells", v.sampledCells},
                                 {"ms", r.volumeReferenceMs}};
    }
    J rows = J::array();
    for (const TradeRow& row : r.rows) {
        J x;
        x["feature_size_mm"] = row.featureSize;
        x["voxel_size_mm"] = row.voxelSize;
        if (!row.note.empty()) x["note"] = row.note;
        x["voxelize_ms"] = row.voxelizeMs;
        if (row.gpuVoxelize)
            x["gpu_voxelize"] = {{"cold_ms", row.gpuVoxelize->coldMs},
                                 {"warm_ms", row.gpuVoxelize->warmMs},
                                 {"populated_voxels", row.gpuVoxelize->populatedVoxels},
                                 {"why_not", row.gpuVoxelize->whyNot}};
        else
            x["gpu_voxelize"] = nullptr;
        if (row.revoxelize)
            x["revoxelize"] = {{"coarse_ms", row.revoxelize->coarseMs},
                               {"final_ms", row.revoxelize->finalMs},
                               {"dirty_tiles", row.revoxelize->dirtyTiles},
                               {"tiles", row.revoxelize->tiles}};
        else
            x["revoxelize"] = nullptr;
        x["populated_voxels"] = row.populatedVoxels;
        x["gpu_bytes"] = row.gpuBytes;
        if (r.vulkan) x["upload_ms"] = row.uploadMs;
        x["trace_ms"] = row.traceMs;
        const auto picture = [&](const ImageError& p) {
            return J{{"pixels_both_hit", p.bothHit},         {"pixels_only_voxels", p.onlyImage},
                     {"pixels_only_exact", p.onlyReference}, {"mismatch_fraction", p.mismatchFraction()},
                     {"depth_error_mm", stats(p.depthMm)},   {"normal_error_deg", stats(p.normalDegrees)}};
        };
        x["picture"] = picture(row.picture);
        if (row.exactEdges)
            x["exact_edges"] = {{"trace_ms", row.exactEdges->traceMs}, {"picture", picture(row.exactEdges->picture)}};
        if (row.bricks)
            x["bricks"] = {{"trace_ms", row.bricks->drawn.traceMs},
                           {"bricks", row.bricks->bricks},
                           {"device_bytes", row.bricks->deviceBytes},
                           {"build_ms", row.bricks->buildMs},
                           {"upload_ms", row.bricks->uploadMs},
                           {"upload_frames", row.bricks->uploadFrames},
                           {"upload_frame_max_ms", row.bricks->uploadFrameMaxMs},
                           {"upload_frames_ms", row.bricks->uploadFramesMs},
                           {"upload_record_ms", row.bricks->uploadRecordMs},
                           {"upload_first_frame_ms", row.bricks->uploadFirstFrameMs},
                           {"upload_longest_frame", row.bricks->uploadLongestFrame},
                           {"prepare_ms", row.bricks->prepareMs},
                           {"picture", picture(row.bricks->drawn.picture)}};
        if (row.exported) {
            const ExportFigures& e = *row.exported;
            J m;
            m["triangles"] = e.triangles;
            m["vertices"] = e.vertices;
            m["export_ms"] = e.meshMs;
            m["watertight"] = e.watertight;
            m["stl_bytes"] = e.stlBytes;
            m["distance_mm"] = {{"mean", e.distance.mean},
                                {"max", e.distance.max},
                                {"max_lower_bound", e.distance.maxLowerBound},
                                {"vertex_max", e.distance.vertexMax},
                                {"samples", e.distance.samples},
                                {"unresolved", e.distance.unresolved}};
            m["volume_mm3"] = e.volume;
            if (r.volumeReference && r.volumeReference->volume > 0.0) {
                const double err = e.volume - r.volumeReference->volume;
                m["volume_error_mm3"] = err;
                m["volume_error_relative"] = err / r.volumeReference->volume;
            }
            m["distance_ms"] = e.distanceMs;
            x["mesh"] = m;
        }
        rows.push_back(x);
    }
    j["results"] = rows;
    return j;
}

} // namespace kerf

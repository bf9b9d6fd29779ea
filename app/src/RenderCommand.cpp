// kerf render FILE.kerf -o OUT.png: voxelizes the part and traces it with the
// Vulkan compute tracer, headless (no window, no window system), then shades
// and writes the image. Without a usable Vulkan device it says so once and
// uses the CPU reference tracer, which runs the same algorithm.

#include "kerf/app/Arguments.hpp"
#include "kerf/app/Commands.hpp"
#include "kerf/app/DocumentSummary.hpp"
#include "kerf/app/Failure.hpp"
#include "kerf/app/Format.hpp"
#include "kerf/app/UnknownFieldWarnings.hpp"
#include "kerf/app/VoxelizeProgress.hpp"
#include "kerf/document/AtomicFile.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/viewport/BrickRenderer.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/GpuVoxelizer.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"
#include "kerf/viewport/SceneRenderer.hpp"
#include "kerf/viewport/VulkanError.hpp"
#include "kerf/voxelizer/BrickLeaves.hpp"
#include "kerf/voxelizer/RequestBudget.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <unistd.h>
#include <ostream>

namespace kerf {

namespace {

const char* kRenderHelp = R"(Usage: kerf render FILE.kerf -o OUT.png [--size WxH] [--view NAME]
                   [--feature-size MM] [--quality voxels|exact|exact-everywhere]
                   [--ortho] [--cpu] [--voxelizer cpu|gpu] [--renderer tracer|bricks]
                   [--json]
                   [-D NAME=VALUE]...

Voxelizes the part and traces it with the Vulkan compute tracer, without a
window, then writes a shaded PNG.

Options:
  -o, --output OUT.png  the image to write (written whole or not at all)
  --size WxH            image size in pixels (default 1280x960)
  --view NAME           iso (default), front, back, left, right, top, bottom
  --feature-size MM     voxel size (default: the document's)
  --quality Q           voxels (default): the surface interpolated in the
                        voxels; exact: each voxel hit checked on the exact
                        field and refined where the voxels round an edge or
                        fill an intersection (sharp edges; the viewport's
                        Exact Edges); exact-everywhere: every ray refined,
                        the slow reference exact is measured against
  --ortho               orthographic instead of perspective projection
  --cpu                 use the CPU reference tracer instead of Vulkan
  --voxelizer V         cpu (default): voxelize with oneTBB on every core;
                        gpu: voxelize on the Vulkan device with compute
                        shaders and trace the voxels where they were built
                        (falls back to cpu, saying why, when the device
                        cannot; not with --cpu)
  --renderer R          tracer (default): the compute tracer walks each
                        pixel's ray down the voxels' trees; bricks: the
                        brick renderer (the voxels as 8x8x8-voxel bricks in
                        3D textures, one cube drawn per brick, the texture
                        unit interpolating): the same picture, measured 18
                        to 32 times slower on an H200 (docs/benchmarks.md);
                        voxels only (no --quality exact); with --voxelizer
                        gpu the bricks are made from the GPU's voxels
  --json                print the figures as one JSON object
  -D NAME=VALUE         set the document's parameter NAME (a number or an
                        expression, like 19 or 3/4in) for this run; repeatable
  --help                show this help

Exit status: 0 written, 1 the work failed, 2 bad usage or a bad input file.
)";

double msSince(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

} // namespace

int runRender(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
    try {
        const Arguments a(args,
                          {"-o", "--output", "--size", "--view", "--feature-size", "--quality", "--voxelizer", "--renderer",
                           "-D"},
                          {"--ortho", "--cpu", "--json", "--help", "-h"});
        if (a.has("--help") || a.has("-h")) {
            out << kRenderHelp;
            return 0;
        }
        if (a.positional().size() != 1) throw UsageError("expects exactly one FILE.kerf");
        const auto output = a.value("-o") ? a.value("-o") : a.value("--output");
        if (!output) throw UsageError("needs -o OUT.png");
        const ImageSize size = a.value("--size") ? Arguments::parseImageSize("--size", *a.value("--size")) : ImageSize{};
        const std::string view = a.value("--view").value_or("iso");
        const std::string qualityName = a.value("--quality").value_or("voxels");
        const std::optional<TraceQuality> quality = parseTraceQuality(qualityName);
        if (!quality) throw UsageError("--quality must be voxels, exact or exact-everywhere, not '" + printable(qualityName) +
                                        "'");
        const std::string voxelizerName = a.value("--voxelizer").value_or("cpu");
        if (voxelizerName != "cpu" && voxelizerName != "gpu")
            throw UsageError("--voxelizer must be cpu or gpu, not '" + printable(voxelizerName) + "'");
        if (voxelizerName == "gpu" && a.has("--cpu"))
            throw UsageError("--voxelizer gpu needs the Vulkan device, and --cpu leaves it out");
        const std::string rendererName = a.value("--renderer").value_or("tracer");
        if (rendererName != "tracer" && rendererName != "bricks")
            throw UsageError("--renderer must be tracer or bricks, not '" + printable(rendererName) + "'");
        const bool withBricks = rendererName == "bricks";
        if (withBricks && a.has("--cpu"))
            throw UsageError("--renderer bricks draws with the Vulkan device, and --cpu leaves it out");
        if (withBricks && *quality != TraceQuality::Voxels)
            throw UsageError("--renderer bricks draws the voxels only: --quality " + qualityName +
                             " needs the compute tracer");
        const std::filesystem::path file = a.positional()[0];
        const bool requested = a.value("--feature-size").has_value();
        const double requestedSize = requested ? Arguments::parseFeatureSize("--feature-size", *a.value("--feature-size")) : 0.0;
        // The output first: a device, a folder, an unwritable place or the
        // document itself is refused before any work (and left as it is).
        refuseOverwriting(*output, file.string(), "the document being read");
        try {
            checkOutputFile(*output);
        } catch (const OutputFileError& e) {
            throw RefusedRequest(e.what());
        }

        const Document doc = Document::load(file, a.defines());
        warnOfUnknownFields(doc, "kerf render", err);
        if (const std::string idle = describeToolsCuttingNothing(doc); !idle.empty())
            err << "kerf render: warning: " << idle << "\n";
        const Tape tape = compileTape(doc);
        const double featureSize =
            requested ? requestedSize : doc.settings.featureSize.value_or(defaultFeatureSize(tape.bounds()));
        if (tape.empty() || tape.bounds().isEmpty()) {
            err << "kerf render: " << printable(file.string()) << ": the part is empty (nothing visible); nothing to render\n";
            return 1;
        }
        // What the voxels and the picture would take, against the machine.
        const RequestCost cost =
            estimateRequest(tape, featureSize, RequestKind::Render, double(size.width) * double(size.height));
        if (const auto over = overBudget(cost, RequestBudget::forThisMachine(), featureSize))
            throw RefusedRequest(printable(file.string(), 400) + ": rendering at " + *over);
        Camera camera;
        try {
            camera = Camera::standardView(tape.bounds(), view, size.width, size.height,
                                          a.has("--ortho") ? Projection::Orthographic : Projection::Perspective);
        } catch (const std::invalid_argument& e) {
            throw UsageError(std::string("--view: ") + printable(e.what()));
        }

        auto t0 = std::chrono::steady_clock::now();
        const GridLayout layout = GridLayout::choose(tape.bounds(), featureSize);
        if (!layout.note.empty()) err << "kerf render: " << layout.note << "\n";
        // The voxels: on the CPU unless the GPU voxelizer was asked for and builds them.
        std::optional<FlatVoxelBuffers> buffers;
        double voxelizeMs = 0.0;
        std::size_t populatedVoxels = 0, voxelBytes = 0;
        std::string builtBy = "cpu";
        const auto voxelizeOnTheCpu = [&] {
            t0 = std::chrono::steady_clock::now();
            const VoxelSnapshot snap = voxelizeWithProgress(tape, layout, "kerf render", cost.seconds > 2.0, err);
            buffers = FlatVoxelBuffers::flatten(snap);
            voxelizeMs = msSince(t0);
            populatedVoxels = snap.populatedVoxels();
            voxelBytes = snap.bytes();
            builtBy = "cpu";
        };
        if (voxelizerName == "cpu") voxelizeOnTheCpu();
        const std::filesystem::path shownOutput = printable(*output);

        // Reference meshes: a missing or broken one is named and left out.
        std::vector<std::string> problems;
        const std::vector<PlacedMesh> meshes = loadReferenceMeshes(doc, file.parent_path(), problems);
        for (const auto& p : problems)
            err << "kerf render: " << printable(file.string()) << ": " << printable(p, 400) << " (left out)\n";

        TraceImage image;
        RgbaImage picture;
        std::string device;
        double traceMs = 0.0, gpuMs = -1.0;
        bool usedVulkan = false;
        // A large picture takes a while on a CPU device: say so (Ctrl+C stops it).
        const bool tracingLong = cost.fixedSeconds > 2.0 && ::isatty(STDERR_FILENO);
        if (tracingLong)
            err << "kerf render: tracing " << size.width << "x" << size.height << " pixels (about "
                << describeSeconds(cost.fixedSeconds) << " on a CPU device; Ctrl+C stops)...\n";
        if (!a.has("--cpu")) {
            try {
                vk::Context ctx;
                vk::ComputeTracer tracer(ctx);
                std::optional<vk::GpuVoxels> gpuVoxels;
                if (!buffers) {
                    vk::GpuVoxelizer voxelizer(ctx);
                    vk::GpuVoxelizeReport report;
                    t0 = std::chrono::steady_clock::now();
                    gpuVoxels = voxelizer.build(tape, layout, {}, &report);
                    voxelizeMs = msSince(t0);
                    if (gpuVoxels) {
                        populatedVoxels = gpuVoxels->populatedVoxels;
                        voxelBytes = gpuVoxels->bytes();
                        builtBy = "gpu";
                    } else {
                        err << "kerf render: the GPU voxelizer cannot build this part here (" << printable(report.whyNot, 300)
                            << "); voxelizing on the CPU\n";
                        voxelizeOnTheCpu();
                    }
                }
                vk::SceneRenderer renderer(ctx);
                renderer.setMeshes(meshes);
                vk::SceneOptions options;
                options.lights = ShadeOptions::forCamera(camera);
                options.quality = *quality;
                if (withBricks) {
                    vk::BrickRenderer bricks(ctx);
                    // The GPU voxelizer's voxels come back to the host to be made into bricks.
                    bricks.setBricks(BrickLeaves::fromVoxels(gpuVoxels ? gpuVoxels->readBack(ctx) : *buffers));
                    t0 = std::chrono::steady_clock::now();
                    picture = renderer.render(bricks, camera, tape.features(), options);
                    traceMs = msSince(t0);
                    gpuMs = bricks.lastGpuMilliseconds();
                    image = bricks.render(camera); // for the figures below
                } else {
                    if (!gpuVoxels) tracer.setVoxels(*buffers);
                    const vk::VoxelAddresses voxels = gpuVoxels ? gpuVoxels->addresses(1) : tracer.voxels();
                    t0 = std::chrono::steady_clock::now();
                    picture = renderer.render(tracer, voxels, camera, tape.features(), options);
                    traceMs = msSince(t0);
                    gpuMs = tracer.lastTiming().gpuMilliseconds;
                    image = tracer.trace(camera, voxels, nullptr, {}, *quality); // for the figures below
                }
                device = ctx.deviceDescription();
                usedVulkan = true;
            } catch (const vk::VulkanError& e) {
                err << "kerf render: no usable Vulkan device (" << printable(e.what(), 300)
                    << "); using the CPU reference tracer" << (withBricks ? " instead of the brick renderer" : "")
                    << "\n";
            }
        }
        if (!usedVulkan) {
            if (!buffers) voxelizeOnTheCpu();
            t0 = std::chrono::steady_clock::now();
            image = traceVoxels(*buffers, camera, 0, {}, *quality);
            traceMs = msSince(t0);
            device = "CPU reference tracer";
            picture = shade(image, tape.features(), ShadeOptions::forCamera(camera));
            if (!meshes.empty()) err << "kerf render: the CPU fallback does not draw reference meshes\n";
        }
        writePng(*output, picture);

        std::size_t hits = 0;
        for (std::size_t i = 0; i < image.depth.size(); ++i) hits += image.hit(i);
        if (a.has("--json")) {
            nlohmann::ordered_json j;
            j["file"] = file.string();
            j["output"] = *output;
            j["width"] = size.width;
            j["height"] = size.height;
            j["view"] = view;
            j["quality"] = qualityName;
            j["renderer"] = usedVulkan ? rendererName : "cpu";
            j["device"] = device;
            j["vulkan"] = usedVulkan;
            j["feature_size_mm"] = layout.voxelSize;
            j["voxelizer"] = builtBy;
            j["populated_voxels"] = populatedVoxels;
            j["voxel_bytes"] = voxelBytes;
            j["voxelize_ms"] = voxelizeMs;
            j["trace_ms"] = traceMs;
            if (gpuMs >= 0.0) j["trace_gpu_ms"] = gpuMs;
            j["pixels_hit"] = hits;
            out << j.dump(2) << "\n";
        } else {
            out << shownOutput.string() << ": " << size.width << "x" << size.height << " " << view << " view of "
                << printable(file.string()) << "\n  quality:      " << qualityName << "\n  device:       " << device
                << (usedVulkan && withBricks ? " (brick renderer)" : "")
                << "\n  voxels:       " << populatedVoxels << " of " << mm(layout.voxelSize) << " mm, "
                << voxelBytes / 1024 << " KiB, built in " << long(voxelizeMs) << " ms on the "
                << (builtBy == "gpu" ? "GPU" : "CPU") << "\n  trace:        "
                << significant(traceMs, 3) << " ms";
            if (gpuMs >= 0.0) out << " (GPU " << significant(gpuMs, 3) << " ms)";
            out << "\n  pixels hit:   " << hits << "\n";
        }
        return 0;
    } catch (const UsageError& e) {
        err << "kerf render: " << e.what() << " (see kerf render --help)\n";
        return 2;
    } catch (const DocumentError& e) {
        err << "kerf render: " << e.what() << "\n";
        return 2;
    } catch (const RefusedRequest& e) {
        err << "kerf render: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        err << "kerf render: " << describeFailure(e) << "\n";
        return 1;
    }
}

} // namespace kerf

// kerf bench [FILE.kerf]: measures the trade between speed and accuracy at a
// list of feature sizes (TradeBench.hpp says what each figure is) and prints
// it as two tables, the screen's and the export's; --json and --plot write
// the same figures to files, whole or not at all.

#include "kerf/app/Arguments.hpp"
#include "kerf/app/Commands.hpp"
#include "kerf/app/Failure.hpp"
#include "kerf/app/Format.hpp"
#include "kerf/app/InstalledResources.hpp"
#include "kerf/app/TradeBench.hpp"
#include "kerf/document/AtomicFile.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/RequestBudget.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <sstream>
#include <unistd.h>

namespace kerf {

namespace {

const char* kBenchHelp = R"(Usage: kerf bench [FILE.kerf] [--feature-sizes LIST] [--json OUT.json] [--plot OUT.png]
                  [--size WxH] [--view NAME] [--frames N] [--cpu] [--trace-only]
                  [--exact-edges] [--bricks] [-D NAME=VALUE]...

Measures the trade between speed and accuracy for a part (the bundled side
chair when no file is given), at each feature size of LIST:
  screen: cold voxelization time; re-voxelization time after a typical edit
          (the part's smallest feature moved 5 mm along x, printed); GPU
          memory of the voxel buffers; trace time per frame on the device
          used (printed); on Vulkan, the same voxels built on the device by
          the GPU voxelizer too (cold and warm, with its voxel count against
          the CPU's); the traced picture against an exact sphere-traced
          reference of the same camera: depth error in mm and normal error
          in degrees (mean, 99th percentile, max) on pixels both hit, and the
          fraction of pixels only one of them hits; with --exact-edges, the
          same for the voxels refined on the exact field near each hit;
  export: triangles and time of the mesh kerf export writes; its distance to
          the exact surface (sampled on every triangle, mean and max); its
          volume against the exact field's integral (with its uncertainty).
docs/accuracy.md explains the methods and what to choose.

Options:
  --feature-sizes LIST  feature sizes in mm, comma-separated, like 2,1,0.5
                        (default: 4, 2 and 1 times the document's feature size)
  --json OUT.json       also write every figure as JSON
  --plot OUT.png        also draw the trade (error against time and memory)
  --size WxH            picture size in pixels (default 1280x960)
  --view NAME           iso (default), front, back, left, right, top, bottom
  --frames N            frames timed per feature size (default 5); on Vulkan
                        they run back to back, as a viewport draws (after
                        300 ms of warm-up that brings the GPU's clocks up)
  --cpu                 trace with the CPU reference tracer instead of Vulkan
  --trace-only          screen figures only: no mesh, no volume reference
  --exact-edges         also trace with the hybrid refinement (kerf render
                        --quality exact, the viewport's Exact Edges): its
                        trace time and picture error, in a second table
  --bricks              also draw with the brick renderer (kerf render
                        --renderer bricks; Vulkan only): its frame time,
                        memory and picture error, in a table of its own, and
                        its upload: in one piece, and in the viewport's rows
                        within the per-frame budget (submissions, longest)
  -D NAME=VALUE         set the document's parameter NAME (a number or an
                        expression, like 19 or 3/4in) for this run; repeatable
  --help                show this help

Feature sizes that would need more than 40 million voxels are refused.
Exit status: 0 measured; 1 the part is empty or the work failed; 2 bad usage
or a bad input file (the reason, naming the file, goes to stderr).
)";

constexpr double kMaxBenchVoxels = 4e7; // about 1.4 GB of voxels, and a mesh of about 80 M triangles

std::vector<double> parseFeatureSizes(const std::string& text)
{
    std::vector<double> sizes;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ','))
        sizes.push_back(Arguments::parseFeatureSize("--feature-sizes", item));
    if (sizes.empty() || text.back() == ',')
        throw UsageError("--feature-sizes must list millimetres separated by commas, like 2,1,0.5, not '" +
                         printable(text) + "'");
    // Coarse to fine, each once.
    std::sort(sizes.begin(), sizes.end(), std::greater<>());
    sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
    return sizes;
}

int parseFrames(const std::string& text)
{
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || v < 1 || v > 1000)
        throw UsageError("--frames must be a whole number from 1 to 1000, not '" + printable(text) + "'");
    return int(v);
}

// An output file must be (or become) a regular file in a folder that takes
// new files before minutes of measuring start (AtomicFile.hpp).
void checkOutputFolder(const std::string& option, const std::filesystem::path& file)
{
    try {
        checkOutputFile(file);
    } catch (const OutputFileError& e) {
        throw RefusedRequest(option + ": " + e.what());
    }
}

// Right-aligns `text` in `width` columns.
std::string right(const std::string& text, std::size_t width)
{
    return text.size() >= width ? text : std::string(width - text.size(), ' ') + text;
}

std::string milliseconds(double ms)
{
    if (ms >= 10000.0) return number(ms / 1000.0, 1) + " s";
    if (ms >= 100.0) return number(ms, 0) + " ms";
    return significant(ms, 2) + " ms";
}

std::string triple(const ErrorStats& s, int digits)
{
    return significant(s.mean, digits) + " / " + significant(s.p99, digits) + " / " + significant(s.max, digits);
}

std::string percent(double fraction) { return significant(100.0 * fraction, 2) + "%"; }

void printReport(std::ostream& out, const std::string& file, const TradeReport& r)
{
    out << "kerf bench: " << printable(file) << "\n";
    out << "  device:          " << r.device << "\n";
    if (!r.vulkanProblem.empty()) out << "  (no Vulkan:      " << r.vulkanProblem << ")\n";
    out << "  threads:         " << r.threads << " (voxelizer and mesher)\n";
    out << "  picture:         " << r.width << "x" << r.height << " " << r.view
        << " view; reference: exact sphere tracing (epsilon " << significant(r.referenceEpsilon, 1) << " mm), "
        << grouped(r.referencePixelsHit) << " pixels hit\n";
    if (r.edit)
        out << "  typical edit:    move '" << printable(r.edit->nodeId) << "' (" << nodeTypeName(r.edit->type)
            << (r.edit->instances > 1 ? ", " + grouped(r.edit->instances) + " instances" : std::string()) << ") by "
            << mm(kTypicalEditMm) << " mm along x, back, and again\n";
    else
        out << "  typical edit:    none (the part has no bounded visible primitive to move)\n";
    if (r.volumeReference) {
        const VolumeEstimate& v = *r.volumeReference;
        out << "  volume ref.:     " << number(v.volume, 1) << " mm^3 +- " << significant(v.uncertainty, 2)
            << " (exact field integrated with " << mm(v.cellSize) << " mm cells; +- is two standard errors)\n";
    }

    out << "\nScreen: voxels and trace (trace time per frame on the device above)\n";
    const std::array<std::pair<const char*, std::size_t>, 8> screen{{{"feature", 9},
                                                                     {"voxelize", 10},
                                                                     {"re-voxelize", 18},
                                                                     {"GPU memory", 11},
                                                                     {"trace", 10},
                                                                     {"depth err mm mean/p99/max", 28},
                                                                     {"normal err deg mean/p99/max", 28},
                                                                     {"silhouette", 11}}};
    out << " ";
    for (const auto& [name, width] : screen)
        out << " " << right(name, width);
    out << "\n";
    for (const TradeRow& row : r.rows) {
        const std::string revox =
            row.revoxelize ? milliseconds(row.revoxelize->coarseMs) + " / " + milliseconds(row.revoxelize->finalMs)
                           : "-";
        const std::array<std::string, 8> cells{mm(row.featureSize) + " mm",
                                               milliseconds(row.voxelizeMs),
                                               revox,
                                               megabytes(row.gpuBytes),
                                               milliseconds(row.traceMs),
                                               triple(row.picture.depthMm, 2),
                                               triple(row.picture.normalDegrees, 2),
                                               percent(row.picture.mismatchFraction())};
        out << " ";
        for (std::size_t i = 0; i < cells.size(); ++i)
            out << " " << right(cells[i], screen[i].second);
        out << "\n";
    }
    out << "  re-voxelize: to the coarse / the complete publication; silhouette: pixels only one picture hits\n";
    if (std::any_of(r.rows.begin(), r.rows.end(), [](const TradeRow& x) { return x.gpuVoxelize; })) {
        out << "\nVoxels built on the GPU (the same grid, the device above)\n";
        out << "    feature   cold       warm       populated voxels\n";
        for (const TradeRow& row : r.rows) {
            if (!row.gpuVoxelize) continue;
            const GpuVoxelizeFigures& g = *row.gpuVoxelize;
            out << "  " << right(mm(row.featureSize) + " mm", 9);
            if (!g.whyNot.empty()) {
                out << "  not built: " << g.whyNot << "\n";
                continue;
            }
            out << " " << right(milliseconds(g.coldMs), 10) << " " << right(milliseconds(g.warmMs), 10) << "  "
                << g.populatedVoxels
                << (g.populatedVoxels == row.populatedVoxels ? " (as the CPU's)"
                                                             : " (the CPU's: " + std::to_string(row.populatedVoxels) + ")")
                << "\n";
        }
        out << "  cold: a fresh GPU voxelizer; warm: the same part again, as after an edit of every tile\n";
    }
    for (const TradeRow& row : r.rows)
        if (!row.note.empty()) out << "  " << mm(row.featureSize) << " mm: " << row.note << "\n";

    if (std::any_of(r.rows.begin(), r.rows.end(), [](const TradeRow& x) { return x.exactEdges; })) {
        out << "\nScreen, exact edges: the same voxels, the surface refined on the exact field near each hit\n";
        const std::array<std::pair<const char*, std::size_t>, 6> exact{{{"feature", 9},
                                                                        {"trace", 10},
                                                                        {"vs voxels", 10},
                                                                        {"depth err mm mean/p99/max", 28},
                                                                        {"normal err deg mean/p99/max", 28},
                                                                        {"silhouette", 11}}};
        out << " ";
        for (const auto& [name, width] : exact)
            out << " " << right(name, width);
        out << "\n";
        for (const TradeRow& row : r.rows) {
            if (!row.exactEdges) continue;
            const PictureFigures& e = *row.exactEdges;
            const std::array<std::string, 6> cells{
                mm(row.featureSize) + " mm",
                milliseconds(e.traceMs),
                row.traceMs > 0.0 ? significant(e.traceMs / row.traceMs, 2) + "x" : std::string("-"),
                triple(e.picture.depthMm, 2),
                triple(e.picture.normalDegrees, 2),
                percent(e.picture.mismatchFraction())};
            out << " ";
            for (std::size_t i = 0; i < cells.size(); ++i)
                out << " " << right(cells[i], exact[i].second);
            out << "\n";
        }
    }

    if (std::any_of(r.rows.begin(), r.rows.end(), [](const TradeRow& x) { return x.bricks; })) {
        out << "\nScreen, brick renderer: the same voxels as bricks of 8x8x8 voxels, one cube drawn per brick\n";
        const std::array<std::pair<const char*, std::size_t>, 10> columns{{{"feature", 9},
                                                                          {"bricks", 9},
                                                                          {"GPU MB", 9},
                                                                          {"build", 10},
                                                                          {"upload", 10},
                                                                          {"frames/longest", 17},
                                                                          {"frame", 10},
                                                                          {"vs tracer", 10},
                                                                          {"depth err mm mean/p99/max", 28},
                                                                          {"silhouette", 11}}};
        out << " ";
        for (const auto& [name, width] : columns)
            out << " " << right(name, width);
        out << "\n";
        for (const TradeRow& row : r.rows) {
            if (!row.bricks) continue;
            const BrickFigures& b = *row.bricks;
            const std::array<std::string, 10> cells{
                mm(row.featureSize) + " mm",
                std::to_string(b.bricks),
                significant(double(b.deviceBytes) / 1e6, 3),
                milliseconds(b.buildMs),
                milliseconds(b.uploadMs),
                std::to_string(b.uploadFrames) + " / " + milliseconds(b.uploadFrameMaxMs),
                milliseconds(b.drawn.traceMs),
                row.traceMs > 0.0 ? significant(b.drawn.traceMs / row.traceMs, 2) + "x" : std::string("-"),
                triple(b.drawn.picture.depthMm, 2),
                percent(b.drawn.picture.mismatchFraction())};
            out << " ";
            for (std::size_t i = 0; i < cells.size(); ++i)
                out << " " << right(cells[i], columns[i].second);
            out << "\n";
        }
    }

    const bool exported = std::any_of(r.rows.begin(), r.rows.end(), [](const TradeRow& x) { return x.exported; });
    if (!exported) return;
    out << "\nExport: marching cubes on the exact field (time excludes writing the STL)\n";
    const std::array<std::pair<const char*, std::size_t>, 6> exportColumns{{{"feature", 9},
                                                                            {"triangles", 12},
                                                                            {"export", 10},
                                                                            {"distance mm mean / max", 24},
                                                                            {"volume error", 24},
                                                                            {"STL size", 11}}};
    out << " ";
    for (const auto& [name, width] : exportColumns)
        out << " " << right(name, width);
    out << "\n";
    for (const TradeRow& row : r.rows) {
        if (!row.exported) continue;
        const ExportFigures& e = *row.exported;
        std::string volume = "-";
        if (r.volumeReference && r.volumeReference->volume > 0.0) {
            const double err = e.volume - r.volumeReference->volume;
            volume = significant(err, 2) + " mm^3 (" + significant(100.0 * err / r.volumeReference->volume, 2) + "%)";
        }
        const std::array<std::string, 6> cells{mm(row.featureSize) + " mm",
                                               grouped(e.triangles),
                                               milliseconds(e.meshMs),
                                               significant(e.distance.mean, 2) + " / " + significant(e.distance.max, 2),
                                               volume,
                                               megabytes(e.stlBytes)};
        out << " ";
        for (std::size_t i = 0; i < cells.size(); ++i)
            out << " " << right(cells[i], exportColumns[i].second);
        if (!e.watertight) out << "  (not watertight)";
        if (e.distance.unresolved) out << "  (" << grouped(e.distance.unresolved) << " samples reached no surface)";
        out << "\n";
    }
    // How sure each max is: the true maximum over the samples lies between
    // the largest |f| (a lower bound) and the max shown (an upper bound).
    double gap = 0.0;
    for (const TradeRow& row : r.rows)
        if (row.exported) gap = std::max(gap, row.exported->distance.max - row.exported->distance.maxLowerBound);
    out << "  distance: sampled at vertices, edge midpoints and centroids, projected onto the surface; each max\n"
           "  is an upper bound, at most "
        << significant(gap, 2) << " mm above the largest |f| at the samples (a lower bound)\n";
}

} // namespace

int runBench(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, const TradePlotter& plot)
{
    std::string file;
    try {
        const Arguments a(args, {"--feature-sizes", "--json", "--plot", "--size", "--view", "--frames", "-D"},
                          {"--cpu", "--trace-only", "--exact-edges", "--bricks", "--help", "-h"});
        if (a.has("--help") || a.has("-h")) {
            out << kBenchHelp;
            return 0;
        }
        if (a.positional().size() > 1) throw UsageError("expects at most one FILE.kerf");
        file = a.positional().empty() ? defaultExample().string() : a.positional()[0];
        TradeBenchOptions options;
        if (const auto v = a.value("--size")) {
            const ImageSize size = Arguments::parseImageSize("--size", *v);
            options.width = size.width;
            options.height = size.height;
        }
        options.view = a.value("--view").value_or("iso");
        static constexpr std::array<std::string_view, 7> kViews{"iso",   "front", "back",  "left",
                                                                "right", "top",   "bottom"};
        if (std::find(kViews.begin(), kViews.end(), options.view) == kViews.end())
            throw UsageError("--view: unknown view '" + printable(options.view) +
                             "' (iso, front, back, left, right, top, bottom)");
        if (const auto v = a.value("--frames")) options.frames = parseFrames(*v);
        options.cpu = a.has("--cpu");
        options.traceOnly = a.has("--trace-only");
        options.exactEdges = a.has("--exact-edges");
        options.bricks = a.has("--bricks");
        const auto json = a.value("--json");
        const auto png = a.value("--plot");
        if (json) checkOutputFolder("--json", *json);
        if (png) {
            if (!plot) throw UsageError("--plot: this program was built without plotting (Qt Charts); use kerf");
            checkOutputFolder("--plot", *png);
        }
        const std::optional<std::string> sizes = a.value("--feature-sizes");
        if (sizes) options.featureSizes = parseFeatureSizes(*sizes);
        for (const auto& written : {json, png})
            if (written) refuseOverwriting(*written, file, "the document being measured");
        if (json && png) refuseOverwriting(*png, *json, "the --json file");

        const Document doc = Document::load(file, a.defines());
        const Tape tape = compileTape(doc);
        if (tape.empty() || tape.bounds().isEmpty()) {
            err << "kerf bench: " << printable(file) << ": the part is empty (nothing visible); nothing to measure\n";
            return 1;
        }
        if (!tape.bounds().isBounded()) {
            err << "kerf bench: " << printable(file)
                << ": the part is unbounded (a halfspace nothing clips); nothing to measure\n";
            return 1;
        }
        if (!sizes) {
            const double base = doc.settings.featureSize.value_or(defaultFeatureSize(tape.bounds()));
            options.featureSizes = {4.0 * base, 2.0 * base, base};
        }
        // Refuse what would take hours and more memory than the machine has:
        // the bench's own cap, then the machine's budget for the mesh (or,
        // with --trace-only, for the voxels and the picture).
        const RequestBudget budget = RequestBudget::forThisMachine();
        for (double fs : options.featureSizes) {
            VoxelEstimate estimate;
            const RequestCost cost =
                options.traceOnly ? estimateRequest(tape, fs, RequestKind::Render, double(options.width) * options.height, &estimate)
                                  : estimateRequest(tape, fs, RequestKind::Mesh, 0.0, &estimate);
            const std::string which = sizes ? "--feature-sizes: " : "the default feature sizes: ";
            if (estimate.populatedVoxels > kMaxBenchVoxels) {
                const double smallest = fs * std::sqrt(estimate.populatedVoxels / kMaxBenchVoxels);
                throw UsageError(which + mm(fs) + " mm needs about " + significant(estimate.populatedVoxels / 1e6, 2) +
                                 " million voxels (" + significant(estimate.bytes / 1e9, 2) + " GB) for " +
                                 printable(file) + "; the bench builds at most 40 million: choose " +
                                 significant(smallest * 1.05, 2) + " mm or more");
            }
            if (const auto over = overBudget(cost, budget, fs)) throw RefusedRequest(which + *over);
        }

        const bool terminal = ::isatty(STDERR_FILENO);
        if (terminal)
            options.progress = [&](const std::string& what) {
                err << "\r\033[Kkerf bench: " << what << "..." << std::flush;
            };
        const TradeReport report = runTradeBench(doc, options);
        if (terminal) err << "\r\033[K" << std::flush;
        if (!report.vulkan && !options.cpu)
            err << "kerf bench: no usable Vulkan device (" << report.vulkanProblem
                << "); trace times are the CPU reference tracer's\n";
        if (options.bricks && !report.vulkan)
            err << "kerf bench: --bricks needs a Vulkan device; the brick renderer was not measured\n";

        printReport(out, file, report);
        if (json) {
            nlohmann::ordered_json j;
            j["file"] = file;
            j.update(tradeReportJson(report));
            writeFileAtomically(*json, j.dump(2) + "\n");
            out << "\nwrote " << printable(*json) << "\n";
        }
        if (png) {
            plot(report, std::filesystem::path(file).filename().string(), *png);
            out << (json ? "" : "\n") << "wrote " << printable(*png) << "\n";
        }
        return 0;
    } catch (const UsageError& e) {
        err << "kerf bench: " << e.what() << " (see kerf bench --help)\n";
        return 2;
    } catch (const DocumentError& e) {
        err << "kerf bench: " << e.what() << "\n";
        return 2;
    } catch (const RefusedRequest& e) {
        err << "kerf bench: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        err << "kerf bench: " << (file.empty() ? "" : printable(file) + ": ") << describeFailure(e) << "\n";
        return 1;
    }
}

} // namespace kerf

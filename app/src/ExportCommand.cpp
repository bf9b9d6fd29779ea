// kerf export FILE.kerf -o OUT.stl|OUT.3mf: meshes the part to a tolerance
// (marching cubes with sharp features on the exact field, then simplified
// and refined against it: kerf_mesher), fits the mesh to the file's
// coordinates and writes it, whole or not at all, reporting the mesh as a
// reader of the file will see it.
// Exit 0 when written; 1 when the part is empty or the export failed
// (nothing is written); 2 for bad usage or a refused document.

#include "kerf/app/Arguments.hpp"
#include "kerf/app/Commands.hpp"
#include "kerf/app/DocumentSummary.hpp"
#include "kerf/app/ExportPreflight.hpp"
#include "kerf/app/Failure.hpp"
#include "kerf/app/Format.hpp"
#include "kerf/app/UnknownFieldWarnings.hpp"
#include "kerf/document/AtomicFile.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/NodePlacement.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshFile.hpp"
#include "kerf/mesher/MeshPart.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <unistd.h>

namespace kerf {

namespace {

const char* kExportHelp = R"(Usage: kerf export FILE.kerf -o OUT.stl|OUT.3mf [--tolerance MM] [--feature-size MM]
                   [--feature ID|NAME] [--ascii] [--json] [-D NAME=VALUE]...

Meshes the part and writes it for a slicer or CAM program: binary STL for
.stl (ASCII with --ascii), 3MF for .3mf (indexed triangles, millimetres,
the part's name). Sharp edges and corners are kept; flat faces become a few
large triangles and curved faces as many as the tolerance needs. The file
is written whole or not at all, and only when a reader of it gets a closed,
consistently oriented 2-manifold without degenerate or crossing triangles
(STL welded by the coordinates written, as slicers do). Prints the figures
of the mesh as read back from those coordinates.

Options:
  -o, --output OUT       the file to write: .stl or .3mf (required)
  --tolerance MM         the largest distance allowed between the mesh and
                         the exact surface: the mesh is simplified and
                         refined to it (flat faces become a few large
                         triangles, curved faces get what the tolerance
                         needs). Default: 0.05 mm, finer than a router or
                         printer reproduces. 0: no simplification, the
                         marching-cubes mesh at the feature size (quicker,
                         hundreds of MB for a whole part)
  --feature-size MM      the smallest feature resolved: the cell edge of the
                         marching cubes (default: the document's feature
                         size, else about a thousandth of the part's largest
                         extent). Walls, pins and gaps thinner than this
                         are found and named in a warning, with the
                         feature size that resolves them.
  --feature ID|NAME      export only this feature (its id, or a name only it
                         has) with what it holds, where the part places it
                         (every copy of an array or mirror above it): one
                         board of a cabinet, for the CNC; at the part's
                         feature size unless told
  --ascii                write ASCII STL instead of binary (.stl only)
  --json                 print the figures as one JSON object
  -D NAME=VALUE          set the document's parameter NAME (a number or an
                         expression, like 19 or 3/4in) for this export;
                         repeatable
  --help                 show this help

STL stores float32 coordinates: a part far from the origin (about 10 m and
more at 0.01 mm) cannot keep its detail there and gets a warning; 3MF then
stores it around its own centre.

Exit status: 0 written; 1 the part is empty or the export failed (nothing is
written); 2 bad usage, a refused document, an output that is not a regular
file, or a mesh larger than this machine allows (the reason, naming the
file, goes to stderr; docs/cli.md has the limits).
)";

// Ctrl-C (SIGINT) or SIGTERM while meshing cancels it: nothing is written.
std::atomic<bool> interrupted{false};
extern "C" void onInterrupt(int) { interrupted = true; }

// Installs onInterrupt for the command's lifetime, then restores the defaults.
class InterruptGuard {
public:
    InterruptGuard()
    {
        interrupted = false;
        previousInt_ = std::signal(SIGINT, onInterrupt);
        previousTerm_ = std::signal(SIGTERM, onInterrupt);
    }
    ~InterruptGuard()
    {
        std::signal(SIGINT, previousInt_);
        std::signal(SIGTERM, previousTerm_);
    }
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

private:
    void (*previousInt_)(int);
    void (*previousTerm_)(int);
};

double since(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

} // namespace

int runExport(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
    std::string file;
    try {
        const Arguments a(args, {"-o", "--output", "--feature-size", "--tolerance", "--feature", "-D"},
                          {"--ascii", "--json", "--help", "-h"});
        if (a.has("--help") || a.has("-h")) {
            out << kExportHelp;
            return 0;
        }
        if (a.positional().size() != 1) throw UsageError("expects exactly one FILE.kerf");
        auto output = a.value("-o");
        if (const auto o = a.value("--output")) output = o;
        if (!output || output->empty()) throw UsageError("needs an output file: -o OUT.stl or -o OUT.3mf");
        std::optional<double> requested;
        if (const auto v = a.value("--feature-size"))
            requested = Arguments::parseFeatureSize("--feature-size", *v);
        const std::optional<std::string> toleranceText = a.value("--tolerance");
        double tolerance =
            toleranceText ? Arguments::parseTolerance("--tolerance", *toleranceText) : kDefaultExportTolerance;
        const bool ascii = a.has("--ascii"), json = a.has("--json");
        file = a.positional()[0];
        const std::filesystem::path target = *output;
        refuseOverwriting(target.string(), file, "the document being read");
        std::optional<MeshFileFormat> format = meshFileFormatFor(target, ascii);
        if (!format) {
            // A target that is no regular file is refused as such first; a
            // link to a file takes the format of the file it points to.
            try {
                format = meshFileFormatFor(checkOutputFile(target), ascii);
            } catch (const OutputFileError& e) {
                throw RefusedRequest(e.what());
            }
        }
        if (!format)
            throw UsageError("cannot tell the format of '" + printable(target.string()) +
                             "': name it .stl (STL) or .3mf (3MF)");
        if (ascii && *format != MeshFileFormat::AsciiStl) throw UsageError("--ascii applies to .stl files only");

        const auto start = std::chrono::steady_clock::now();
        // Ctrl+C from here on cancels cleanly: loading and the estimate
        // below take seconds on large documents and slow builds.
        const InterruptGuard guard;
        auto interruptedMessage = [&] {
            err << "kerf export: " << printable(file) << ": interrupted; " << printable(target.string())
                << " not written\n";
            return 1;
        };
        const Document whole = Document::load(file, a.defines());
        warnOfUnknownFields(whole, "kerf export", err);
        // The part's own feature size, also for one feature of it.
        const Aabb wholeBounds = partBounds(whole);
        std::string partName = std::filesystem::path(file).stem().string();
        Document doc = whole;
        std::string alone; // "Side L alone, with every copy of the mirror above it"
        if (const auto feature = a.value("--feature")) {
            std::string id;
            try {
                id = edit::featureNamed(whole, *feature);
            } catch (const std::invalid_argument& e) {
                throw RefusedRequest(printable(file) + ": --feature: " + e.what());
            }
            doc = edit::documentOfNodeAlone(whole, id);
            const Node& n = *whole.root.find(id);
            partName = n.name.value_or(id);
            alone = edit::describeFeatureAlone(whole, id);
        }
        const Aabb bounds = partBounds(doc);
        if (bounds.isEmpty()) {
            err << "kerf export: " << printable(file) << ": the part is empty (nothing is visible); nothing to export\n";
            return 1;
        }
        const char* source = requested ? "option" : doc.settings.featureSize ? "document" : "default";
        MeshOptions options;
        options.featureSize =
            requested.value_or(doc.settings.featureSize.value_or(defaultFeatureSize(wholeBounds.isEmpty() ? bounds : wholeBounds)));
        options.tolerance = tolerance;
        // A tolerance asked for that the file cannot hold is refused; the
        // default on a part far from the origin is written with a warning
        // (below), as the issue asks of far parts.
        if (const auto why = toleranceText ? toleranceTheFileCannotHold(bounds, *format, tolerance) : std::nullopt)
            throw RefusedRequest(printable(file) + ": " + *why);
        // The default, where the file cannot hold it, is the finest the file
        // holds: meshing to less only splits triangles that rounding undoes
        // (a sphere 200 km across split on past 5 GB for 0.05 mm that its
        // STL steps by 8 mm).
        if (const auto why = partTheFileCannotHold(bounds, *format))
            throw RefusedRequest(printable(file) + ": " + *why);
        const double defaultTolerance = tolerance;
        const bool heldCoarser = !toleranceText && toleranceTheFileCannotHold(bounds, *format, tolerance);
        if (heldCoarser) {
            tolerance = defaultToleranceFor(bounds, *format);
            options.tolerance = tolerance;
        }
        // The output and the machine's budget, before any meshing.
        preflightExport(doc, file, target, options.featureSize, options.tolerance);
        // Said once the request is taken (a refusal stays one line).
        if (heldCoarser)
            err << "kerf export: warning: the default tolerance of " << mm(defaultTolerance) << " mm is finer than "
                << (*format == MeshFileFormat::ThreeMf ? "a 3MF" : "an STL") << " file holds for this part: meshed to "
                << significant(tolerance, 2) << " mm, the finest it holds\n";
        if (interrupted) return interruptedMessage();

        const bool terminal = ::isatty(STDERR_FILENO);
        int shownPercent = -1;
        Progress::OnFraction showPercent;
        if (terminal) {
            showPercent = [&](double fraction) {
                const int percent = int(fraction * 100.0);
                if (percent == shownPercent) return;
                shownPercent = percent;
                err << "\rkerf export: meshing at " << mm(options.featureSize) << " mm... " << percent << "%"
                    << std::flush;
            };
        }
        const Progress progress(showPercent, [] { return interrupted.load(); });
        const auto meshStart = std::chrono::steady_clock::now();
        // Meshing, checking the mesh as a reader will see it, and writing;
        // the file is written whole or, if the process is killed, not at all.
        const ExportedPart exported = exportPart(doc, options, target, *format, partName, progress);
        const double meshSeconds = since(meshStart);
        if (terminal) err << "\r\033[K" << std::flush;
        // (A signal that came only while the file was being written leaves
        // it complete: then it is reported as written.)
        if (exported.cancelled) return interruptedMessage();
        const MeshStats& stats = exported.stats;
        if (exported.empty) {
            err << "kerf export: " << printable(file) << ": " << describeEmptyPart(stats, bounds)
                << "; nothing to export\n";
            return 1;
        }
        const MeshFileReport& written = exported.report;
        const std::string& fallback = exported.simplificationDefects;
        if (!written.solid()) {
            err << "kerf export: " << printable(file) << ": " << describeNotWritten(exported, *format) << "; "
                << printable(target.string()) << " not written\n";
            return 1;
        }
        if (!fallback.empty())
            err << "kerf export: warning: the mesh simplified to " << mm(tolerance) << " mm had " << fallback
                << "; wrote the marching-cubes mesh at " << mm(stats.cellSize)
                << " mm instead (closed, sharp edges kept, larger, not held to the tolerance)\n";
        const MeshReport& report = written.asRead;
        const double seconds = since(start);
        // Where the file's coordinates leave little room to the tolerance.
        if (const std::string coarse =
                describeCoarseCoordinates(bounds, *format, written.spacing, written.offset, tolerance);
            !coarse.empty())
            err << "kerf export: warning: " << printable(target.string()) << ": " << coarse << "\n";
        const double ownFeatureSize = doc.settings.featureSize.value_or(defaultFeatureSize(bounds));
        if (const std::string idle = describeToolsCuttingNothing(doc); !idle.empty())
            err << "kerf export: warning: " << idle << "\n";
        if (stats.hiddenDetailCells > 0)
            err << "kerf export: warning: " << describeHiddenDetail(stats, ownFeatureSize) << "\n";
        if (stats.trianglesOverTolerance > 0)
            err << "kerf export: warning: " << describeTrianglesOverTolerance(stats, tolerance, ownFeatureSize) << "\n";
        if (const std::string coarse = describeCoarseTolerance(stats, tolerance); !coarse.empty())
            err << "kerf export: warning: " << coarse << "\n";
        if (const std::string miss = describeVisibleMiss(stats, tolerance, ownFeatureSize); !miss.empty())
            err << "kerf export: warning: " << printable(target.string()) << ": " << miss << "\n";

        if (json) {
            nlohmann::ordered_json j;
            j["file"] = file;
            if (const auto feature = a.value("--feature")) j["feature"] = partName;
            j["output"] = target.string();
            j["format"] = describe(*format);
            j["bytes"] = written.bytes;
            j["tolerance_mm"] = tolerance;
            j["tolerance_source"] = toleranceText ? "option" : "default";
            j["feature_size_mm"] = stats.featureSize;
            j["feature_size_source"] = source;
            j["cell_size_mm"] = stats.cellSize;
            if (!stats.note.empty()) j["note"] = stats.note;
            // The mesh as a reader of the file gets it.
            j["triangles"] = report.triangles;
            j["vertices"] = report.vertices;
            j["closed"] = report.closed();
            j["manifold"] = report.manifold();
            j["oriented"] = report.oriented();
            j["degenerate_triangles"] = report.degenerateTriangles;
            j["self_intersections"] = written.selfIntersections;
            j["components"] = report.components;
            j["euler_characteristic"] = report.eulerCharacteristic;
            j["genus"] = report.genus().value_or(-1);
            j["volume_mm3"] = report.volume;
            j["area_mm2"] = report.area;
            j["simplified"] = tolerance > 0.0 && fallback.empty();
            if (!fallback.empty()) j["simplification_defects"] = fallback;
            if (fallback.empty() && tolerance > 0.0) {
                j["worst_sample_mm"] = stats.worstSample;
                if (stats.trianglesOverTolerance > 0)
                    j["worst_sample_at_mm"] = {stats.worstSampleAt.x, stats.worstSampleAt.y, stats.worstSampleAt.z};
            }
            if (fallback.empty() && tolerance > 0.0) {
                j["part_samples"] = stats.partSamples;
                j["part_samples_beyond_tolerance"] = stats.partSamplesBeyond;
                j["part_point_splits"] = stats.partPointSplits;
                if (stats.partSamplesBeyond > 0) {
                    j["worst_part_sample_mm"] = stats.worstPartSample;
                    j["worst_part_sample_at_mm"] = {stats.worstPartSampleAt.x, stats.worstPartSampleAt.y,
                                                    stats.worstPartSampleAt.z};
                }
            }
            j["triangles_over_tolerance"] = stats.trianglesOverTolerance;
            j["area_over_tolerance_mm2"] = stats.areaOverTolerance;
            j["triangles_folded"] = stats.foldedTriangles;
            j["unfolds"] = stats.unfolds;
            j["retriangulations"] = stats.retriangulations;
            if (stats.hiddenDetailCells > 0)
                j["hidden_detail"] = {{"kind", stats.hiddenDetailIsMaterial ? "material" : "gap"},
                                      {"thickness_mm", stats.hiddenDetailThickness},
                                      {"at_mm", {stats.hiddenDetailAt.x, stats.hiddenDetailAt.y, stats.hiddenDetailAt.z}},
                                      {"cells", stats.hiddenDetailCells}};
            // The feature size the warnings advise, where one does (hidden
            // detail, a visible miss; not a few triangles left just over).
            if (const double finer = finerFeatureSize(stats);
                finer > 0.0 && (stats.hiddenDetailCells > 0 || missesVisibly(stats, tolerance)))
                j["finer_feature_size_mm"] = finer;
            j["file_spacing_mm"] = written.spacing;
            j["file_offset_mm"] = {written.offset.x, written.offset.y, written.offset.z};
            j["fit_collapses"] = written.fit.collapses;
            j["fit_nudges"] = written.fit.nudges;
            j["fit_largest_move_mm"] = written.fit.largestMove;
            j["lattice_triangles"] = stats.latticeTriangles;
            j["planar_fans"] = stats.planarFans;
            j["planar_fan_triangles_removed"] = stats.planarFanRemoved;
            j["feature_vertices"] = stats.featureVertices;
            j["zero_corners"] = stats.zeroCorners;
            j["collapses"] = stats.collapses;
            j["splits"] = stats.splits;
            j["seconds"] = seconds;
            j["lattice_seconds"] = stats.seconds - stats.simplifySeconds - stats.refineSeconds - stats.coverageSeconds;
            j["simplify_seconds"] = stats.simplifySeconds;
            j["refine_seconds"] = stats.refineSeconds;
            j["coverage_seconds"] = stats.coverageSeconds;
            j["crossing_checks"] = stats.crossingChecks;
            j["crossing_redos"] = stats.crossingRedos;
            out << j.dump(2) << "\n";
            return 0;
        }
        out << printable(target.string()) << ": " << grouped(report.triangles) << " triangles, " << describe(*format)
            << " (" << fileSize(written.bytes) << "), from " << printable(file)
            << (alone.empty() ? std::string() : " (" + printable(alone) + ")") << "\n";
        if (tolerance == 0.0)
            out << "  tolerance:     none (marching cubes at the feature size)\n";
        else if (fallback.empty())
            out << "  tolerance:     " << mm(tolerance) << " mm" << (toleranceText ? "" : " (default)")
                << "; samples of every triangle within " << significant(stats.worstSample, 2) << " mm\n"
                << "  part's side:   " << describePartSide(stats, tolerance) << "\n";
        else
            out << "  tolerance:     " << mm(tolerance)
                << " mm not reached (plain marching-cubes mesh written, see the warning)\n";
        out << "  feature size:  " << mm(stats.featureSize) << " mm"
            << (requested                  ? ""
                : doc.settings.featureSize ? " (document)"
                                           : " (default: the document sets none)")
            << "\n";
        if (!stats.note.empty()) out << "  note:          " << stats.note << "\n";
        out << "  as read back:  closed, consistently oriented 2-manifold, no degenerate or crossing triangles ("
            << report.components << (report.components == 1 ? " component" : " components") << ", genus "
            << report.genus().value_or(-1) << ", " << grouped(report.vertices) << " vertices)\n";
        out << "  volume:        " << number(report.volume, 1) << " mm^3 (area " << number(report.area, 1)
            << " mm^2)\n";
        out << "  time:          " << number(seconds, 2) << " s (meshing " << number(stats.seconds, 2)
            << " s, checking and writing " << number(meshSeconds - stats.seconds, 2) << " s)\n";
        return 0;
    } catch (const UsageError& e) {
        err << "kerf export: " << e.what() << " (see kerf export --help)\n";
        return 2;
    } catch (const DocumentError& e) {
        err << "kerf export: " << e.what() << "\n";
        return 2;
    } catch (const RefusedRequest& e) {
        err << "kerf export: " << e.what() << "\n";
        return 2;
    } catch (const OutputFileError& e) {
        err << "kerf export: " << e.what() << "\n"; // names the output file
        return 1;
    } catch (const std::exception& e) {
        err << "kerf export: " << (file.empty() ? "" : printable(file) + ": ") << describeFailure(e) << "\n";
        return 1;
    }
}

} // namespace kerf

// kerf export FILE.kerf -o OUT.stl: meshes the part (marching cubes on the
// exact field, kerf_mesher) and writes it as STL, whole or not at all.
// Exit 0 when written; 1 when the part is empty or the export failed
// (nothing is written); 2 for bad usage or a refused document.

#include "kerf/app/Arguments.hpp"
#include "kerf/app/Commands.hpp"
#include "kerf/app/DocumentSummary.hpp"
#include "kerf/app/ExportPreflight.hpp"
#include "kerf/app/Failure.hpp"
#include "kerf/app/Format.hpp"
#include "kerf/document/AtomicFile.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/mesher/StlWriter.hpp"

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

const char* kExportHelp = R"(Usage: kerf export FILE.kerf -o OUT.stl [--feature-size MM] [--ascii] [--json]

Meshes the part with marching cubes on its exact field and writes an STL
file (binary unless --ascii). The file is written whole or not at all. Prints
the triangle count, the time, and whether the mesh is closed (every edge
shared by exactly two consistently oriented triangles).

Options:
  -o, --output OUT.stl   the STL file to write (required)
  --feature-size MM      cell edge in millimetres (default: the document's
                         feature size, else about a thousandth of the part's
                         largest extent)
  --ascii                write ASCII STL instead of binary
  --json                 print the figures as one JSON object
  --help                 show this help

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

// What went wrong with a mesh that is not watertight, in words.
std::string defects(const MeshReport& r)
{
    std::string s;
    auto add = [&](std::size_t n, const char* what) {
        if (!n) return;
        if (!s.empty()) s += ", ";
        s += grouped(n) + " " + what;
    };
    add(r.boundaryEdges, "open edges");
    add(r.nonManifoldEdges, "non-manifold edges");
    add(r.misorientedEdges, "misoriented edges");
    add(r.nonManifoldVertices, "non-manifold vertices");
    add(r.degenerateTriangles, "degenerate triangles");
    if (s.empty() && !(r.volume > 0.0)) s = "triangles face inward";
    return s;
}

} // namespace

int runExport(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
    std::string file;
    try {
        const Arguments a(args, {"-o", "--output", "--feature-size"}, {"--ascii", "--json", "--help", "-h"});
        if (a.has("--help") || a.has("-h")) {
            out << kExportHelp;
            return 0;
        }
        if (a.positional().size() != 1) throw UsageError("expects exactly one FILE.kerf");
        auto output = a.value("-o");
        if (const auto o = a.value("--output")) output = o;
        if (!output || output->empty()) throw UsageError("needs an output file: -o OUT.stl");
        std::optional<double> requested;
        if (const auto v = a.value("--feature-size"))
            requested = Arguments::parseFeatureSize("--feature-size", *v);
        const bool ascii = a.has("--ascii"), json = a.has("--json");
        file = a.positional()[0];
        const std::filesystem::path target = *output;

        const auto start = std::chrono::steady_clock::now();
        const Document doc = Document::load(file);
        const Aabb bounds = partBounds(doc);
        if (bounds.isEmpty()) {
            err << "kerf export: " << printable(file) << ": the part is empty (nothing is visible); nothing to export\n";
            return 1;
        }
        const char* source = requested ? "option" : doc.settings.featureSize ? "document" : "default";
        MeshOptions options;
        options.featureSize = requested.value_or(doc.settings.featureSize.value_or(defaultFeatureSize(bounds)));
        // The output and the machine's budget, before any meshing.
        preflightExport(doc, file, target, options.featureSize);

        const bool terminal = ::isatty(STDERR_FILENO);
        const InterruptGuard guard;
        MeshProgress progress;
        progress.cancelled = [] { return interrupted.load(); };
        int shownPercent = -1;
        if (terminal) {
            progress.onProgress = [&](double fraction) {
                const int percent = int(fraction * 100.0);
                if (percent == shownPercent) return;
                shownPercent = percent;
                err << "\rkerf export: meshing at " << mm(options.featureSize) << " mm... " << percent << "%"
                    << std::flush;
            };
        }
        MeshStats stats;
        const auto meshStart = std::chrono::steady_clock::now();
        std::optional<Mesh> mesh = meshPart(doc, options, progress, &stats);
        const double meshSeconds = since(meshStart);
        if (terminal) err << "\r\033[K" << std::flush;
        if (!mesh) {
            err << "kerf export: " << printable(file) << ": interrupted; " << printable(target.string()) << " not written\n";
            return 1;
        }
        if (mesh->empty()) {
            err << "kerf export: " << printable(file) << ": the part is empty at a feature size of " << mm(stats.cellSize)
                << " mm (thinner than a cell everywhere); nothing to export\n";
            return 1;
        }

        if (terminal) err << "kerf export: checking the mesh..." << std::flush;
        const auto checkStart = std::chrono::steady_clock::now();
        const MeshReport report = checkMesh(*mesh);
        const double checkSeconds = since(checkStart);
        if (terminal) err << "\r\033[K" << std::flush;
        if (!report.watertight()) {
            err << "kerf export: " << printable(file) << ": internal error: the mesh is not watertight ("
                << defects(report) << "); " << printable(target.string()) << " not written\n";
            return 1;
        }

        if (interrupted) {
            err << "kerf export: " << printable(file) << ": interrupted; " << printable(target.string()) << " not written\n";
            return 1;
        }
        // Writing is not interruptible: the file is written whole or, if the
        // process is killed, not at all (only a temporary file beside it remains).
        if (terminal) err << "kerf export: writing " << printable(target.string()) << "..." << std::flush;
        const auto writeStart = std::chrono::steady_clock::now();
        writeStl(*mesh, target, ascii ? StlFormat::Ascii : StlFormat::Binary);
        const double writeSeconds = since(writeStart);
        if (terminal) err << "\r\033[K" << std::flush;
        std::error_code ec;
        const std::uint64_t bytes = std::filesystem::file_size(target, ec);
        const double seconds = since(start);

        if (json) {
            nlohmann::ordered_json j;
            j["file"] = file;
            j["output"] = target.string();
            j["format"] = ascii ? "ascii" : "binary";
            j["bytes"] = bytes;
            j["feature_size_mm"] = stats.featureSize;
            j["feature_size_source"] = source;
            j["cell_size_mm"] = stats.cellSize;
            if (!stats.note.empty()) j["note"] = stats.note;
            j["triangles"] = report.triangles;
            j["vertices"] = report.vertices;
            j["closed"] = report.closed();
            j["manifold"] = report.manifold();
            j["oriented"] = report.oriented();
            j["degenerate_triangles"] = report.degenerateTriangles;
            j["components"] = report.components;
            j["euler_characteristic"] = report.eulerCharacteristic;
            j["genus"] = report.genus().value_or(-1);
            j["volume_mm3"] = report.volume;
            j["area_mm2"] = report.area;
            j["seconds"] = seconds;
            j["mesh_seconds"] = meshSeconds;
            j["check_seconds"] = checkSeconds;
            j["write_seconds"] = writeSeconds;
            out << j.dump(2) << "\n";
            return 0;
        }
        out << printable(target.string()) << ": " << grouped(report.triangles) << " triangles, "
            << (ascii ? "ASCII" : "binary") << " STL (" << megabytes(bytes) << "), from " << printable(file) << "\n";
        out << "  feature size:  " << mm(stats.featureSize) << " mm"
            << (requested                  ? ""
                : doc.settings.featureSize ? " (document)"
                                           : " (default: the document sets none)")
            << "\n";
        if (!stats.note.empty()) out << "  note:          " << stats.note << "\n";
        out << "  mesh:          closed, consistently oriented 2-manifold, no degenerate triangles ("
            << report.components << (report.components == 1 ? " component" : " components") << ", genus "
            << report.genus().value_or(-1) << ", " << grouped(report.vertices) << " vertices)\n";
        out << "  volume:        " << number(report.volume, 1) << " mm^3 (area " << number(report.area, 1)
            << " mm^2)\n";
        out << "  time:          " << number(seconds, 2) << " s (meshing " << number(meshSeconds, 2) << " s, checking "
            << number(checkSeconds, 2) << " s, writing " << number(writeSeconds, 2) << " s)\n";
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

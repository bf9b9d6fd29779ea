// kerf check FILE.kerf: loads and validates a document and reports what it
// holds. Exit 0 when valid, 2 when the file is refused or usage is wrong.

#include "kerf/app/Arguments.hpp"
#include "kerf/app/Commands.hpp"
#include "kerf/app/DocumentSummary.hpp"
#include "kerf/app/Failure.hpp"
#include "kerf/app/Format.hpp"
#include "kerf/app/UnknownFieldWarnings.hpp"
#include "kerf/app/VoxelizeProgress.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/document/UnknownFields.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/RequestBudget.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <unistd.h>
#include <filesystem>
#include <ostream>

namespace kerf {

namespace {

const char* kCheckHelp = R"(Usage: kerf check FILE.kerf [--json] [-D NAME=VALUE]...

Loads and validates a Kerf document. Prints the feature count, the bounding
box, and the voxel memory the viewport needs at the document's feature size:
measured (the part is voxelized) when that takes seconds, else estimated
from a coarse voxelization, with the feature size this machine could build.
Lists the document's parameters with their expressions and values.

Options:
  --json           print the figures as one JSON object
  -D NAME=VALUE    set the document's parameter NAME (a number or an
                   expression, like 19 or 3/4in) for this check; repeatable
  --help           show this help

A tool that cuts nothing (a hole moved clear of its board) is named in a
warning on stderr too. Fields Kerf does not know are kept when the document is saved, but the part
goes without them: each is named in a warning on stderr, with the field it is
probably a misspelling of.

Exit status: 0 valid, 2 bad usage or a refused document (the reason, naming
the file, the node id and the field, goes to stderr).
)";

std::string point(const glm::dvec3& p) { return "(" + mm(p.x) + ", " + mm(p.y) + ", " + mm(p.z) + ")"; }

} // namespace

int runCheck(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
    try {
        const Arguments a(args, {"-D"}, {"--json", "--help", "-h"});
        if (a.has("--help") || a.has("-h")) {
            out << kCheckHelp;
            return 0;
        }
        if (a.positional().size() != 1) throw UsageError("expects exactly one FILE.kerf");
        const std::filesystem::path file = a.positional()[0];
        const Document doc = Document::load(file, a.defines());
        warnOfUnknownFields(doc, "kerf check", err);
        // A hole moved off its board is valid, and missing from the part.
        if (const std::string idle = describeToolsCuttingNothing(doc); !idle.empty())
            err << "kerf check: warning: " << idle << "\n";
        const std::vector<UnknownField> unknown = unknownFields(doc);
        const DocumentSummary s = summarize(doc, file.parent_path().string());

        // The viewport's voxel memory: estimated first (a coarse voxelization
        // of the surface), then measured when building it takes seconds and
        // fits the machine. A feature size far too fine for the part (2 um on
        // a 2 m panel) would take hours and terabytes.
        const Tape tape = compileTape(doc);
        const GridLayout layout = GridLayout::choose(tape.bounds(), s.featureSize);
        const auto t0 = std::chrono::steady_clock::now();
        VoxelEstimate estimate;
        const RequestCost cost = estimateRequest(tape, s.featureSize, RequestKind::Voxels, 0.0, &estimate);
        const std::optional<std::string> tooLarge = overBudget(cost, RequestBudget::forThisMachine(), s.featureSize);
        constexpr double kMaxCheckSeconds = 10.0; // check answers in seconds; the viewport builds the rest
        const bool built = estimate.exact || (!tooLarge && cost.seconds <= kMaxCheckSeconds);
        if (built && !estimate.exact && ::isatty(STDERR_FILENO))
            err << "kerf check: voxelizing at " << mm(layout.voxelSize) << " mm...\n";
        const VoxelSnapshot voxels = estimate.snapshot ? std::move(*estimate.snapshot)
                                     : built ? voxelizeWithProgress(tape, layout, "kerf check", cost.seconds > 2.0, err)
                                             : VoxelSnapshot{};
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

        if (a.has("--json")) {
            nlohmann::ordered_json j;
            j["file"] = file.string();
            j["valid"] = true;
            j["name"] = doc.name.value_or("");
            j["nodes"] = s.nodes;
            j["visible_nodes"] = s.visibleNodes;
            j["primitives"] = s.primitives;
            j["primitive_copies"] = s.primitiveCopies;
            j["tape_instructions"] = s.tapeLength;
            j["empty"] = s.bounds.isEmpty();
            if (!s.bounds.isEmpty()) {
                j["bounds_mm"] = {{s.bounds.min.x, s.bounds.min.y, s.bounds.min.z},
                                  {s.bounds.max.x, s.bounds.max.y, s.bounds.max.z}};
                j["size_mm"] = {s.bounds.size().x, s.bounds.size().y, s.bounds.size().z};
            }
            j["feature_size_mm"] = s.featureSize;
            j["feature_size_from_document"] = s.featureSizeFromDocument;
            j["voxel_bytes"] = built ? double(voxels.bytes()) : estimate.bytes;
            j["populated_voxels"] = built ? double(voxels.populatedVoxels()) : estimate.populatedVoxels;
            j["voxel_memory_estimated"] = !built;
            if (!built) j["voxelize_seconds_estimated"] = cost.seconds;
            if (tooLarge) j["too_large"] = *tooLarge;
            j["voxel_size_mm"] = layout.voxelSize;
            j["tiles"] = {layout.dims.x, layout.dims.y, layout.dims.z};
            j["contree_levels"] = layout.levels;
            j["voxelize_seconds"] = seconds;
            if (!layout.note.empty()) j["note"] = layout.note;
            j["parameters"] = nlohmann::ordered_json::array();
            for (const Parameter& p : doc.parameters) {
                nlohmann::ordered_json pj;
                pj["name"] = p.name;
                pj["expression"] = p.expression;
                pj["value"] = p.value;
                if (p.unit) pj["unit"] = *p.unit;
                if (p.comment) pj["comment"] = *p.comment;
                j["parameters"].push_back(std::move(pj));
            }
            j["unknown_fields"] = nlohmann::ordered_json::array();
            for (const UnknownField& u : unknown) {
                nlohmann::ordered_json uj;
                uj["owner"] = u.owner == UnknownField::Owner::Feature ? "feature"
                              : u.owner == UnknownField::Owner::Mesh  ? "mesh"
                                                                      : "document";
                if (!u.id.empty()) uj["id"] = u.id;
                uj["field"] = u.field;
                if (!u.suggestion.empty()) uj["did_you_mean"] = u.suggestion;
                j["unknown_fields"].push_back(std::move(uj));
            }
            j["tools_cutting_nothing"] = toolsCuttingNothing(doc);
            j["meshes"] = s.meshes;
            j["missing_meshes"] = s.missingMeshes;
            out << j.dump(2) << "\n";
            return 0;
        }

        out << printable(file.string()) << ": valid Kerf document"
            << (doc.name ? " \"" + printable(*doc.name) + "\"" : "") << "\n";
        out << "  features:      " << s.nodes << " nodes (" << s.visibleNodes << " visible, " << s.primitives
            << " primitives, " << s.primitiveCopies << " primitive copies after arrays and mirrors)\n";
        if (s.bounds.isEmpty()) {
            out << "  bounding box:  none (the part is empty: nothing visible)\n";
        } else {
            const glm::dvec3 e = s.bounds.size();
            out << "  bounding box:  " << point(s.bounds.min) << " to " << point(s.bounds.max) << " mm\n";
            out << "  size:          " << mm(e.x) << " x " << mm(e.y) << " x " << mm(e.z) << " mm\n";
        }
        out << "  feature size:  " << mm(s.featureSize) << " mm"
            << (s.featureSizeFromDocument ? " (document)" : " (default: the document sets none)") << "\n";
        out << "  tape:          " << s.tapeLength << " instructions\n";
        if (!doc.parameters.empty()) {
            out << "  parameters:    " << doc.parameters.size() << "\n";
            for (const Parameter& p : doc.parameters) {
                const std::string unit = p.unit == "length" ? " mm" : p.unit == "angle" ? " deg" : "";
                out << "    " << printable(p.name) << " = " << mm(p.value) << unit;
                if (p.expression != mm(p.value)) out << "  (" << printable(p.expression) << ")";
                if (p.comment) out << "  " << printable(*p.comment);
                out << "\n";
            }
        }
        char mib[64];
        if (built) {
            std::snprintf(mib, sizeof mib, "%.1f MiB", double(voxels.bytes()) / (1024.0 * 1024.0));
            out << "  voxel memory:  " << mib << " (" << voxels.populatedVoxels() << " populated voxels of "
                << mm(layout.voxelSize) << " mm; " << layout.dims.x << " x " << layout.dims.y << " x "
                << layout.dims.z << " tiles, " << layout.levels << " levels; voxelized in " << mm(seconds) << " s)\n";
        } else {
            // Readable at any size ("about 3.2 GB", "more than 1000 EB").
            const std::string bytes = describeBytes(estimate.bytes);
            out << "  voxel memory:  " << (bytes.rfind("more", 0) == 0 ? bytes : "about " + bytes) << " (about "
                << describeCount(estimate.populatedVoxels)
                << " populated voxels of " << mm(layout.voxelSize) << " mm, estimated from a coarse voxelization in "
                << mm(seconds) << " s; ";
            if (tooLarge)
                out << "too large to build: " << *tooLarge << ")\n";
            else
                out << "building them would take about " << describeSeconds(cost.seconds)
                    << ", so kerf check only estimates; the viewport builds what the view needs)\n";
        }
        if (!layout.note.empty()) out << "  note:          " << layout.note << "\n";
        if (s.meshes) {
            out << "  meshes:        " << s.meshes << " reference mesh(es)";
            if (s.missingMeshes) out << ", " << s.missingMeshes << " missing on disk";
            out << "\n";
        }
        return 0;
    } catch (const UsageError& e) {
        err << "kerf check: " << e.what() << " (see kerf check --help)\n";
        return 2;
    } catch (const DocumentError& e) {
        err << "kerf check: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        err << "kerf check: " << describeFailure(e) << "\n";
        return 1;
    }
}

} // namespace kerf

#include "kerf/app/ExportPreflight.hpp"

#include "kerf/app/Arguments.hpp"
#include "kerf/document/AtomicFile.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshPart.hpp"

namespace kerf {

RequestCost preflightExport(const Document& doc, const std::string& file, const std::filesystem::path& target,
                            double featureSize, double tolerance)
{
    try {
        checkOutputFile(target);
    } catch (const OutputFileError& e) {
        throw RefusedRequest(e.what());
    }
    const Tape tape = compileTape(doc);
    // Longer than the mesher's lattice holds: refused as a request, with
    // what fits (it was an exit 1 after the estimate, "too large to mesh at
    // a feature size of 1.000000 mm").
    if (const auto why = partTooLongToMesh(tape.bounds(), featureSize))
        throw RefusedRequest(printable(file, 400) + ": " + *why);
    const RequestCost cost = estimateRequest(tape, featureSize, meshRequestKind(tolerance));
    if (const auto over = overBudget(cost, RequestBudget::forThisMachine(), featureSize))
        throw RefusedRequest(printable(file, 400) + ": meshing at " + *over);
    return cost;
}

} // namespace kerf

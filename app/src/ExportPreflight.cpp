#include "kerf/app/ExportPreflight.hpp"

#include "kerf/app/Arguments.hpp"
#include "kerf/document/AtomicFile.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

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
    const RequestCost cost = estimateRequest(tape, featureSize, meshRequestKind(tolerance));
    if (const auto over = overBudget(cost, RequestBudget::forThisMachine(), featureSize))
        throw RefusedRequest(printable(file, 400) + ": meshing at " + *over);
    return cost;
}

} // namespace kerf

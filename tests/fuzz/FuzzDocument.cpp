// What the fuzzer does with one input (tests/fuzz/DocumentFuzzer.cpp), shared
// with the test suite, which runs it on every file in tests/fuzz/seeds (the
// seeds and every finding's reproducer): a document's bytes, then everything
// `kerf check` and the desktop application do with a document that loads.
// Besides what the sanitizers catch, a finding is: a refusal that is not one
// line, a loaded document that does not load again equal from its own
// serialization, a NaN in the field, or a point value outside the interval
// of its box.

#include "FuzzDocument.hpp"

#include "kerf/document/Document.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/evaluator/CutList.hpp"
#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace kerf::fuzz {

namespace {

struct Finding {
    std::string what;
};

[[noreturn]] void finding(const char* what) { throw Finding{what}; }

void exercise(const Document& doc)
{
    // A loaded document saves and loads again unchanged.
    const Document again = Document::parse(doc.serialize(), "again.kerf");
    if (!(again == doc)) finding("a document does not round-trip through its own serialization");

    const Aabb bounds = partBounds(doc);
    (void)worldBoundsOfNodes(doc);
    const Tape tape = compileTape(doc);
    if (tape.empty() || bounds.isEmpty() || !bounds.isBounded()) return;

    // Points: the centre and the corners of the bounds, in double and float,
    // with gradients; each inside the interval of the whole box.
    PointEvaluator<double> pd;
    PointEvaluator<float> pf;
    GradientEvaluator<double> gd;
    IntervalEvaluator intervals;
    const Interval whole = intervals.evaluate(tape, bounds);
    for (int k = 0; k < 9; ++k) {
        const glm::dvec3 p = k == 8 ? bounds.center()
                                    : glm::dvec3(k & 1 ? bounds.max.x : bounds.min.x, k & 2 ? bounds.max.y : bounds.min.y,
                                                 k & 4 ? bounds.max.z : bounds.min.z);
        const double d = pd.evaluate(tape, p.x, p.y, p.z);
        (void)pf.evaluate(tape, float(p.x), float(p.y), float(p.z));
        (void)gd.evaluate(tape, p.x, p.y, p.z);
        if (std::isnan(d)) finding("the field is NaN at a point of the bounds");
        const double slack = 1e-6 * (1.0 + std::fabs(d));
        if (d < whole.lo - slack || d > whole.hi + slack) finding("a point value lies outside the interval of its box");
    }

    // The cut list (tight bounds of every body).
    (void)cutList(doc, 0.5);

    // One coarse voxelization: at most 8 tiles of 2 levels, on this thread.
    const glm::dvec3 e = bounds.size();
    const double coarse = std::max({e.x, e.y, e.z, 1e-3}) / 24.0;
    const GridLayout layout = GridLayout::choose(bounds, coarse, {.maxTiles = 8, .maxLevels = 2, .minLevels = 2});
    TileBuildScratch scratch;
    for (long i = 0; i < layout.tileCount(); ++i) (void)buildTile(tape, layout, layout.tileCoord(i), layout.levels, scratch);
}

} // namespace

std::optional<std::string> fuzzDocument(std::string_view bytes)
{
    try {
        Document doc;
        try {
            doc = Document::parse(bytes, "fuzz.kerf");
        } catch (const DocumentError& e) {
            for (const char* c = e.what(); *c; ++c)
                if (static_cast<unsigned char>(*c) < 0x20) finding("a refusal message holds a control character");
            return std::nullopt;
        }
        exercise(doc);
    } catch (const Finding& f) {
        return f.what;
    }
    return std::nullopt;
}

} // namespace kerf::fuzz

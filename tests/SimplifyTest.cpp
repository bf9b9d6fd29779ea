// Tape simplification: inside its box a simplified tape gives exactly the
// full tape's values (and features), and on deep boxes it is much shorter.

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

namespace kerf {
namespace {

TEST(Simplify, AgreesWithTheFullTapeInsideItsBox)
{
    test::RandomShapes r(9);
    IntervalEvaluator intervals;
    PointEvaluator<double> points;
    std::size_t fullLength = 0, simplifiedLength = 0;
    for (int t = 0; t < 200; ++t) {
        const Tape tape = compileTape(r.tree(4));
        for (int b = 0; b < 20; ++b) {
            const double size = std::pow(10.0, r.uniform(-1.0, 1.5));
            const glm::dvec3 lo = r.vec(-40.0, 40.0);
            const Aabb box{lo, lo + glm::dvec3(size)};
            Tape simple;
            const Interval iv = intervals.simplify(tape, box, simple);
            const Interval direct = intervals.evaluate(tape, box);
            EXPECT_EQ(iv.lo, direct.lo);
            EXPECT_EQ(iv.hi, direct.hi);
            ASSERT_LE(simple.size(), tape.size());
            fullLength += tape.size();
            simplifiedLength += simple.size();
            for (int i = 0; i < 25; ++i) {
                const glm::dvec3 p = lo + glm::dvec3(size) * r.vec(0.0, 1.0);
                std::uint32_t fa = 0, fb = 0;
                const double a = points.evaluate(tape, p.x, p.y, p.z, &fa);
                const double s = points.evaluate(simple, p.x, p.y, p.z, &fb);
                ASSERT_EQ(a, s) << "tree " << t << " box " << b;
                ASSERT_EQ(fa, fb);
            }
        }
    }
    EXPECT_LT(simplifiedLength, fullLength * 3 / 4) << "simplification should drop branches on small boxes";
}

TEST(Simplify, KeepsOnlyTheNearbyCopyOfAnArray)
{
    Node s = makeNode(NodeType::Sphere, "s");
    s.params = SphereParams{4.0};
    Node a = makeNode(NodeType::Array, "a");
    a.params = ArrayParams{{8, 8, 8}, {20, 20, 20}};
    a.children = {s};
    const Tape tape = compileTape(a);
    EXPECT_EQ(tape.size(), 2u * 512u - 1u);
    IntervalEvaluator intervals;
    Tape simple;
    const Interval iv = intervals.simplify(tape, Aabb{{58, 58, 58}, {62, 62, 62}}, simple);
    EXPECT_LT(iv.lo, 0.0);
    EXPECT_EQ(simple.size(), 1u);
    EXPECT_EQ(simple.shapes().front().worldBounds.center(), glm::dvec3(60, 60, 60));
}

TEST(Simplify, SmoothUnionKeepsBothSidesOnlyWithinTheBlend)
{
    Document d = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","blend":2,
      "children":[{"id":"a","type":"sphere","radius":5},
                  {"id":"b","type":"sphere","radius":5,"transform":{"translate":[20,0,0]}}]}})",
                                 "t");
    const Tape tape = compileTape(d);
    IntervalEvaluator intervals;
    Tape simple;
    intervals.simplify(tape, Aabb{{-6, -1, -1}, {-4, 1, 1}}, simple); // far from b
    EXPECT_EQ(simple.size(), 1u);
    intervals.simplify(tape, Aabb{{9, -1, -1}, {11, 1, 1}}, simple); // between them, within reach of both
    EXPECT_EQ(simple.size(), 3u);
}

} // namespace
} // namespace kerf

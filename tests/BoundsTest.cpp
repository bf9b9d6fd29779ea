// Node bounds are conservative: every point where a field is below the
// margin lies inside the bounds of {f < margin}, for random trees of every
// node type, blends, offsets, arrays and mirrors included.

#include "kerf/document/NodeBounds.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

namespace kerf {
namespace {

TEST(Bounds, ContainEveryPointBelowTheMargin)
{
    test::RandomShapes r(21);
    PointEvaluator<double> points;
    long inside = 0;
    for (int t = 0; t < 300; ++t) {
        const Node root = r.tree(3);
        const Tape tape = compileTape(root);
        for (double margin : {0.0, 2.0}) {
            const Aabb b = nodeBounds(root, margin);
            if (b.isEmpty()) continue;
            // Sample around the bounds, well past them on every side.
            const Aabb around = b.grown(10.0 + 0.5 * std::max({b.size().x, b.size().y, b.size().z}));
            for (int i = 0; i < 2000; ++i) {
                const glm::dvec3 p = around.min + around.size() * r.vec(0.0, 1.0);
                if (points.evaluate(tape, p.x, p.y, p.z) < margin) {
                    ++inside;
                    ASSERT_TRUE(b.contains(p)) << "tree " << t << " margin " << margin;
                }
            }
        }
    }
    EXPECT_GT(inside, 5000); // the property was exercised
}

TEST(Bounds, ArraysSweepAndMirrorsReflect)
{
    Document d = Document::parse(R"({"format":"kerf","version":1,"root":
      {"id":"m","type":"mirror","normal":[1,0,0],"children":[
        {"id":"a","type":"array","count":[3,1,2],"step":[10,0,-20],"transform":{"translate":[5,0,0]},"children":[
          {"id":"s","type":"sphere","radius":1}]}]}})",
                                 "t");
    const Aabb b = partBounds(d);
    EXPECT_EQ(b.min, glm::dvec3(-26, -1, -21));
    EXPECT_EQ(b.max, glm::dvec3(26, 1, 1));
    const auto all = worldBoundsOfNodes(d);
    // The sphere node's bounds cover all 12 of its instances.
    EXPECT_EQ(all.at("s").min, glm::dvec3(-26, -1, -21));
    EXPECT_EQ(all.at("a").max, glm::dvec3(26, 1, 1));
}

TEST(Bounds, BlendsGrowTheUnionByAQuarterOfTheRadius)
{
    Document d = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","blend":8,
      "children":[{"id":"a","type":"box","size":[2,2,2]},{"id":"b","type":"box","size":[2,2,2]}]}})",
                                 "t");
    EXPECT_EQ(partBounds(d).max, glm::dvec3(3, 3, 3));
}

} // namespace
} // namespace kerf

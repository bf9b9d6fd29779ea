// Node bounds are conservative: every point where a field is below the
// margin lies inside the bounds of {f < margin}, for random trees of every
// node type, blends, offsets, arrays and mirrors included.

#include "kerf/document/NodeBounds.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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

// A dowel hole moved off its board (a newcomer set its Y to 100 on a board
// 60 deep): it cuts nothing, and the part and its file lacked it without a
// word. Found by bounds, so for certain: a hole touching or entering the
// board, a hidden hole and a blended difference are not named.
TEST(Bounds, AToolClearOfItsBoardCutsNothing)
{
    const auto idle = [](const std::string& holeAt, const std::string& extra = "") {
        return toolsCuttingNothing(Document::parse(
            R"({"format":"kerf","version":1,"root":{"id":"d","type":"difference")" + extra + R"(,"children":[
              {"id":"board","type":"box","size":[400,60,20],"name":"Rail"},
              {"id":"hole","type":"cylinder","radius":4,"height":25,"transform":{"translate":[)" + holeAt + R"(]}},
              {"id":"pins","type":"array","count":[3,1,1],"step":[100,0,0],"children":[
                {"id":"pin","type":"cylinder","radius":2.5,"height":10,"transform":{"translate":[-100,0,0]}}]}]}})",
            "t"));
    };
    EXPECT_TRUE(idle("0,0,0").empty());
    EXPECT_EQ(idle("0,100,0"), std::vector<std::string>{"hole"});
    EXPECT_TRUE(idle("0,34,0").empty()); // its side 4 mm into the board
    EXPECT_TRUE(idle("0,100,0", R"(,"blend":2)").empty());
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"d","type":"difference","children":[
              {"id":"board","type":"box","size":[400,60,20],"name":"Rail"},
              {"id":"hole","type":"cylinder","radius":4,"height":25,"transform":{"translate":[0,100,0]}},
              {"id":"hidden","type":"cylinder","radius":4,"height":25,"visible":false,"transform":{"translate":[0,100,0]}}]}})",
                                         "t");
    EXPECT_EQ(toolsCuttingNothing(doc), std::vector<std::string>{"hole"});
    EXPECT_EQ(describeToolsCuttingNothing(doc), "the cylinder 'hole' cuts nothing: it lies clear of Rail ('board')");
}

} // namespace
} // namespace kerf

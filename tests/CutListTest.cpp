// Tight bounds (evaluator/TightBounds.hpp) and the cut list built on them
// (evaluator/CutList.hpp): dimensions a person would measure, within the
// stated tolerance, in each body's own frame.

#include "kerf/document/Affine.hpp"
#include "kerf/evaluator/CutList.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/evaluator/TightBounds.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>

namespace kerf {
namespace {

Document parse(const std::string& root, const std::string& settings = "")
{
    return Document::parse(R"({"format":"kerf","version":1,)" + settings + R"("root":)" + root + "}", "test.kerf");
}

TEST(TightBounds, AxisAlignedBoxIsExactToTheTolerance)
{
    const Tape tape = compileTape(parse(R"({"id":"b","type":"box","size":[450,300,18],"round":3,
        "transform":{"translate":[10,-20,5]}})"));
    const auto tb = tightBounds(tape, 1e-4);
    ASSERT_TRUE(tb);
    EXPECT_LE(tb->uncertainty(), 1e-4);
    const glm::dvec3 lo(10 - 225, -20 - 150, 5 - 9), hi(10 + 225, -20 + 150, 5 + 9);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(tb->outer.min[a], lo[a], 1e-4);
        EXPECT_NEAR(tb->outer.max[a], hi[a], 1e-4);
        EXPECT_LE(tb->outer.min[a], lo[a] + 1e-12) << "outer bounds must enclose";
        EXPECT_GE(tb->outer.max[a], hi[a] - 1e-12);
        EXPECT_LE(tb->outer.min[a], tb->inner.min[a]);
        EXPECT_GE(tb->outer.max[a], tb->inner.max[a]);
    }
}

TEST(TightBounds, RotatedCylinderMatchesItsClosedForm)
{
    // A cylinder of radius r, height h, tilted by 30 degrees about X: its
    // extent along Y is h sin 30 + 2 r cos 30, along Z h cos 30 + 2 r sin 30.
    const double r = 15, h = 400;
    const Tape tape = compileTape(parse(R"({"id":"leg","type":"cylinder","radius":15,"height":400,
        "transform":{"rotate":[30,0,0]}})"));
    const auto tb = tightBounds(tape, 1e-3);
    ASSERT_TRUE(tb);
    const double s = 0.5, c = std::sqrt(3.0) / 2.0;
    EXPECT_NEAR(tb->outer.size().x, 2 * r, 2e-3);
    EXPECT_NEAR(tb->outer.size().y, h * s + 2 * r * c, 2e-3);
    EXPECT_NEAR(tb->outer.size().z, h * c + 2 * r * s, 2e-3);
}

TEST(TightBounds, OuterBoundsEncloseEverySolidSampleOfRandomParts)
{
    // Property: no solid point lies outside `outer`, and inner faces are
    // reached by solid points (sampled densely near each face).
    test::RandomShapes rs(20261123);
    PointEvaluator<double> eval;
    for (int i = 0; i < 8; ++i) {
        Document doc;
        doc.root = rs.tree(2);
        const Tape tape = compileTape(doc);
        if (tape.empty() || tape.bounds().isEmpty()) continue;
        const auto tb = tightBounds(tape, 1e-3);
        if (!tb) continue;
        const Aabb box = tape.bounds();
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int k = 0; k < 5000; ++k) {
            const glm::dvec3 p = box.min + box.size() * glm::dvec3(u(rs.engine()), u(rs.engine()), u(rs.engine()));
            const glm::dvec3 q = p - tape.origin();
            if (eval.evaluate(tape, q.x, q.y, q.z) > 0.0) continue;
            for (int a = 0; a < 3; ++a) {
                ASSERT_GE(p[a], tb->outer.min[a] - 1e-9) << "part " << i;
                ASSERT_LE(p[a], tb->outer.max[a] + 1e-9) << "part " << i;
            }
        }
    }
}

TEST(TightBounds, EmptySolidHasNoBoundsAndUnboundedIsRefused)
{
    const Tape empty = compileTape(parse(R"({"id":"i","type":"intersection","children":[
        {"id":"a","type":"sphere","radius":5},
        {"id":"b","type":"sphere","radius":5,"transform":{"translate":[20,0,0]}}]})"));
    EXPECT_FALSE(tightBounds(empty).has_value());
    const Tape half = compileTape(parse(R"({"id":"h","type":"halfspace","normal":[0,0,1],"offset":0})",
                                        R"("settings":{"bounds":[[-1,-1,-1],[1,1,1]]},)"));
    EXPECT_TRUE(tightBounds(half).has_value()); // bounded by settings.bounds
    Node lone = makeNode(NodeType::Halfspace, "h");
    EXPECT_THROW(tightBounds(compileTape(lone)), std::invalid_argument);
}

TEST(Affine, TransformFromAffineInvertsFromTransform)
{
    test::RandomShapes rs(7);
    for (int i = 0; i < 1000; ++i) {
        Transform t;
        t.translate = rs.vec(-500, 500);
        t.rotate = rs.vec(-180, 180);
        if (i % 10 == 0) t.rotate.y = 90.0; // gimbal lock
        const Affine a = Affine::fromTransform(t);
        const Affine b = Affine::fromTransform(transformFromAffine(a));
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) ASSERT_NEAR(a.linear[c][r], b.linear[c][r], 1e-12) << i;
        ASSERT_EQ(a.translation, b.translation);
    }
    // Axis-aligned placements survive exactly.
    Transform q;
    q.rotate = {90, 0, -90};
    const Transform back = transformFromAffine(Affine::fromTransform(q));
    EXPECT_EQ(back.rotate, q.rotate);
}

TEST(CutList, BodiesOfAssembliesInTheirOwnFrames)
{
    // A union of a panel with two holes (a difference), a splayed leg (rotated
    // 10 degrees) and a mirrored pair of rails, all clipped by a floor.
    const Document doc = parse(R"({"id":"root","type":"intersection","children":[
        {"id":"parts","type":"union","children":[
            {"id":"side","type":"difference","name":"Side, with holes","children":[
                {"id":"panel","type":"box","size":[18,300,720],"transform":{"translate":[0,0,400]}},
                {"id":"holes","type":"array","count":[1,2,1],"step":[0,100,0],
                 "children":[{"id":"hole","type":"cylinder","radius":2.5,"height":40,
                              "transform":{"rotate":[0,90,0],"translate":[0,-50,300]}}]}]},
            {"id":"leg","type":"box","size":[40,40,500],"name":"Leg",
             "transform":{"translate":[300,0,240],"rotate":[10,0,0]}},
            {"id":"rails","type":"mirror","normal":[1,0,0],"offset":0,"children":[
                {"id":"rail","type":"box","size":[20,60,600],"transform":{"translate":[200,0,400],"rotate":[0,90,0]}}]}]},
        {"id":"floor","type":"halfspace","normal":[0,0,-1],"offset":0}]})");
    const auto rows = cutList(doc);
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_EQ(rows[0].nodeId, "panel");
    EXPECT_EQ(rows[0].name, "Side, with holes"); // the unnamed panel takes its difference's name
    EXPECT_EQ(rows[0].quantity, 1);
    EXPECT_NEAR(rows[0].length, 720, 2e-3);
    EXPECT_NEAR(rows[0].width, 300, 2e-3);
    EXPECT_NEAR(rows[0].thickness, 18, 2e-3);
    // The leg is measured along its own axes: the floor (z >= 0 in the
    // world) cuts its lower end, tilted; its stock is 40 x 40 x full height
    // of what remains along its axis.
    EXPECT_EQ(rows[1].name, "Leg");
    EXPECT_NEAR(rows[1].width, 40, 2e-3);
    EXPECT_NEAR(rows[1].thickness, 40, 2e-3);
    EXPECT_LT(rows[1].length, 500.0);
    EXPECT_GT(rows[1].length, 480.0);
    EXPECT_EQ(rows[2].nodeId, "rail");
    EXPECT_EQ(rows[2].quantity, 2);
    EXPECT_NEAR(rows[2].length, 600, 2e-3);
    EXPECT_NEAR(rows[2].width, 60, 2e-3);
    EXPECT_NEAR(rows[2].thickness, 20, 2e-3);
    for (const auto& r : rows) EXPECT_LE(r.uncertainty, 1e-2) << r.nodeId;
}

TEST(CutList, AnUnnamedBodyTakesTheNameOfTheBoardItIsMadeOf)
{
    // A newcomer rounded a shelf side by an offset of the drilled board: the
    // cut list said "offset", the node's id, where the board was "Side".
    const Document doc = parse(R"({"id":"root","type":"union","children":[
        {"id":"offset","type":"offset","distance":1,"children":[
            {"id":"d","type":"difference","children":[
                {"id":"board","type":"box","name":"Side","size":[18,300,720]},
                {"id":"hole","type":"cylinder","name":"Pin hole","radius":2.5,"height":40}]}]},
        {"id":"shell","type":"shell","thickness":2,"children":[
            {"id":"block","type":"box","size":[50,50,50],"transform":{"translate":[200,0,0]}}]}]})");
    const auto rows = cutList(doc);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].nodeId, "offset");
    EXPECT_EQ(rows[0].name, "Side");
    EXPECT_EQ(rows[1].name, "shell"); // nothing named on the way down: the id
}

TEST(CutList, TenonsAreCutFromTheirRailsStock)
{
    // A newcomer's rail: an extruded rail 400 long, 60 wide, 22 thick, with
    // a 30 mm tenon on each end (8 thick, 50 wide), rotated into place. The
    // cut list gave the rail and each tenon as stock of its own.
    const Document doc = parse(R"({"id":"root","type":"union","children":[
        {"id":"railbody","type":"union","transform":{"translate":[100,50,300],"rotate":[0,0,30]},"children":[
            {"id":"rail","type":"box","name":"Rail","size":[400,60,22]},
            {"id":"tl","type":"box","name":"Tenon L","size":[30,50,8],"transform":{"translate":[-215,0,0]}},
            {"id":"tr","type":"box","name":"Tenon R","size":[30,50,8],"transform":{"translate":[215,0,0]}}]},
        {"id":"leg","type":"box","name":"Leg","size":[40,40,700],"transform":{"translate":[-140,0,350]}},
        {"id":"apron","type":"box","name":"Apron","size":[300,20,80],"transform":{"translate":[30,0,600]}},
        {"id":"dowel","type":"cylinder","name":"Dowel","radius":4,"height":30,
         "transform":{"translate":[-140,0,705]}},
        {"id":"side","type":"difference","name":"Side","children":[
            {"id":"panel","type":"box","size":[18,300,600],"transform":{"translate":[500,0,300]}},
            {"id":"housing","type":"box","size":[6,310,18],"transform":{"translate":[506,0,300]}}]},
        {"id":"shelf","type":"box","name":"Shelf","size":[400,300,18],"transform":{"translate":[703,0,300]}}]})");
    const auto rows = cutList(doc);
    std::vector<std::string> names;
    for (const auto& r : rows) names.push_back(r.name);
    ASSERT_EQ(names, (std::vector<std::string>{"Rail", "Leg", "Apron", "Dowel", "Side", "Shelf"}));
    // The rail's stock is 460 long: the tenons are cut from it.
    EXPECT_NEAR(rows[0].length, 460, 2e-2);
    EXPECT_NEAR(rows[0].width, 60, 2e-2);
    EXPECT_NEAR(rows[0].thickness, 22, 2e-2);
    EXPECT_EQ(rows[0].joined, (std::vector<std::string>{"Tenon L", "Tenon R"}));
    EXPECT_EQ(cutListName(rows[0]), "Rail (with its tenons: Tenon L, Tenon R)");
    // The apron butts against the leg, the dowel stands in the leg's end (too
    // thin for its width), the shelf sits in the side's housing: each is
    // stock of its own, and none lengthens another.
    EXPECT_NEAR(rows[1].length, 700, 2e-2);
    EXPECT_NEAR(rows[2].length, 300, 2e-2);
    EXPECT_NEAR(rows[3].length, 30, 2e-2);
    EXPECT_NEAR(rows[4].length, 600, 2e-2);
    EXPECT_NEAR(rows[5].length, 400, 2e-2);
    for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_TRUE(rows[i].joined.empty()) << rows[i].name;
    EXPECT_NE(cutListCsv(rows).find("\"Rail (with its tenons: Tenon L, Tenon R)\",rail,1,460.00,60.00,22.00\r\n"),
              std::string::npos);
}

TEST(CutList, ATenonOfAnArrayedRailJoinsEachCopysStock)
{
    // Three rails, each with its tenon, made by an array of the union: the
    // quantity is 3, the stock the rail's with its tenon.
    const Document doc = parse(R"({"id":"rails","type":"array","count":[1,3,1],"step":[0,100,0],"children":[
        {"id":"u","type":"union","children":[
            {"id":"rail","type":"box","name":"Rail","size":[400,60,22]},
            {"id":"t","type":"box","name":"Tenon","size":[25,50,8],"transform":{"translate":[212.5,0,0]}}]}]})");
    const auto rows = cutList(doc);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].quantity, 3);
    EXPECT_NEAR(rows[0].length, 425, 2e-2);
    EXPECT_EQ(rows[0].joined, std::vector<std::string>{"Tenon"});
}

TEST(CutList, CsvQuotesAndUsesCrLf)
{
    std::vector<CutListRow> rows(2);
    rows[0].name = "Side, left";
    rows[0].nodeId = "side";
    rows[0].quantity = 2;
    rows[0].length = 720;
    rows[0].width = 300.004;
    rows[0].thickness = 18;
    rows[1].name = "Floor \"plane\"";
    rows[1].nodeId = "floor";
    rows[1].unbounded = true;
    EXPECT_EQ(cutListCsv(rows), "Part,Id,Quantity,Length (mm),Width (mm),Thickness (mm)\r\n"
                                "\"Side, left\",side,2,720.00,300.00,18.00\r\n"
                                "\"Floor \"\"plane\"\"\",floor,1,unbounded,unbounded,unbounded\r\n");
    // Lengths shown in inches: decimal inches, the unit in the header.
    EXPECT_EQ(cutListCsv(rows, LengthUnit::Inches), "Part,Id,Quantity,Length (in),Width (in),Thickness (in)\r\n"
                                                    "\"Side, left\",side,2,28.3465,11.8112,0.7087\r\n"
                                                    "\"Floor \"\"plane\"\"\",floor,1,unbounded,unbounded,unbounded\r\n");
}

TEST(CutList, BundledChairListsItsParts)
{
    const Document doc = Document::load(std::string(KERF_EXAMPLES_DIR) + "/side-chair.kerf");
    const auto rows = cutList(doc);
    EXPECT_GE(rows.size(), 4u);
    for (const auto& r : rows) {
        EXPECT_FALSE(r.unbounded) << r.nodeId;
        EXPECT_GT(r.thickness, 0.0) << r.nodeId;
        EXPECT_GE(r.length, r.width);
        EXPECT_GE(r.width, r.thickness);
    }
}

} // namespace
} // namespace kerf

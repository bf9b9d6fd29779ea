// Primitive distances against closed forms and against an independent
// computation in the profile plane (solids of revolution: the signed distance
// in the (r, z) half-plane to the profile's boundary).

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/PolygonIndex.hpp"
#include "kerf/evaluator/Primitives.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace kerf {
namespace {

double at(const Node& n, glm::dvec3 p)
{
    return PointEvaluator<double>().evaluate(compileTape(n), p.x, p.y, p.z);
}

Node box(glm::dvec3 size, double round = 0.0)
{
    Node n = makeNode(NodeType::Box, "b");
    n.params = BoxParams{size, round};
    return n;
}

TEST(PrimitiveDistance, Sphere)
{
    Node s = makeNode(NodeType::Sphere, "s");
    s.params = SphereParams{10.0};
    EXPECT_DOUBLE_EQ(at(s, {20, 0, 0}), 10.0);
    EXPECT_DOUBLE_EQ(at(s, {0, 0, 0}), -10.0);
    EXPECT_NEAR(at(s, {3, 4, 12}), 13.0 - 10.0, 1e-12);
}

TEST(PrimitiveDistance, BoxFacesEdgesCornersAndRounding)
{
    const Node b = box({20, 40, 60});
    EXPECT_DOUBLE_EQ(at(b, {15, 0, 0}), 5.0);
    EXPECT_DOUBLE_EQ(at(b, {15, 25, 0}), std::sqrt(50.0));
    EXPECT_DOUBLE_EQ(at(b, {13, 24, 42}), std::sqrt(9.0 + 16.0 + 144.0));
    EXPECT_DOUBLE_EQ(at(b, {0, 0, 0}), -10.0);
    EXPECT_DOUBLE_EQ(at(b, {0, 18, 0}), -2.0);
    // Rounded: the corner is a sphere of radius 3 centred 3 inside each face.
    const Node r = box({20, 40, 60}, 3.0);
    EXPECT_NEAR(at(r, {12, 22, 32}), std::sqrt(75.0) - 3.0, 1e-12);
    EXPECT_DOUBLE_EQ(at(r, {15, 0, 0}), 5.0); // faces keep the outer size
    EXPECT_DOUBLE_EQ(at(r, {0, 0, 0}), -10.0);
}

TEST(PrimitiveDistance, Cylinder)
{
    Node c = makeNode(NodeType::Cylinder, "c");
    c.params = CylinderParams{5.0, 20.0};
    EXPECT_DOUBLE_EQ(at(c, {8, 0, 0}), 3.0);
    EXPECT_DOUBLE_EQ(at(c, {0, 0, 15}), 5.0);
    EXPECT_DOUBLE_EQ(at(c, {8, 0, 14}), 5.0);
    EXPECT_DOUBLE_EQ(at(c, {0, 0, 0}), -5.0);
    EXPECT_DOUBLE_EQ(at(c, {0, 0, 9}), -1.0);
}

TEST(PrimitiveDistance, Torus)
{
    Node t = makeNode(NodeType::Torus, "t");
    t.params = TorusParams{20.0, 5.0};
    EXPECT_NEAR(at(t, {25, 0, 0}), 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(at(t, {0, 0, 0}), 15.0);
    EXPECT_NEAR(at(t, {0, 20, 8}), 3.0, 1e-12);
    EXPECT_NEAR(at(t, {20, 0, 0}), -5.0, 1e-12);
}

TEST(PrimitiveDistance, Halfspace)
{
    Document d = Document::parse(R"({"format":"kerf","version":1,"settings":{"bounds":[[-1,-1,-1],[1,1,1]]},
        "root":{"id":"h","type":"halfspace","normal":[0,0,2],"offset":4}})",
                                 "t");
    // Normal normalised; offset = distance along the unit normal = 4 / 2.
    EXPECT_DOUBLE_EQ(d.root.as<HalfspaceParams>().offset, 2.0);
    EXPECT_DOUBLE_EQ(at(d.root, {0, 0, 5}), 3.0);
    EXPECT_DOUBLE_EQ(at(d.root, {7, -3, 0}), -2.0);
}

// Signed distance from q to a polygon's boundary, counting only the listed
// edges (a profile's axis edge is not surface), sign from point-in-polygon.
double profileDistance(const std::vector<glm::dvec2>& poly, const std::vector<int>& edges, glm::dvec2 q)
{
    double d = 1e300;
    for (int e : edges) {
        const glm::dvec2 a = poly[e], b = poly[(e + 1) % poly.size()];
        const double t = glm::clamp(glm::dot(q - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
        d = std::min(d, glm::length(q - (a + t * (b - a))));
    }
    bool inside = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
        if ((poly[i].y > q.y) != (poly[j].y > q.y) &&
            q.x < (poly[j].x - poly[i].x) * (q.y - poly[i].y) / (poly[j].y - poly[i].y) + poly[i].x)
            inside = !inside;
    return inside ? -d : d;
}

TEST(PrimitiveDistance, ConeMatchesItsProfileInTheMeridianPlane)
{
    test::RandomShapes r(4);
    for (int shape = 0; shape < 50; ++shape) {
        const double rb = r.chance(0.2) ? 0.0 : r.uniform(0.5, 20.0);
        const double rt = rb == 0.0 ? r.uniform(0.5, 20.0) : (r.chance(0.2) ? 0.0 : r.uniform(0.0, 20.0));
        const double h = r.uniform(1.0, 40.0);
        Node c = makeNode(NodeType::Cone, "c");
        c.params = ConeParams{rb, rt, h};
        const Tape tape = compileTape(c);
        PointEvaluator<double> eval;
        // Profile: axis-bottom, bottom rim, top rim, axis-top; the last edge is the axis.
        const std::vector<glm::dvec2> profile = {{0, -h / 2}, {rb, -h / 2}, {rt, h / 2}, {0, h / 2}};
        for (int i = 0; i < 200; ++i) {
            const glm::dvec3 p = r.vec(-40.0, 40.0);
            const glm::dvec2 q(std::sqrt(p.x * p.x + p.y * p.y), p.z);
            EXPECT_NEAR(eval.evaluate(tape, p.x, p.y, p.z), profileDistance(profile, {0, 1, 2}, q), 1e-9)
                << "rb=" << rb << " rt=" << rt << " h=" << h;
        }
    }
}

TEST(PrimitiveDistance, ExtrudeMatchesAnIndependentPolygonDistance)
{
    test::RandomShapes r(5);
    for (int shape = 0; shape < 50; ++shape) {
        const auto poly = r.simplePolygon(r.integer(3, 10), 20.0);
        const double h = r.uniform(1.0, 30.0);
        Node e = makeNode(NodeType::Extrude, "e");
        e.params = ExtrudeParams{poly, h};
        const Tape tape = compileTape(e);
        PointEvaluator<double> eval;
        std::vector<int> all;
        for (int i = 0; i < int(poly.size()); ++i) all.push_back(i);
        for (int i = 0; i < 200; ++i) {
            const glm::dvec3 p = r.vec(-30.0, 30.0);
            const double d2 = profileDistance(poly, all, {p.x, p.y});
            const double wz = std::fabs(p.z) - h / 2;
            const double expected =
                std::min(std::max(d2, wz), 0.0) + std::hypot(std::max(d2, 0.0), std::max(wz, 0.0));
            EXPECT_NEAR(eval.evaluate(tape, p.x, p.y, p.z), expected, 1e-9);
        }
    }
}

TEST(PrimitiveDistance, ExtrudedSquareEqualsABox)
{
    Node e = makeNode(NodeType::Extrude, "e");
    e.params = ExtrudeParams{{{-10, -5}, {10, -5}, {10, 5}, {-10, 5}}, 30.0};
    const Node b = box({20, 10, 30});
    test::RandomShapes r(6);
    for (int i = 0; i < 1000; ++i) {
        const glm::dvec3 p = r.vec(-30.0, 30.0);
        EXPECT_NEAR(at(e, p), at(b, p), 1e-12);
    }
}

TEST(PrimitiveDistance, RevolveMatchesItsProfileInTheMeridianPlane)
{
    // Random profiles, half of them pressed onto the axis; points anywhere,
    // a quarter of them on the axis itself (where edges on the axis must
    // decide neither the distance nor the side).
    test::RandomShapes r(7);
    int onAxis = 0;
    for (int shape = 0; shape < 60; ++shape) {
        const Node n = [&] {
            Node m = r.primitive(NodeType::Revolve);
            m.transform = {};
            return m;
        }();
        const auto& profile = n.as<RevolveParams>().profile;
        std::vector<int> surfaceEdges;
        for (int e = 0; e < int(profile.size()); ++e)
            if (!(profile[e].x == 0 && profile[(e + 1) % profile.size()].x == 0)) surfaceEdges.push_back(e);
        onAxis += surfaceEdges.size() < profile.size();
        const Tape tape = compileTape(n);
        PointEvaluator<double> eval;
        for (int i = 0; i < 200; ++i) {
            glm::dvec3 p = r.vec(-45.0, 45.0);
            if (i % 4 == 0) p.x = p.y = 0.0;
            const glm::dvec2 q(std::hypot(p.x, p.y), p.z);
            EXPECT_NEAR(eval.evaluate(tape, p.x, p.y, p.z), profileDistance(profile, surfaceEdges, q), 1e-9)
                << "shape " << shape << " at (" << p.x << ", " << p.y << ", " << p.z << ")";
        }
    }
    EXPECT_GT(onAxis, 10) << "profiles with an edge on the axis were tested";
}

TEST(PrimitiveDistance, RevolvedRectanglesAndTrianglesEqualCylindersAndCones)
{
    test::RandomShapes r(8);
    Node cylinder = makeNode(NodeType::Cylinder, "c");
    cylinder.params = CylinderParams{5.0, 20.0};
    Node cone = makeNode(NodeType::Cone, "k");
    cone.params = ConeParams{8.0, 0.0, 30.0};
    for (const bool reversed : {false, true}) {
        std::vector<glm::dvec2> rectangle = {{0, -10}, {5, -10}, {5, 10}, {0, 10}};
        std::vector<glm::dvec2> triangle = {{0, -15}, {8, -15}, {0, 15}};
        if (reversed) {
            std::reverse(rectangle.begin(), rectangle.end());
            std::reverse(triangle.begin(), triangle.end());
        }
        Node turnedCylinder = makeNode(NodeType::Revolve, "rc");
        turnedCylinder.params = RevolveParams{rectangle};
        Node turnedCone = makeNode(NodeType::Revolve, "rk");
        turnedCone.params = RevolveParams{triangle};
        for (int i = 0; i < 1000; ++i) {
            glm::dvec3 p = r.vec(-30.0, 30.0);
            if (i % 3 == 0) p.x = p.y = 0.0; // on the axis: inside, as deep as the nearest face
            EXPECT_NEAR(at(turnedCylinder, p), at(cylinder, p), 1e-12) << reversed;
            EXPECT_NEAR(at(turnedCone, p), at(cone, p), 1e-9) << reversed;
        }
        EXPECT_DOUBLE_EQ(at(turnedCylinder, {0, 0, 0}), -5.0);
    }
}

TEST(PrimitiveDistance, RotationOrderIsXThenYThenZAboutFixedAxes)
{
    // Rx(90) maps local y to z; then Ry(90) maps x to -z and z to x.
    // A 10 x 20 x 30 box ends with world half extents (10, 15, 5).
    Node b = box({10, 20, 30});
    b.transform.rotate = {90, 90, 0};
    EXPECT_NEAR(at(b, {12, 0, 0}), 2.0, 1e-12);
    EXPECT_NEAR(at(b, {0, 17, 0}), 2.0, 1e-12);
    EXPECT_NEAR(at(b, {0, 0, 7}), 2.0, 1e-12);
    b.transform.translate = {100, 0, 0};
    EXPECT_NEAR(at(b, {112, 0, 0}), 2.0, 1e-12);
}

TEST(PrimitiveDistance, FloatEvaluationFarFromTheOriginKeepsPrecisionAfterRebasing)
{
    // A 10 mm sphere one kilometre away: in world float coordinates the
    // millimetre grid is 0.06 mm coarse; rebased, float is exact to ~1e-6 mm.
    Node s = makeNode(NodeType::Sphere, "s");
    s.params = SphereParams{10.0};
    s.transform.translate = {1e6, 2e6, -1e6};
    const Tape world = compileTape(s);
    const Tape local = world.rebased({1e6, 2e6, -1e6});
    PointEvaluator<float> f;
    EXPECT_NEAR(f.evaluate(local, 10.123f, 0.0f, 0.0f), 0.123f, 1e-5);
    PointEvaluator<double> d;
    EXPECT_NEAR(d.evaluate(world, 1e6 + 10.123, 2e6, -1e6), 0.123, 1e-8);
}

// The same tape with its profiles unindexed: every edge visited.
Tape withoutProfileIndexes(const Tape& tape)
{
    std::vector<ShapeInstance> shapes = tape.shapes();
    for (ShapeInstance& s : shapes)
        if (s.polygon) {
            auto plain = std::make_shared<Polygon>(*s.polygon);
            plain->index = {};
            plain->indexF = {};
            s.polygon = plain;
        }
    return Tape::assemble(tape.code(), shapes, tape.sharedFeatures(), tape.origin(), tape.bounds());
}

// A block of points close together skips a long profile's far edges
// (PointEvaluator.cpp's profileBlock, through the profile's index from 16
// points): the values are those of the points one by one over every edge,
// to the bit, in double and float, for extrusions and revolves
// of 9 to 400 edges, at clusters from a hundredth of the profile to all of it.
template <class S>
void expectBlocksEqualSinglePoints(const Tape& indexedTape, test::RandomShapes& r, const std::string& what)
{
    const Tape tape = withoutProfileIndexes(indexedTape);
    PointEvaluator<S> eval;
    for (int block = 0; block < 40; ++block) {
        const std::size_t n = std::size_t(r.integer(8, 64));
        const glm::dvec3 centre = r.vec(-25.0, 25.0);
        const double spread = std::pow(10.0, r.uniform(-1.0, 1.6));
        std::vector<S> x(n), y(n), z(n), together(n);
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec3 p = centre + r.vec(-spread, spread);
            x[i] = S(p.x);
            y[i] = S(p.y);
            z[i] = S(p.z);
        }
        eval.evaluate(indexedTape, x.data(), y.data(), z.data(), n, together.data());
        for (std::size_t i = 0; i < n; ++i) {
            const S alone = eval.evaluate(tape, x[i], y[i], z[i]);
            ASSERT_EQ(together[i], alone) << what << ", block " << block << " of " << n << " points, spread " << spread
                                          << ", point (" << x[i] << ", " << y[i] << ", " << z[i] << ")";
        }
    }
}

TEST(PrimitiveDistance, LongProfilesGiveBlocksOfPointsTheirValuesOneByOne)
{
    test::RandomShapes r(9);
    for (int shape = 0; shape < 30; ++shape) {
        auto poly = r.simplePolygon(shape % 2 ? r.integer(9, 15) : r.integer(16, 400), 20.0);
        Node e = makeNode(NodeType::Extrude, "e");
        e.params = ExtrudeParams{poly, r.uniform(1.0, 30.0)};
        // The same outline against the axis: its leftmost point on it.
        double left = poly[0].x;
        for (const glm::dvec2& q : poly)
            left = std::min(left, q.x);
        for (glm::dvec2& q : poly)
            q.x -= left;
        Node v = makeNode(NodeType::Revolve, "v");
        v.params = RevolveParams{poly};
        for (const Node* n : {&e, &v}) {
            const Tape tape = compileTape(*n);
            const std::string what = std::string(n == &e ? "extrusion" : "revolve") + " " + std::to_string(shape) +
                                     " (" + std::to_string(poly.size()) + " points)";
            expectBlocksEqualSinglePoints<double>(tape, r, what);
            expectBlocksEqualSinglePoints<float>(tape, r, what + ", float");
        }
    }
}

// The profile's index (PolygonIndex.hpp) gives the loop over every edge's
// values to the bit: distance, side and gradient, in double and float, with
// and without the axis edges, at random points, at points on the vertices'
// heights (the slabs' borders), on vertices and edges, and far away; also
// for a comb whose slab lists would be too long (built without them).
template <class P>
void expectIndexedEqualsEveryEdge(const std::vector<P>& points, test::RandomShapes& r, bool axisEdges,
                                  const std::string& what)
{
    using S = typename P::value_type;
    const PolygonIndex<P> index = buildPolygonIndex(points);
    ASSERT_TRUE(index.indexed()) << what;
    const sdf::IndexedProfile<P> indexed{points, index};
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const P& q : points) {
        lo = glm::min(lo, glm::dvec2(q));
        hi = glm::max(hi, glm::dvec2(q));
    }
    const glm::dvec2 size = hi - lo;
    for (int k = 0; k < 600; ++k) {
        glm::dvec2 q(r.uniform(lo.x - 0.2 * size.x, hi.x + 0.2 * size.x), r.uniform(lo.y - 0.2 * size.y, hi.y + 0.2 * size.y));
        const std::size_t at = std::size_t(r.integer(0, int(points.size()) - 1));
        if (k % 6 == 1) q.y = double(points[at].y);                                 // a slab's border
        if (k % 6 == 2) q = glm::dvec2(points[at]);                                 // a vertex
        if (k % 6 == 3) q = glm::mix(glm::dvec2(points[at]), glm::dvec2(points[(at + 1) % points.size()]), 0.5); // an edge
        if (k % 6 == 4) q *= 50.0;                                                  // far away
        if (k % 6 == 5) q.x = 0.0;                                                  // the axis
        const S x = S(q.x), y = S(q.y);
        const S plain = sdf::polygon2d(x, y, points, axisEdges), fast = sdf::polygon2d(x, y, indexed, axisEdges);
        ASSERT_EQ(plain, fast) << what << " at (" << x << ", " << y << ")";
        const Dual<S> dx(x, S(1), S(0), S(0)), dy(y, S(0), S(1), S(0));
        const Dual<S> dualPlain = sdf::polygon2d(dx, dy, points, axisEdges), dualFast = sdf::polygon2d(dx, dy, indexed, axisEdges);
        ASSERT_EQ(dualPlain.v, dualFast.v) << what << " at (" << x << ", " << y << ")";
        ASSERT_EQ(dualPlain.d[0], dualFast.d[0]) << what << " at (" << x << ", " << y << ")";
        ASSERT_EQ(dualPlain.d[1], dualFast.d[1]) << what << " at (" << x << ", " << y << ")";
    }
}

TEST(PrimitiveDistance, AProfilesIndexGivesEveryEdgesValuesToTheBit)
{
    test::RandomShapes r(10);
    for (int shape = 0; shape < 24; ++shape) {
        auto poly = r.simplePolygon(shape < 20 ? r.integer(16, 400) : r.integer(2000, 5000), 20.0);
        for (const bool axis : {true, false}) {
            if (!axis) {
                // Against the axis, with a run of edges on it.
                for (glm::dvec2& q : poly)
                    q.x = std::max(q.x, 0.0);
            }
            const std::string what = std::to_string(poly.size()) + " points" + (axis ? "" : ", on the axis");
            expectIndexedEqualsEveryEdge(poly, r, axis, what);
            std::vector<glm::vec2> rounded;
            for (const glm::dvec2& q : poly)
                rounded.emplace_back(float(q.x), float(q.y));
            expectIndexedEqualsEveryEdge(rounded, r, axis, what + ", float");
        }
    }
    // A comb of 400 teeth: each tooth's long edges span most slabs.
    std::vector<glm::dvec2> comb;
    for (int t = 0; t < 400; ++t) {
        comb.emplace_back(2.0 * t, 0.0);
        comb.emplace_back(2.0 * t + 0.5, 100.0 + 0.01 * t);
        comb.emplace_back(2.0 * t + 1.0, 0.01 * t + 0.005);
    }
    comb.emplace_back(800.0, -10.0);
    comb.emplace_back(0.0, -10.0);
    std::reverse(comb.begin(), comb.end());
    EXPECT_FALSE(buildPolygonIndex(comb).hasSlabs);
    expectIndexedEqualsEveryEdge(comb, r, true, "comb");
    // NaN: the index steps aside (the loop's parity flips at every edge).
    const PolygonIndex<glm::dvec2> index = buildPolygonIndex(comb);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double plain = sdf::polygon2d(nan, 5.0, comb), fast = sdf::polygon2d(nan, 5.0, sdf::IndexedProfile<glm::dvec2>{comb, index});
    EXPECT_TRUE(std::isnan(plain) == std::isnan(fast) && (std::isnan(plain) || plain == fast));
}

} // namespace
} // namespace kerf

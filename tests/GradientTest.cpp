// Gradients by automatic differentiation against central finite differences
// of the double evaluator, at random points of random trees. Near a crease
// (a min/max switch, a box edge) finite differences are meaningless, so a
// point counts only where two step sizes agree; most points must count.

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

namespace kerf {
namespace {

void compareGradients(const Tape& tape, test::RandomShapes& r, int points, int& compared, int& skipped)
{
    PointEvaluator<double> values;
    GradientEvaluator<double> grads;
    auto f = [&](glm::dvec3 p) { return values.evaluate(tape, p.x, p.y, p.z); };
    for (int i = 0; i < points; ++i) {
        const glm::dvec3 p = r.vec(-40.0, 40.0);
        const Dual<double> g = grads.evaluate(tape, p.x, p.y, p.z);
        ASSERT_NEAR(g.v, f(p), 1e-9) << "the gradient evaluator's value differs from the point evaluator's";
        glm::dvec3 fd1, fd2;
        for (int a = 0; a < 3; ++a) {
            glm::dvec3 e(0.0);
            e[a] = 1e-4;
            fd1[a] = (f(p + e) - f(p - e)) / 2e-4;
            fd2[a] = (f(p + 0.5 * e) - f(p - 0.5 * e)) / 1e-4;
        }
        if (glm::length(fd1 - fd2) > 1e-6) {
            ++skipped; // a crease within 1e-4 mm
            continue;
        }
        ++compared;
        const glm::dvec3 ad(g.d[0], g.d[1], g.d[2]);
        ASSERT_LT(glm::length(ad - fd1), 1e-5) << "at (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
}

class PrimitiveGradient : public ::testing::TestWithParam<NodeType> {};

TEST_P(PrimitiveGradient, MatchesFiniteDifferences)
{
    test::RandomShapes r(300 + static_cast<int>(GetParam()));
    int compared = 0, skipped = 0;
    for (int i = 0; i < 200; ++i) {
        compareGradients(compileTape(r.primitive(GetParam())), r, 50, compared, skipped);
        if (HasFatalFailure()) return;
    }
    EXPECT_GT(compared, 9 * skipped) << "too many points near creases: the comparison is weak";
}

INSTANTIATE_TEST_SUITE_P(EveryPrimitive, PrimitiveGradient,
                         ::testing::ValuesIn(test::RandomShapes::primitiveTypes()),
                         [](const auto& p) { return std::string(nodeTypeName(p.param)); });

TEST(TreeGradient, RandomTreesMatchFiniteDifferences)
{
    test::RandomShapes r(31);
    int compared = 0, skipped = 0;
    for (int i = 0; i < 200; ++i) {
        compareGradients(compileTape(r.tree(3)), r, 50, compared, skipped);
        if (HasFatalFailure()) return;
    }
    EXPECT_GT(compared, 9 * skipped);
}

TEST(Gradient, ExactDistanceFieldsHaveUnitGradientOutside)
{
    // Exact distances have |grad| = 1 wherever they are differentiable.
    test::RandomShapes r(8);
    GradientEvaluator<double> grads;
    for (NodeType t : {NodeType::Box, NodeType::Sphere, NodeType::Cylinder, NodeType::Cone, NodeType::Torus,
                       NodeType::Revolve}) {
        const Tape tape = compileTape(r.primitive(t));
        for (int i = 0; i < 200; ++i) {
            const glm::dvec3 p = r.vec(-60.0, 60.0);
            const Dual<double> g = grads.evaluate(tape, p.x, p.y, p.z);
            EXPECT_NEAR(std::sqrt(g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2]), 1.0, 1e-9)
                << nodeTypeName(t);
        }
    }
}

TEST(Gradient, OnAProfilesFaceTheNormalIsSquareToIt)
{
    // On the side face of an extrusion the offset from the nearest point of
    // the profile is rounding noise; the normal must still be square to the
    // face (the tracer takes its hits' normals from here). A slanted, long
    // edge far from the origin makes the noise large in float.
    const Tape tape = compileTape(Document::parse(
        R"({"format":"kerf","version":1,"root":{"id":"e","type":"extrude","height":20,)"
        R"("profile":[[300,100],[340,100],[330,173],[305,161]]}})",
        "test.kerf"));
    const glm::dvec2 a(330, 173), b(340, 100);
    const glm::dvec2 along = glm::normalize(b - a), across(-along.y, along.x); // outward
    GradientEvaluator<float> floats;
    GradientEvaluator<double> doubles;
    int points = 0, judged = 0;
    for (int i = 1; i < 200; ++i) {
        const glm::dvec2 p = a + (double(i) / 200.0) * (b - a);
        for (const double off : {0.0, 1e-6, -1e-6}) {
            const glm::dvec2 q = p + off * across;
            const Dual<float> f = floats.evaluate(tape, float(q.x), float(q.y), 3.0f);
            const Dual<double> d = doubles.evaluate(tape, q.x, q.y, 3.0);
            for (const glm::dvec3 g : {glm::dvec3(f.d[0], f.d[1], f.d[2]), glm::dvec3(d.d[0], d.d[1], d.d[2])}) {
                ++points;
                if (glm::length(g) == 0.0) continue; // exactly on the edge: any normal will do
                ++judged;
                EXPECT_GT(glm::dot(glm::normalize(g), glm::dvec3(across, 0.0)), std::cos(glm::radians(0.1)))
                    << "at " << q.x << ", " << q.y << ": (" << g.x << ", " << g.y << ", " << g.z << ")";
            }
        }
    }    EXPECT_GT(judged, points * 9 / 10);
    // (The generic product rule, and p - q over its length, both failed
    // here: inwards where the rounding puts the point inside.)
}

TEST(Gradient, FloatBatchMatchesDoubleSinglePoint)
{
    test::RandomShapes r(12);
    const Tape tape = compileTape(r.tree(3));
    std::vector<float> x, y, z;
    for (int i = 0; i < 1000; ++i) {
        const glm::dvec3 p = r.vec(-40.0, 40.0);
        x.push_back(float(p.x));
        y.push_back(float(p.y));
        z.push_back(float(p.z));
    }
    std::vector<float> d(x.size()), gx(x.size()), gy(x.size()), gz(x.size());
    GradientEvaluator<float>().evaluate(tape, x.data(), y.data(), z.data(), x.size(), d.data(), gx.data(), gy.data(),
                                        gz.data());
    GradientEvaluator<double> ref;
    int agree = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const Dual<double> g = ref.evaluate(tape, x[i], y[i], z[i]);
        EXPECT_NEAR(d[i], g.v, 1e-3);
        if (std::fabs(gx[i] - g.d[0]) + std::fabs(gy[i] - g.d[1]) + std::fabs(gz[i] - g.d[2]) < 1e-3) ++agree;
    }
    // Float and double can pick different sides of a crease at a few points.
    EXPECT_GT(agree, 990);
}

} // namespace
} // namespace kerf

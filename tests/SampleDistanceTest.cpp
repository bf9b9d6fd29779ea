// How the exporter judges a triangle's sample against the tolerance
// (mesher/src/SampleDistance.hpp): the distance to the part's surface, where
// |f| understates it (in a blend, inside a union where bodies meet), and
// never a zero of the field that is no surface (bodies touching inside the
// part). Checked against the accuracy library's walk, which measures the
// exported files, and against distances worked out by hand.

#include "SampleDistance.hpp"

#include "kerf/accuracy/SurfaceDistance.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <random>

namespace kerf::mesher {
namespace {

Tape tapeOf(const std::string& root)
{
    return compileTape(Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf"));
}

double judge(const Tape& tape, const glm::dvec3& world, double tolerance, bool finalJudgement = false)
{
    const glm::dvec3 p = world - tape.origin();
    SampleDistance samples(finalJudgement);
    double d = 0.0;
    samples.measure(tape, &p.x, &p.y, &p.z, 1, tolerance, &d);
    return d;
}

double field(const Tape& tape, const glm::dvec3& world)
{
    PointEvaluator<double> eval;
    const glm::dvec3 p = world - tape.origin();
    return eval.evaluate(tape, p.x, p.y, p.z);
}

TEST(SampleDistance, IsTheFieldWhereTheFieldIsADistance)
{
    const Tape tape = tapeOf(R"({"id":"s","type":"sphere","radius":10})");
    for (const double off : {-0.04, -0.01, 0.0, 0.02, 0.049, 0.2}) {
        const glm::dvec3 p = glm::normalize(glm::dvec3(1.0, 2.0, 3.0)) * (10.0 + off);
        EXPECT_NEAR(judge(tape, p, 0.05), std::abs(off), 1e-9) << off;
    }
}

// A rail whose end is buried in a leg: a point inside both, 0.05 mm from
// the leg's face that the rail covers and 0.08 mm below the rail's top face
// that the leg covers. |f| says 0.08 mm; the nearest surface is the corner
// where the rail's top leaves the leg, sqrt(0.05^2 + 0.08^2) mm away.
TEST(SampleDistance, WalksRoundTheFacesOneBodyHidesInAnother)
{
    const Tape tape = tapeOf(R"({"id":"u","type":"union","children":[
        {"id":"leg","type":"box","size":[40,40,400],"transform":{"translate":[20,0,200]}},
        {"id":"rail","type":"box","size":[120,20,60],"transform":{"translate":[-40,0,300]}}]})");
    const glm::dvec3 p(0.05, 0.0, 330.0 - 0.08);
    EXPECT_NEAR(std::abs(field(tape, p)), 0.08, 1e-9);
    EXPECT_NEAR(judge(tape, p, 0.1), std::sqrt(0.05 * 0.05 + 0.08 * 0.08), 1e-4);
    // Judged against 0.2 mm, 0.08 is under half: such a sample does not walk.
    EXPECT_NEAR(judge(tape, p, 0.2), 0.08, 1e-9);
}

// Two boards glued face to face: the field is 0 on the glue line, inside
// the part, and changes sign nowhere near it. A sample that walks there is
// not on the surface: it counts as beyond the tolerance.
TEST(SampleDistance, AGlueLineInsideThePartIsNoSurface)
{
    const Tape tape = tapeOf(R"({"id":"u","type":"union","children":[
        {"id":"a","type":"box","size":[20,50,50],"transform":{"translate":[-10,0,0]}},
        {"id":"b","type":"box","size":[20,50,50],"transform":{"translate":[10,0,0]}}]})");
    const glm::dvec3 p(-0.03, 1.0, 2.0);
    EXPECT_NEAR(field(tape, p), -0.03, 1e-12);
    EXPECT_GT(judge(tape, p, 0.05), 0.05);
    // The final judgement marches from the sample instead: here the surface
    // is 24 mm away, beyond any march.
    EXPECT_GT(judge(tape, p, 0.05, true), 0.05);
    // Near the boards' top face the marches find it: 0.06 mm up, where the
    // glue line meets it (up to a march step, 1/64 of the final
    // judgement's reach of 4 tolerances).
    const glm::dvec3 q(-0.03, 24.94, 2.0);
    EXPECT_NEAR(field(tape, q), -0.03, 1e-12);
    EXPECT_GT(judge(tape, q, 0.05), 0.05);
    const double marched = judge(tape, q, 0.05, true);
    EXPECT_GE(marched, 0.06 - 1e-9);
    EXPECT_LE(marched, 0.06 + 0.2 / 64.0 + 1e-9);
}

// Around a smooth blend between two boards at a right angle, where the
// field's gradient is shorter than 1 and |f| understates the distance by up
// to a third: where a sample walks (|f| between half the tolerance and the
// tolerance) the judgement agrees with the accuracy library's walk (an upper
// bound of the distance) to a hundredth of itself; elsewhere it is |f|, and
// it says "within the tolerance" only of points that are.
// A hole drilled 13 mm into a 12 mm board ends flush with its underside:
// the field is 0 across the hole's mouth (its end on the board's face), and
// |f| put a triangle cutting the rim there on the surface. Given the
// triangle's normal, the final judgement asks whether the field changes sign
// across the sample: there it does not, and the sample counts as far as the
// nearest crossing of straight marches, into the board past the rim
// diagonally: at most 0.1 * sqrt(2) mm for the rim 0.1 mm away. On the
// underside beside the mouth, the face is the surface.
TEST(SampleDistance, AFilmAcrossAHolesMouthIsNoSurfaceToTheFinalJudgement)
{
    const Tape tape = tapeOf(R"({"id":"d","type":"difference","children":[
        {"id":"b","type":"box","size":[60,30,12],"transform":{"translate":[30,15,6]}},
        {"id":"h","type":"cylinder","radius":5,"height":13,"transform":{"translate":[30,15,6.5]}}]})");
    auto judgeOnFace = [&](const glm::dvec3& world) {
        const glm::dvec3 p = world - tape.origin();
        const glm::dvec3 down(0, 0, -1);
        SampleDistance samples(true);
        double d = 0.0;
        samples.measure(tape, &p.x, &p.y, &p.z, 1, 0.05, &d, &down);
        return d;
    };
    const glm::dvec3 inMouth(34.9, 15.0, 0.0), beside(35.1, 15.0, 0.0);
    EXPECT_NEAR(field(tape, inMouth), 0.0, 1e-12); // what |f| says
    EXPECT_EQ(judge(tape, inMouth, 0.05, true), 0.0); // without the normal
    const double d = judgeOnFace(inMouth);
    EXPECT_GE(d, 0.1 - 1e-9);
    EXPECT_LE(d, 0.1 * std::sqrt(2.0) + 0.2 / 64.0); // a march's last step: a 64th of its reach
    EXPECT_LE(judgeOnFace(beside), 1e-9);
}

TEST(SampleDistance, AgreesWithTheMeasuredDistanceAroundABlend)
{
    const Tape tape = tapeOf(R"({"id":"u","type":"union","blend":6,"children":[
        {"id":"a","type":"box","size":[100,18,100],"transform":{"translate":[0,0,50]}},
        {"id":"b","type":"box","size":[100,100,18],"transform":{"translate":[0,41,9]}}]})");
    constexpr double kTolerance = 0.1;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> along(-30.0, 30.0), off(-kTolerance, kTolerance);
    std::vector<glm::dvec3> points;
    GradientEvaluator<double> gradients;
    // Points on the blend (found by Newton steps from around its middle),
    // then moved off the surface along its normal.
    for (int i = 0; i < 400; ++i) {
        glm::dvec3 p(along(random), 9.0 + 3.0 + 0.1 * along(random), 18.0 + 3.0 + 0.1 * along(random));
        for (int step = 0; step < 30; ++step) {
            const glm::dvec3 q = p - tape.origin();
            const auto v = gradients.evaluate(tape, q.x, q.y, q.z);
            const glm::dvec3 g(v.d[0], v.d[1], v.d[2]);
            p -= v.v * g / glm::dot(g, g);
        }
        const glm::dvec3 q = p - tape.origin();
        const auto v = gradients.evaluate(tape, q.x, q.y, q.z);
        points.push_back(p + off(random) * glm::normalize(glm::dvec3(v.d[0], v.d[1], v.d[2])));
    }
    const std::vector<PointDistance> measured = distancesToSurface(tape, points);
    int understated = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        ASSERT_TRUE(measured[i].resolved);
        const double judged = judge(tape, points[i], kTolerance), f = measured[i].lower;
        if (f > 0.5 * kTolerance && f <= kTolerance) {
            EXPECT_NEAR(judged, measured[i].upper, 0.01 * measured[i].upper + 1e-6) << i;
            if (f < 0.9 * measured[i].upper) ++understated;
        } else {
            EXPECT_EQ(judged, f) << i;
        }
        if (judged <= kTolerance) {
            EXPECT_LE(measured[i].upper, kTolerance * (1.0 + 1e-6)) << i;
        }
    }
    // The blend is where |f| alone would have said too little.
    EXPECT_GT(understated, 20);
}

} // namespace
} // namespace kerf::mesher

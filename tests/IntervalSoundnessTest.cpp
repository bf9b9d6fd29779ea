// Interval soundness as a property: for random boxes and random points inside
// them (corners included), the double-precision field at every point lies in
// the interval the evaluator returns for the box. At least 100,000 samples
// per primitive and per operation, seeded and reproducible.

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

namespace kerf {
namespace {

constexpr int kShapes = 100;
constexpr int kBoxesPerShape = 50;
constexpr int kPointsPerBox = 20; // 100 x 50 x 20 = 100,000 samples

struct Samples {
    long checked = 0;
    long tightHits = 0; // boxes whose interval was decisive (all positive or all negative)
};

// Samples `tape` over random boxes around `centre`; fails on the first point
// outside its box's interval.
void checkSoundness(const Tape& tape, test::RandomShapes& r, Samples& s, double reach)
{
    IntervalEvaluator intervals;
    PointEvaluator<double> points;
    for (int b = 0; b < kBoxesPerShape; ++b) {
        // Box sizes from a hundredth of a millimetre to tens of millimetres.
        const double size = std::pow(10.0, r.uniform(-2.0, 1.7));
        const glm::dvec3 lo = r.vec(-reach, reach);
        const glm::dvec3 hi = lo + glm::dvec3(size) * r.vec(0.2, 1.0);
        const Aabb box{lo, hi};
        const Interval iv = intervals.evaluate(tape, box);
        ASSERT_LE(iv.lo, iv.hi);
        if (iv.lo > 0.0 || iv.hi < 0.0) ++s.tightHits;
        for (int i = 0; i < kPointsPerBox; ++i) {
            glm::dvec3 p;
            if (i < 8) // the corners, where extreme values often are
                p = {i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z};
            else
                p = lo + (hi - lo) * r.vec(0.0, 1.0);
            const double v = points.evaluate(tape, p.x, p.y, p.z);
            ++s.checked;
            ASSERT_TRUE(iv.contains(v)) << "value " << v << " outside [" << iv.lo << ", " << iv.hi << "] at ("
                                        << p.x << ", " << p.y << ", " << p.z << ")";
        }
    }
}

class PrimitiveSoundness : public ::testing::TestWithParam<NodeType> {};

TEST_P(PrimitiveSoundness, PointsInsideBoxesLieInsideTheInterval)
{
    test::RandomShapes r(1000 + static_cast<int>(GetParam()));
    Samples s;
    for (int i = 0; i < kShapes; ++i) {
        const Tape tape = compileTape(r.primitive(GetParam()));
        checkSoundness(tape, r, s, 40.0);
        if (HasFatalFailure()) return;
    }
    EXPECT_GE(s.checked, 100000);
    // Not vacuous: many boxes were decided (the interval is useful, not [-inf, inf]).
    EXPECT_GT(s.tightHits, kShapes * kBoxesPerShape / 4);
}

INSTANTIATE_TEST_SUITE_P(EveryPrimitive, PrimitiveSoundness,
                         ::testing::ValuesIn(test::RandomShapes::primitiveTypes()),
                         [](const auto& p) { return std::string(nodeTypeName(p.param)); });

class OperationSoundness : public ::testing::TestWithParam<NodeType> {};

TEST_P(OperationSoundness, PointsInsideBoxesLieInsideTheInterval)
{
    test::RandomShapes r(2000 + static_cast<int>(GetParam()));
    Samples s;
    for (int i = 0; i < kShapes; ++i) {
        const Tape tape = compileTape(r.operation(GetParam()));
        checkSoundness(tape, r, s, 50.0);
        if (HasFatalFailure()) return;
    }
    EXPECT_GE(s.checked, 100000);
    EXPECT_GT(s.tightHits, kShapes * kBoxesPerShape / 4);
}

INSTANTIATE_TEST_SUITE_P(EveryOperation, OperationSoundness,
                         ::testing::ValuesIn(test::RandomShapes::operationTypes()),
                         [](const auto& p) { return std::string(nodeTypeName(p.param)); });

TEST(TreeSoundness, RandomDeepTreesAreSound)
{
    test::RandomShapes r(77);
    Samples s;
    for (int i = 0; i < kShapes; ++i) {
        const Tape tape = compileTape(r.tree(4));
        checkSoundness(tape, r, s, 50.0);
        if (HasFatalFailure()) return;
    }
    EXPECT_GE(s.checked, 100000);
}

// The interval arithmetic itself, operation by operation, against random
// operands: the result of the real operation on points of the operands lies
// in the interval result.
TEST(IntervalArithmetic, EveryOperationEnclosesItsPointwiseResults)
{
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto randomInterval = [&] {
        const double scale = std::pow(10.0, 6.0 * u(rng));
        double a = u(rng) * scale, b = u(rng) * scale;
        if (a > b) std::swap(a, b);
        return Interval{a, b};
    };
    auto pick = [&](Interval i) { return i.lo + (i.hi - i.lo) * (0.5 + 0.5 * u(rng)); };
    for (int i = 0; i < 100000; ++i) {
        const Interval a = randomInterval(), b = randomInterval();
        const double x = pick(a), y = pick(b);
        ASSERT_TRUE((a + b).contains(x + y));
        ASSERT_TRUE((a - b).contains(x - y));
        ASSERT_TRUE((a * b).contains(x * y));
        ASSERT_TRUE(square(a).contains(x * x));
        ASSERT_TRUE(abs(a).contains(std::fabs(x)));
        ASSERT_TRUE(min(a, b).contains(std::min(x, y)));
        ASSERT_TRUE(max(a, b).contains(std::max(x, y)));
        ASSERT_TRUE(sqrt(abs(a)).contains(std::sqrt(std::fabs(x))));
        ASSERT_GE(square(a).lo, 0.0);
    }
}

TEST(IntervalArithmetic, SquareOfAnIntervalAcrossZeroStartsAtZero)
{
    const Interval s = square(Interval{-2.0, 3.0});
    EXPECT_EQ(s.lo, 0.0);
    EXPECT_GE(s.hi, 9.0);
    // Outward rounding: 0.1 + 0.2 is not representable; the true sum is inside.
    const Interval sum = Interval(0.1) + Interval(0.2);
    EXPECT_LT(sum.lo, sum.hi);
}

} // namespace
} // namespace kerf

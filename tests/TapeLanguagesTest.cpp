// One tape evaluator per language, held to the same results: the GLSL tape
// library (shaders/tape.glsl, run on the Vulkan device: lavapipe here)
// against the C++ ones (voxelizer/src/TileTape.cpp over the sdf:: templates
// for points and gradients, IntervalEvaluator for intervals) on every shape
// kind and operation, at the same points and over the same boxes; and a
// shape kind neither knows is NaN in both, never a plane.

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/viewport/TapeProbe.hpp"
#include "kerf/viewport/VulkanError.hpp"
#include "kerf/voxelizer/TileTape.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <set>

namespace kerf {
namespace {

class TapeLanguages : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        try {
            context = std::make_unique<vk::Context>(vk::ContextOptions{.validation = true, .preferCpu = false});
            probe = std::make_unique<vk::TapeProbe>(*context);
        } catch (const vk::VulkanError& e) {
            skipReason = e.what();
        }
    }
    static void TearDownTestSuite()
    {
        probe.reset();
        context.reset();
    }
    void SetUp() override
    {
        if (!context) GTEST_SKIP() << "no Vulkan device: " << skipReason;
    }
    void TearDown() override
    {
        if (context) {
            EXPECT_EQ(context->validationErrors(), 0);
        }
    }
    static inline std::unique_ptr<vk::Context> context;
    static inline std::unique_ptr<vk::TapeProbe> probe;
    static inline std::string skipReason;
};

// Tile tapes as the voxelizer makes them: simplified for a box near the
// surface, rebased to its corner, encoded.
struct TileCase {
    Tape tape; // simplified and rebased: what `words` encodes, in double
    std::vector<std::uint32_t> words;
    std::vector<glm::vec3> points;
    double size = 0.0; // the tile's edge: it spans [0, size]^3
};

std::vector<TileCase> tileCases(const Tape& tape, test::RandomShapes& r, int boxes)
{
    std::vector<TileCase> out;
    IntervalEvaluator intervals;
    for (int b = 0; b < boxes; ++b) {
        const double size = std::pow(10.0, r.uniform(-0.5, 1.5));
        const glm::dvec3 lo = r.vec(-40.0, 40.0);
        const Aabb box{lo, lo + glm::dvec3(size)};
        Tape simple;
        const Interval iv = intervals.simplify(tape, box, simple);
        if (iv.lo > 0.0 || iv.hi < 0.0) continue;
        TileCase c;
        c.tape = simple.rebased(lo);
        c.words = voxel::encodeTileTape(c.tape);
        if (c.words.empty()) continue;
        c.size = size;
        for (int i = 0; i < 32; ++i) c.points.push_back(glm::vec3(glm::dvec3(size) * r.vec(0.0, 1.0)));
        out.push_back(std::move(c));
    }
    return out;
}

// Kinds present in an encoded tape.
void kindsOf(const std::vector<std::uint32_t>& w, std::set<std::uint32_t>& kinds)
{
    const std::uint32_t shapesAt = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * w[0];
    for (std::uint32_t s = 0; s < w[1]; ++s) kinds.insert(w[shapesAt + s * KERF_TAPE_SHAPE_WORDS]);
}

// Every shape alone and random trees of every operation, as tapes.
std::vector<Tape> testTapes(test::RandomShapes& r)
{
    std::vector<Tape> tapes;
    for (NodeType type : test::RandomShapes::primitiveTypes())
        for (int i = 0; i < 3; ++i) tapes.push_back(compileTape(test::RandomShapes::document(r.primitive(type))));
    for (int i = 0; i < 60; ++i) tapes.push_back(compileTape(r.tree(3)));
    return tapes;
}

TEST_F(TapeLanguages, GlslAndCppGiveTheSameValuesGradientsAndFeaturesOnEveryKind)
{
    test::RandomShapes r(29);
    // Each primitive alone (the halfspace too, which random trees leave out) and random trees.
    const std::vector<Tape> tapes = testTapes(r);

    std::set<std::uint32_t> kinds;
    int points = 0, featureMismatches = 0;
    double worstValue = 0.0, worstGradient = 0.0;
    for (const Tape& tape : tapes)
        for (const TileCase& c : tileCases(tape, r, 30)) {
            kindsOf(c.words, kinds);
            const std::vector<vk::TapeProbe::Result> gpu = probe->evaluate(c.words, c.points);
            ASSERT_EQ(gpu.size(), c.points.size());
            for (std::size_t i = 0; i < c.points.size(); ++i) {
                std::uint32_t feature = 0;
                const float value = voxel::evaluateTileTape(c.words.data(), c.points[i]);
                const glm::vec4 dual = voxel::evaluateTileTapeGradient(c.words.data(), c.points[i], feature);
                const double scale = 1.0 + std::abs(double(value));
                worstValue = std::max({worstValue, std::abs(double(gpu[i].value) - value) / scale,
                                       std::abs(double(gpu[i].dual.x) - dual.x) / scale});
                for (int a = 1; a < 4; ++a)
                    worstGradient = std::max(worstGradient, std::abs(double(gpu[i].dual[a]) - double(dual[a])));
                featureMismatches += gpu[i].feature != feature;
                ++points;
            }
        }
    std::printf("    %d points: worst relative difference GLSL - C++ %.3g, gradient %.3g, %d feature mismatches\n",
                points, worstValue, worstGradient, featureMismatches);
    // Every kind the format names was evaluated by both.
    for (std::uint32_t k = 0; k < KERF_SHAPE_KINDS; ++k) EXPECT_TRUE(kinds.count(k)) << "shape kind " << k << " untested";
    EXPECT_GT(points, 5000);
    // The same float operations in the same order; the devices' square roots may differ in the last bit.
    EXPECT_LT(worstValue, 1e-5);
    EXPECT_LT(worstGradient, 1e-4);
    EXPECT_LE(featureMismatches, points / 1000); // only where two operands tie to the last bit
}

TEST_F(TapeLanguages, GlslIntervalsEncloseTheTapeAndAgreeWithTheCppIntervalEvaluator)
{
    test::RandomShapes r(31);
    std::set<std::uint32_t> kinds;
    int boxes = 0, escapes = 0, samples = 0;
    double worstEscape = 0.0, worstDifference = 0.0;
    IntervalEvaluator cpp;
    for (const Tape& tape : testTapes(r))
        for (const TileCase& c : tileCases(tape, r, 30)) {
            kindsOf(c.words, kinds);
            // Boxes inside the tile from a hundredth of it to all of it, as the voxelizer's levels are.
            std::vector<vk::TapeProbe::Box> in;
            for (int i = 0; i < 16; ++i) {
                const double edge = c.size * std::pow(10.0, r.uniform(-2.0, 0.0));
                const glm::dvec3 lo = r.vec(0.0, c.size - edge);
                in.push_back({glm::vec3(lo), glm::vec3(lo + glm::dvec3(edge))});
            }
            const std::vector<glm::vec2> gpu = probe->enclose(c.words, in);
            ASSERT_EQ(gpu.size(), in.size());
            for (std::size_t i = 0; i < in.size(); ++i) {
                const Aabb box{glm::dvec3(in[i].lo), glm::dvec3(in[i].hi)};
                const Interval ref = cpp.evaluate(c.tape, box);
                ASSERT_TRUE(std::isfinite(gpu[i].x) && std::isfinite(gpu[i].y)) << gpu[i].x << " " << gpu[i].y;
                ASSERT_LE(gpu[i].x, gpu[i].y);
                // The same enclosures in float and in double: they differ by rounding and margins only.
                const double scale = 1.0 + std::max(std::abs(ref.lo), std::abs(ref.hi));
                worstDifference = std::max({worstDifference, std::abs(double(gpu[i].x) - ref.lo) / scale,
                                            std::abs(double(gpu[i].y) - ref.hi) / scale});
                // Sound: every value the float tape takes in the box lies inside (the corners, the centre, random points).
                for (int j = 0; j < 24; ++j) {
                    glm::dvec3 t = j < 8 ? glm::dvec3(j & 1, (j >> 1) & 1, (j >> 2) & 1) : r.vec(0.0, 1.0);
                    if (j == 8) t = glm::dvec3(0.5);
                    const glm::vec3 p = glm::vec3(box.min + t * box.size());
                    const float v = voxel::evaluateTileTape(c.words.data(), p);
                    const double outside = std::max(double(gpu[i].x) - v, v - double(gpu[i].y));
                    if (outside > 0.0) {
                        ++escapes;
                        worstEscape = std::max(worstEscape, outside / (1.0 + std::abs(v)));
                    }
                    ++samples;
                }
                ++boxes;
            }
        }
    std::printf("    %d boxes, %d samples: worst relative difference GLSL - C++ interval %.3g; %d samples outside "
                "the GLSL interval (worst by %.3g relative)\n",
                boxes, samples, worstDifference, escapes, worstEscape);
    for (std::uint32_t k = 0; k < KERF_SHAPE_KINDS; ++k) EXPECT_TRUE(kinds.count(k)) << "shape kind " << k << " untested";
    EXPECT_GT(boxes, 2000);
    EXPECT_EQ(escapes, 0);
    // GLSL widens the centre's value by 2^-20 of the magnitudes involved (coordinates and parameters up to
    // about 100 mm here: 1e-4 mm) for its float rounding; C++ by 1e-12 of them.
    EXPECT_LT(worstDifference, 3e-4);
}

TEST_F(TapeLanguages, AnUnknownShapeKindIsNaNInBothLanguagesEvenUnderAMin)
{
    test::RandomShapes r(3);
    Node u = r.operation(NodeType::Union); // a few primitives under a min
    const Tape tape = compileTape(test::RandomShapes::document(u));
    std::vector<std::uint32_t> words = voxel::encodeTileTape(tape);
    ASSERT_FALSE(words.empty());
    ASSERT_GE(words[1], 2u);
    // The last shape becomes a kind from a future version.
    const std::uint32_t shapesAt = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * words[0];
    words[shapesAt + (words[1] - 1) * KERF_TAPE_SHAPE_WORDS] = KERF_SHAPE_KINDS + 3u;
    const std::vector<glm::vec3> points{{0, 0, 0}, {5, -3, 2}, {100, 100, 100}};
    const auto gpu = probe->evaluate(words, points);
    const auto intervals = probe->enclose(words, {{{-1, -1, -1}, {1, 1, 1}}, {{50, 50, 50}, {60, 70, 80}}});
    for (const glm::vec2& iv : intervals) EXPECT_TRUE(std::isnan(iv.x) && std::isnan(iv.y)) << iv.x << " " << iv.y;
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::uint32_t feature = 0;
        EXPECT_TRUE(std::isnan(voxel::evaluateTileTape(words.data(), points[i])));
        EXPECT_TRUE(std::isnan(voxel::evaluateTileTapeGradient(words.data(), points[i], feature).x));
        EXPECT_TRUE(std::isnan(gpu[i].value)) << gpu[i].value;
        EXPECT_TRUE(std::isnan(gpu[i].dual.x)) << gpu[i].dual.x;
    }
}

} // namespace
} // namespace kerf

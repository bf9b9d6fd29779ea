// One tape evaluator per language, held to the same values: the GLSL tape
// library (shaders/tape.glsl, run on the Vulkan device: lavapipe here)
// against the C++ one (voxelizer/src/TileTape.cpp over the sdf:: templates)
// on every shape kind and operation, at the same points; and a shape kind
// neither knows is NaN in both, never a plane.

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
    std::vector<std::uint32_t> words;
    std::vector<glm::vec3> points;
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
        c.words = voxel::encodeTileTape(simple.rebased(lo));
        if (c.words.empty()) continue;
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

TEST_F(TapeLanguages, GlslAndCppGiveTheSameValuesGradientsAndFeaturesOnEveryKind)
{
    test::RandomShapes r(29);
    std::vector<Tape> tapes;
    // Each primitive alone (the halfspace too, which random trees leave out)...
    for (NodeType type : test::RandomShapes::primitiveTypes())
        for (int i = 0; i < 3; ++i) tapes.push_back(compileTape(test::RandomShapes::document(r.primitive(type))));
    // ... and random trees of every operation.
    for (int i = 0; i < 60; ++i) tapes.push_back(compileTape(r.tree(3)));

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

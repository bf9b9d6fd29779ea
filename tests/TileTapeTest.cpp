// A tile's exact tape in the GPU form (TileTape.hpp): evaluated as the
// shader does, it gives the evaluator's values and deciding features; tiles
// carry the tape they were built from, precise far from the origin; tapes the
// GPU evaluator cannot hold are refused.

#include "kerf/voxelizer/TileTape.hpp"
#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/Primitives.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace kerf {
namespace {

TEST(TileTape, EvaluatesAsTheEvaluatorDoes)
{
    // Random trees of every primitive and operation, simplified for random
    // boxes and rebased to the box's corner, exactly as tiles are built.
    test::RandomShapes r(17);
    IntervalEvaluator intervals;
    PointEvaluator<float> floats;
    PointEvaluator<double> doubles;
    GradientEvaluator<float> gradients;
    int encoded = 0, refused = 0, points = 0, featureMismatches = 0;
    double worstFloat = 0.0, worstDouble = 0.0, worstGradient = 0.0;
    for (int t = 0; t < 400; ++t) {
        const Tape tape = compileTape(r.tree(4));
        for (int b = 0; b < 20; ++b) {
            const double size = std::pow(10.0, r.uniform(-0.5, 1.5));
            const glm::dvec3 lo = r.vec(-40.0, 40.0);
            const Aabb box{lo, lo + glm::dvec3(size)};
            Tape simple;
            const Interval iv = intervals.simplify(tape, box, simple);
            if (iv.lo > 0.0 || iv.hi < 0.0) continue; // no surface: tiles keep no tape
            const Tape local = simple.rebased(lo);
            const std::vector<std::uint32_t> words = voxel::encodeTileTape(local);
            if (words.empty()) {
                // Arrays of many copies: more than the GPU evaluator holds.
                EXPECT_TRUE(local.maxStack() > KERF_TAPE_MAX_STACK || local.size() > KERF_TAPE_MAX_INSTRUCTIONS);
                ++refused;
                continue;
            }
            ++encoded;
            for (int i = 0; i < 20; ++i) {
                const glm::dvec3 rel = glm::dvec3(size) * r.vec(0.0, 1.0);
                const glm::vec3 p(rel);
                std::uint32_t gpuFeature = 0, cpuFeature = 0;
                const float gpu = voxel::evaluateTileTape(words.data(), p);
                const float cpu = floats.evaluate(local, p.x, p.y, p.z, &cpuFeature);
                const double exact = doubles.evaluate(tape, lo.x + rel.x, lo.y + rel.y, lo.z + rel.z);
                // The same float arithmetic but for the order of a few
                // operations (the evaluator's extrusions run edge by edge).
                worstFloat = std::max(worstFloat, std::abs(double(gpu) - double(cpu)) / (1.0 + std::abs(double(cpu))));
                worstDouble = std::max(worstDouble, std::abs(double(gpu) - exact));
                // The gradient: forward differentiation as the evaluator does it.
                const glm::vec4 fg = voxel::evaluateTileTapeGradient(words.data(), p, gpuFeature);
                featureMismatches += gpuFeature != cpuFeature;
                const Dual<float> dual = gradients.evaluate(local, p.x, p.y, p.z);
                worstFloat = std::max(worstFloat, std::abs(double(fg.x) - double(cpu)) / (1.0 + std::abs(double(cpu))));
                for (int a = 0; a < 3; ++a)
                    worstGradient = std::max(worstGradient, std::abs(double(fg[a + 1]) - double(dual.d[a])));
                ++points;
            }
        }
    }
    std::printf("    %d tapes (%d refused), %d points: worst relative difference to the float evaluator %.3g, "
                "worst difference to double %.3g mm, to the evaluator's gradient %.3g, %d feature mismatches\n",
                encoded, refused, points, worstFloat, worstDouble, worstGradient, featureMismatches);
    EXPECT_GT(encoded, 300);
    EXPECT_LT(refused, encoded / 10);
    EXPECT_LT(worstFloat, 1e-5);
    EXPECT_LT(worstDouble, 1e-3); // float on tile-relative coordinates of parts within 100 mm
    EXPECT_LT(worstGradient, 1e-4);
    EXPECT_LE(featureMismatches, points / 1000); // only where two operands tie to the last bit
}

TEST(TileTape, SurfaceTilesCarryTheTapeTheyWereBuiltFrom)
{
    // The chair has extrusions (shared polygons), booleans and blends; far
    // from the origin, float stays precise because the tape is tile-relative.
    for (const glm::dvec3 offset : {glm::dvec3(0.0), glm::dvec3(100000.0, -50000.0, 2000.0)}) {
        Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf");
        doc.root.transform.translate += offset;
        const Tape tape = compileTape(doc);
        const GridLayout layout = GridLayout::choose(tape.bounds(), 4.0);
        const VoxelSnapshot snap = voxelize(tape, layout, {.levels = 0, .threads = 2});
        const FlatVoxelBuffers flat = FlatVoxelBuffers::flatten(snap);
        test::RandomShapes r(3);
        PointEvaluator<double> doubles;
        int surface = 0, withTape = 0, extrusions = 0;
        double worst = 0.0;
        std::size_t tapeWords = 0;
        for (long i = 0; i < layout.tileCount(); ++i) {
            const auto& t = snap.tiles[std::size_t(i)];
            if (!t || t->state != TileState::Surface) continue;
            ++surface;
            if (t->tape.empty()) continue;
            ++withTape;
            tapeWords += t->tape.size();
            // The flat buffers reach the same words through the tile's entry.
            const TileEntry& entry = flat.entries[flat.tiles[std::size_t(i)]];
            ASSERT_NE(entry.tape, voxel::kNoTape);
            ASSERT_TRUE(std::equal(t->tape.begin(), t->tape.end(), flat.tapes.begin() + entry.tape));
            const std::uint32_t shapes = t->tape[1];
            for (std::uint32_t s = 0; s < shapes; ++s)
                extrusions += t->tape[KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * t->tape[0] +
                                      s * KERF_TAPE_SHAPE_WORDS] == KERF_SHAPE_EXTRUDE;
            const Aabb box = layout.tileBox(layout.tileCoord(i));
            for (int k = 0; k < 8; ++k) {
                const glm::dvec3 rel = glm::dvec3(layout.tileSize) * r.vec(0.0, 1.0);
                std::uint32_t feature = 0;
                const float v = voxel::evaluateTileTape(t->tape.data(), glm::vec3(rel));
                const glm::dvec3 w = box.min + rel;
                worst = std::max(worst, std::abs(double(v) - doubles.evaluate(tape, w.x, w.y, w.z)));
                EXPECT_NEAR(voxel::evaluateTileTapeGradient(t->tape.data(), glm::vec3(rel), feature).x, v, 1e-4);
                EXPECT_LT(feature, tape.features().size());
            }
        }
        EXPECT_GT(surface, 20);
        EXPECT_EQ(withTape, surface) << "the chair's tile tapes are short";
        EXPECT_GT(extrusions, 0);
        EXPECT_LT(worst, 2e-3) << "at offset " << offset.x;
        EXPECT_EQ(flat.tapes.size(), tapeWords);
        EXPECT_EQ(flat.bytes(), snap.bytes()) << "the flat buffers and the snapshot count the same bytes";
    }
}

TEST(TileTape, RefusesWhatTheGpuEvaluatorCannotHold)
{
    ShapeInstance s;
    s.kind = ShapeKind::Sphere;
    s.param[0] = 1.0;
    auto tapeOf = [&](int primitives, bool nested) {
        // nested: p0 p1 ... pn-1 min ... min (the stack grows to n);
        // otherwise a left fold: p0 p1 min p2 min ... (the stack stays at 2).
        std::vector<Instruction> code;
        Instruction prim, op;
        op.op = Op::Min;
        for (int i = 0; i < primitives; ++i) {
            code.push_back(prim);
            if (!nested && i > 0) code.push_back(op);
        }
        if (nested)
            for (int i = 1; i < primitives; ++i)
                code.push_back(op);
        return Tape::assemble(code, {s}, nullptr, glm::dvec3(0.0), Aabb{glm::dvec3(-1.0), glm::dvec3(1.0)});
    };
    EXPECT_FALSE(voxel::encodeTileTape(tapeOf(KERF_TAPE_MAX_STACK, true)).empty());
    EXPECT_TRUE(voxel::encodeTileTape(tapeOf(KERF_TAPE_MAX_STACK + 1, true)).empty()) << "stack too deep";
    const int longest = int(KERF_TAPE_MAX_INSTRUCTIONS + 1) / 2; // 2n - 1 instructions
    EXPECT_FALSE(voxel::encodeTileTape(tapeOf(longest, false)).empty());
    EXPECT_TRUE(voxel::encodeTileTape(tapeOf(longest + 1, false)).empty()) << "too many instructions";
    EXPECT_TRUE(voxel::encodeTileTape(Tape{}).empty());
}

} // namespace
} // namespace kerf

namespace kerf {
namespace {

// A shape kind this build does not know (a newer file's, or one forgotten in
// an evaluator) is NaN everywhere, never a plane or a silent zero; under a
// min the whole value is NaN, not the other operand's.
TEST(TileTape, AnUnknownShapeKindIsNaNNotAPlane)
{
    test::RandomShapes r(5);
    const Tape tape = compileTape(test::RandomShapes::document(r.operation(NodeType::Union)));
    std::vector<std::uint32_t> words = voxel::encodeTileTape(tape);
    ASSERT_GE(words.size(), 2u);
    const std::uint32_t shapesAt = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * words[0];
    for (std::uint32_t kind : {KERF_SHAPE_KINDS, 200u, 0x100u}) { // 0x100 would wrap to a box in a uint8 cast
        std::vector<std::uint32_t> w = words;
        w[shapesAt] = kind;
        std::uint32_t feature = 0;
        EXPECT_TRUE(std::isnan(voxel::evaluateTileTape(w.data(), glm::vec3(1, 2, 3)))) << kind;
        EXPECT_TRUE(std::isnan(voxel::evaluateTileTapeGradient(w.data(), glm::vec3(1, 2, 3), feature).x)) << kind;
    }
    // The document's evaluators alike.
    ShapeInstance unknown = tape.shapes().front();
    unknown.kind = ShapeKind(99);
    EXPECT_TRUE(std::isnan(shapeDistanceLocal<double>(unknown, 1.0, 2.0, 3.0)));
    EXPECT_TRUE(std::isnan(shapeDistanceLocal<Dual<float>>(unknown, 1.0f, 2.0f, 3.0f).v));
}

} // namespace
} // namespace kerf

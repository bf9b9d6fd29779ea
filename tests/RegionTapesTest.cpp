// Tapes simplified for a neighbourhood (mesher/src/RegionTapes.hpp), which
// the export's refinement and simplification evaluate instead of the whole
// part's: equal to the full tape, bit for bit, at every point of the
// neighbourhood asked for, and much shorter on a part of many features.

#include "RegionTapes.hpp"

#include "support/RandomShapes.hpp"

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <random>

namespace kerf::mesher {
namespace {

double valueAt(PointEvaluator<double>& points, const Tape& tape, const glm::dvec3& world)
{
    const glm::dvec3 q = world - tape.origin();
    return points.evaluate(tape, q.x, q.y, q.z);
}

// Random points within `radius` (up to `reach` cubes) of random centres:
// the regional tape gives exactly the full tape's value.
void expectEqualNearby(const Tape& tape, double cube, std::uint64_t seed, int centres, double reach = 1.0)
{
    RegionTapes regions(tape, cube);
    PointEvaluator<double> points;
    std::mt19937_64 rng(seed);
    const Aabb box = tape.bounds();
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int c = 0; c < centres; ++c) {
        const glm::dvec3 centre = box.min + (box.max - box.min) * glm::dvec3(u(rng), u(rng), u(rng));
        const double radius = reach * cube * u(rng);
        const Tape& local = regions.near(centre, radius);
        for (int k = 0; k < 20; ++k) {
            glm::dvec3 d(2.0 * u(rng) - 1.0, 2.0 * u(rng) - 1.0, 2.0 * u(rng) - 1.0);
            if (glm::length(d) > 1.0) d /= glm::length(d);
            const glm::dvec3 p = centre + radius * d;
            const double full = valueAt(points, tape, p), near = valueAt(points, local, p);
            ASSERT_TRUE(full == near || (std::isnan(full) && std::isnan(near)))
                << "centre " << centre.x << "," << centre.y << "," << centre.z << " radius " << radius << ": " << full
                << " against " << near;
        }
    }
}

TEST(RegionTapes, EqualTheFullTapeWithinTheRadiusOnRandomParts)
{
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        test::RandomShapes shapes(seed);
        const Tape tape = compileTape(test::RandomShapes::document(shapes.tree(3)));
        if (tape.empty() || !tape.bounds().isBounded()) continue;
        const double extent = glm::length(tape.bounds().max - tape.bounds().min);
        expectEqualNearby(tape, 0.1 * extent, seed, 40);
        expectEqualNearby(tape, 0.05 * extent, seed, 20, 8.0); // the larger cubes' tapes
    }
}

TEST(RegionTapes, AShelfSideIsAFewInstructionsNearAHoleAndWholeOnlyBeyondTheLargestCube)
{
    const Tape tape = compileTape(Document::load(std::string(KERF_EXAMPLES_DIR) + "/bookshelf-side.kerf"));
    expectEqualNearby(tape, 32.0, 5, 200);
    RegionTapes regions(tape, 32.0);
    // A shelf-pin hole's rim (the first row: x = 9, y = 37, z = 160 in the example).
    const Tape& nearHole = regions.near(glm::dvec3(9.0, 37.0, 160.0), 8.0);
    EXPECT_LT(nearHole.size() * 5, tape.size()) << nearHole.size() << " of " << tape.size();
    // Asked for more than a cube: the tape of a cube twice as large, equal
    // within the radius (above), still shorter than the whole part's.
    const Tape& wider = regions.near(glm::dvec3(9.0, 37.0, 160.0), 40.0);
    EXPECT_NE(&wider, &tape);
    EXPECT_LT(wider.size() * 2, tape.size()) << wider.size() << " of " << tape.size();
    EXPECT_GE(wider.size(), nearHole.size());
    expectEqualNearby(tape, 32.0, 6, 100, 6.0);
    // Asked for more than the largest cube (2048 of them): the whole tape.
    EXPECT_EQ(&regions.near(glm::dvec3(9.0, 37.0, 160.0), 32.0 * 4096.0), &tape);
    // Asked twice in one cube: the same cached tape.
    EXPECT_EQ(&regions.near(glm::dvec3(9.0, 37.0, 161.0), 8.0), &nearHole);
}

} // namespace
} // namespace kerf::mesher

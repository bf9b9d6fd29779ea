// The part's side of the export's tolerance (mesher/src/SurfaceCoverage.hpp):
// each sample's distance to the mesh against brute force, and the case the
// triangles' own samples cannot see, a box whose edge a triangle cuts off.
#include "SurfaceCoverage.hpp"
#include "TriangleClearance.hpp"

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace kerf::mesher {
namespace {

// A 10 mm cube [0, 10]^3 with its edge along z at x = y = 10 cut off by a
// chamfer `cut` mm wide on each face: 8 + 2 corners, outward triangles.
Mesh chamferedCube(double cut)
{
    Mesh m;
    const double c = 10.0 - cut;
    m.vertices = {{0, 0, 0}, {10, 0, 0}, {10, c, 0}, {c, 10, 0}, {0, 10, 0},
                  {0, 0, 10}, {10, 0, 10}, {10, c, 10}, {c, 10, 10}, {0, 10, 10}};
    auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t cc, std::uint32_t d) {
        m.triangles.push_back({a, b, cc});
        m.triangles.push_back({a, cc, d});
    };
    // Bottom (z = 0, facing down) and top as fans of the pentagon.
    for (std::uint32_t k = 1; k + 1 < 5; ++k) {
        m.triangles.push_back({0, k + 1, k});
        m.triangles.push_back({5, 5 + k, 5 + k + 1});
    }
    quad(0, 1, 6, 5); // y = 0
    quad(1, 2, 7, 6); // x = 10
    quad(2, 3, 8, 7); // the chamfer
    quad(3, 4, 9, 8); // y = 10
    quad(4, 0, 5, 9); // x = 0
    return m;
}

TEST(SurfaceCoverage, DistancesBeyondTheToleranceAreExactAndOrdered)
{
    const Mesh mesh = chamferedCube(2.0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> where(-3.0, 13.0);
    SurfaceSamples samples;
    samples.origin = {5.0, 5.0, 5.0};
    for (int i = 0; i < 2000; ++i)
        samples.points.emplace_back(glm::vec3(where(rng), where(rng), where(rng)) - glm::vec3(samples.origin));
    samples.onSharpEdge.assign(samples.points.size(), 0);
    const double tolerance = 0.5;
    tbb::task_arena arena(2);
    std::vector<std::pair<double, std::uint32_t>> beyond;
    const CoverageCheck check = measureCoverage(samples, mesh, tolerance, arena, &beyond);
    std::uint64_t expectedBeyond = 0;
    double expectedWorst = 0.0;
    for (std::uint32_t i = 0; i < samples.points.size(); ++i) {
        const glm::dvec3 p = samples.origin + glm::dvec3(samples.points[i]);
        double d = std::numeric_limits<double>::infinity();
        for (const auto& t : mesh.triangles)
            d = std::min(d, pointTriangleDistance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
        if (d <= tolerance) continue;
        ++expectedBeyond;
        expectedWorst = std::max(expectedWorst, d);
        const auto it = std::find_if(beyond.begin(), beyond.end(), [&](const auto& b) { return b.second == i; });
        ASSERT_NE(it, beyond.end()) << "sample " << i << " at " << d << " mm";
        EXPECT_NEAR(it->first, d, 1e-9);
    }
    EXPECT_EQ(check.samples, samples.points.size());
    EXPECT_EQ(check.samplesBeyond, expectedBeyond);
    EXPECT_EQ(beyond.size(), expectedBeyond);
    EXPECT_NEAR(check.worst, expectedWorst, 1e-9);
    EXPECT_TRUE(std::is_sorted(beyond.begin(), beyond.end(),
                               [](const auto& a, const auto& b) { return a.first > b.first; }));
    EXPECT_GT(expectedBeyond, 100u); // the test means something
}

// Samples in the order the lattice gives them, neighbours after one
// another, each near a face of the cube and on either side of the
// tolerance: the triangle that held the last few samples is asked first
// (measureCoverage), and the answers must still be brute force's, for all
// the samples and for a subset.
TEST(SurfaceCoverage, NeighbouringSamplesGetBruteForcesAnswers)
{
    const Mesh mesh = chamferedCube(2.0);
    const double tolerance = 0.05;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> off(-2.0f * float(tolerance), 2.0f * float(tolerance));
    SurfaceSamples samples;
    samples.origin = {5.0, 5.0, 5.0};
    for (int i = 0; i <= 100; ++i)
        for (int j = 0; j <= 100; ++j) {
            const float u = 0.1f * float(i), v = 0.1f * float(j);
            samples.points.push_back(glm::vec3(10.0f + off(rng), u, v) - glm::vec3(samples.origin));
            samples.points.push_back(glm::vec3(u, 10.0f + off(rng), v) - glm::vec3(samples.origin));
            samples.points.push_back(glm::vec3(u, v, off(rng)) - glm::vec3(samples.origin));
        }
    samples.onSharpEdge.assign(samples.points.size(), 0);
    std::vector<double> distance(samples.points.size());
    for (std::size_t i = 0; i < samples.points.size(); ++i) {
        const glm::dvec3 p = samples.origin + glm::dvec3(samples.points[i]);
        distance[i] = std::numeric_limits<double>::infinity();
        for (const auto& t : mesh.triangles)
            distance[i] = std::min(distance[i], pointTriangleDistance(p, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                                                      mesh.vertices[t[2]]));
    }
    tbb::task_arena arena(2);
    std::vector<std::uint32_t> odd;
    for (std::uint32_t i = 1; i < samples.points.size(); i += 2)
        odd.push_back(i);
    const std::vector<std::uint32_t>* subsets[] = {nullptr, &odd};
    for (const std::vector<std::uint32_t>* only : subsets) {
        std::vector<std::pair<double, std::uint32_t>> beyond;
        const CoverageCheck check = measureCoverage(samples, mesh, tolerance, arena, &beyond, only);
        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = 0; i < samples.points.size(); ++i)
            if ((!only || i % 2 == 1) && distance[i] > tolerance) expected.push_back(i);
        std::vector<std::uint32_t> found;
        for (const auto& [d, i] : beyond) {
            EXPECT_NEAR(d, distance[i], 1e-9) << "sample " << i;
            found.push_back(i);
        }
        std::sort(found.begin(), found.end());
        EXPECT_EQ(found, expected);
        EXPECT_EQ(check.samplesBeyond, expected.size());
        // Both sides of the tolerance are met, many times (the test means something).
        EXPECT_GT(expected.size(), 2000u);
        EXPECT_GT(check.samples - expected.size(), 2000u);
    }
}

// The cube's own points: its faces' and edges' points, as the cells find
// them. The chamfer (the mesh) cuts the edge at x = y = 10 off: every point
// of the faces is within a hair of the mesh except near that edge, whose
// points lie cut * sqrt(1/2) from the chamfer, and the triangles' samples
// (on the chamfer) lie only cut / 2 from the faces.
TEST(SurfaceCoverage, FindsTheEdgeATriangleCutsOff)
{
    const double cut = 0.08, tolerance = 0.05;
    const Mesh mesh = chamferedCube(cut);
    SurfaceSamples samples;
    samples.origin = {0.0, 0.0, 0.0};
    for (int i = 0; i <= 40; ++i)
        for (int j = 0; j <= 40; ++j) {
            const float u = 0.25f * float(i), v = 0.25f * float(j);
            samples.points.push_back({10.0f, u, v}); // the face x = 10, up to the edge
            samples.points.push_back({u, 10.0f, v}); // the face y = 10
            samples.points.push_back({u, v, 0.0f});  // the bottom
        }
    samples.onSharpEdge.assign(samples.points.size(), 0);
    tbb::task_arena arena(2);
    const CoverageCheck check = measureCoverage(samples, mesh, tolerance, arena);
    // On the edge (u = 10 on either face, 41 heights each, once per face),
    // and the bottom's corner under it.
    EXPECT_EQ(check.samplesBeyond, 2u * 41u + 1u);
    EXPECT_NEAR(check.worst, cut * std::sqrt(0.5), 1e-6);
    EXPECT_NEAR(check.worstAt.x, 10.0, 1e-6);
    EXPECT_NEAR(check.worstAt.y, 10.0, 1e-6);
    // The chamfer's own points are within cut / 2 of the faces: the
    // triangles' samples say "within the tolerance".
    EXPECT_LT(0.5 * cut, tolerance);
}

} // namespace
} // namespace kerf::mesher

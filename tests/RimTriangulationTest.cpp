// The best triangulation of a rim (RimTriangulation.hpp): the worst
// triangle decides, the sum breaks ties, forbidden triangles never appear,
// and every triangulation it returns covers the polygon once.

#include "RimTriangulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <set>
#include <utility>

namespace kerf::mesher {
namespace {

constexpr double kForbidden = std::numeric_limits<double>::infinity();

// A triangulation of an n-gon: n - 2 triangles, corners ascending, each of
// the n rim edges in one triangle and each diagonal in two.
void expectTriangulates(const RimTriangulation& t, int n)
{
    ASSERT_EQ(int(t.triangles.size()), n - 2);
    std::multiset<std::pair<int, int>> edges;
    for (const auto& [i, k, j] : t.triangles) {
        EXPECT_LT(i, k);
        EXPECT_LT(k, j);
        edges.insert({i, k});
        edges.insert({k, j});
        edges.insert({i, j});
    }
    for (int i = 0; i < n; ++i) {
        const std::pair<int, int> rim = i + 1 < n ? std::pair{i, i + 1} : std::pair{0, n - 1};
        EXPECT_EQ(edges.count(rim), 1u) << rim.first << "-" << rim.second;
    }
    for (const auto& e : edges) {
        const bool onRim = e.second - e.first == 1 || (e.first == 0 && e.second == n - 1);
        if (!onRim) {
            EXPECT_EQ(edges.count(e), 2u) << e.first << "-" << e.second;
        }
    }
}

TEST(RimTriangulation, TheWorstTriangleDecidesNotTheSum)
{
    // A square: diagonal 0-2 makes triangles costing 5 and 0 (sum 5),
    // diagonal 1-3 makes two costing 3 (sum 6): the worst, 3, is better.
    const auto t = triangulateRim(4, [](int i, int k, int j) {
        if (i == 0 && k == 1 && j == 2) return 5.0;
        if (i == 0 && k == 2 && j == 3) return 0.0;
        return 3.0; // (0, 1, 3) and (1, 2, 3)
    });
    ASSERT_TRUE(t);
    expectTriangulates(*t, 4);
    EXPECT_EQ(t->worst, 3.0);
    EXPECT_EQ(t->sum, 6.0);
    const std::set<std::array<int, 3>> chosen(t->triangles.begin(), t->triangles.end());
    EXPECT_EQ(chosen, (std::set<std::array<int, 3>>{{0, 1, 3}, {1, 2, 3}}));
}

TEST(RimTriangulation, TiesGoToTheSmallerSum)
{
    const auto t = triangulateRim(4, [](int i, int k, int j) {
        if (i == 0 && k == 1 && j == 2) return 2.0;
        if (i == 0 && k == 2 && j == 3) return 0.5;
        return 2.0;
    });
    ASSERT_TRUE(t);
    EXPECT_EQ(t->worst, 2.0);
    EXPECT_EQ(t->sum, 2.5);
}

TEST(RimTriangulation, NeverUsesAForbiddenTriangle)
{
    // A hexagon whose only allowed triangles fan from corner 3.
    const auto t =
        triangulateRim(6, [](int i, int k, int j) { return (i == 3 || k == 3 || j == 3) ? 1.0 : kForbidden; });
    ASSERT_TRUE(t);
    expectTriangulates(*t, 6);
    for (const auto& tri : t->triangles)
        EXPECT_TRUE(std::find(tri.begin(), tri.end(), 3) != tri.end());
}

TEST(RimTriangulation, NothingWhereEveryTriangulationIsForbidden)
{
    EXPECT_FALSE(triangulateRim(5, [](int i, int, int j) { return j - i == 4 ? kForbidden : 1.0; }));
    EXPECT_FALSE(triangulateRim(2, [](int, int, int) { return 0.0; }));
}

TEST(RimTriangulation, FindsTheBestOfEveryTriangulationOfAHeptagon)
{
    // Costs from a fixed pseudo-random table; the best worst triangle is
    // checked against all 42 triangulations of the heptagon, enumerated.
    const auto cost = [](int i, int k, int j) { return double((i * 7919 + k * 104729 + j * 1299709) % 97); };
    const auto t = triangulateRim(7, cost);
    ASSERT_TRUE(t);
    expectTriangulates(*t, 7);
    // Every triangulation of corners i..j as its worst triangle, recursively.
    std::function<double(int, int)> bestWorst = [&](int i, int j) {
        if (j - i < 2) return 0.0;
        double best = kForbidden;
        for (int k = i + 1; k < j; ++k)
            best = std::min(best, std::max({cost(i, k, j), bestWorst(i, k), bestWorst(k, j)}));
        return best;
    };
    EXPECT_EQ(t->worst, bestWorst(0, 6));
    double worst = 0.0;
    for (const auto& [i, k, j] : t->triangles)
        worst = std::max(worst, cost(i, k, j));
    EXPECT_EQ(worst, t->worst);
}

} // namespace
} // namespace kerf::mesher

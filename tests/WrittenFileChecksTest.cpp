// The checks of an exported file as a reader gets it (mesher/src/
// SelfIntersections.cpp, WrittenCoordinates.cpp), against brute force: the
// crossing test's quick rejections against the test without them, the
// hierarchy's pairs against every pair, the weld by written coordinates
// against a map of the float32 points.

#include "TriangleClearance.hpp"

#include "kerf/mesher/SelfIntersections.hpp"
#include "kerf/mesher/WrittenCoordinates.hpp"

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <tuple>
#include <vector>

namespace kerf {
namespace {

using Tri = std::array<std::uint32_t, 3>;

// Pairs as an export's checks meet them: in one plane (a board's face, its
// corners on a lattice's lines or anywhere), nearly in one plane, sharing
// an edge, a corner or nothing, and anywhere.
TEST(WrittenFileChecks, QuickRejectionsAgreeWithTheExhaustiveCrossingTest)
{
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0), tilt(-1e-3, 1e-3);
    std::uniform_int_distribution<int> grid(-4, 4);
    int crossing = 0, apart = 0;
    for (int trial = 0; trial < 60000; ++trial) {
        const int plane = trial % 4;   // 0, 1: in z = 0 (1: corners on a grid of 0.25); 2: nearly; 3: anywhere
        const int shared = trial / 4 % 3; // corners shared by index
        auto point = [&] {
            if (plane == 1) return glm::dvec3(0.25 * grid(rng), 0.25 * grid(rng), 0.0);
            return glm::dvec3(u(rng), u(rng), plane == 3 ? u(rng) : plane == 2 ? tilt(rng) : 0.0);
        };
        glm::dvec3 a[3], b[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = point();
            b[k] = point();
        }
        Tri A{0, 1, 2}, B{3, 4, 5};
        // B's first corners are A's (by index and position), in either turn.
        for (int k = 0; k < shared; ++k) {
            const int from = trial % 2 == 0 ? k : 2 - k;
            B[std::size_t(k)] = A[std::size_t(from)];
            b[k] = a[from];
        }
        const bool expected = trianglesCrossExhaustively(A, a, B, b);
        crossing += expected;
        apart += !expected;
        ASSERT_EQ(trianglesCross(A, a, B, b), expected) << "trial " << trial;
        ASSERT_EQ(trianglesCross(B, b, A, a), trianglesCrossExhaustively(B, b, A, a)) << "trial " << trial;
    }
    EXPECT_GT(crossing, 5000);
    EXPECT_GT(apart, 5000);
}

// Clusters of small random triangles, far apart from each other, some
// corners shared within a cluster: every crossing pair lies in one cluster,
// where brute force finds them all. More triangles than the hierarchy
// builds and walks on one thread.
struct Soup {
    Mesh mesh;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> clusters; // [first, last) triangle ranges
};

Soup clusteredSoup(int clusters, int perCluster, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0), d(-0.15, 0.15);
    Soup soup;
    for (int c = 0; c < clusters; ++c) {
        const glm::dvec3 centre(10.0 * (c % 17), 10.0 * (c / 17 % 17), 10.0 * (c / 289));
        const std::uint32_t firstVertex = std::uint32_t(soup.mesh.vertices.size());
        const std::uint32_t first = std::uint32_t(soup.mesh.triangles.size());
        for (int t = 0; t < perCluster; ++t) {
            Tri tri;
            for (std::size_t k = 0; k < 3; ++k) {
                const std::uint32_t count = std::uint32_t(soup.mesh.vertices.size()) - firstVertex;
                // A third of the corners reuse one of the cluster's.
                if (count > 0 && k > 0 && u(rng) < 0.33) {
                    tri[k] = firstVertex + std::uint32_t(u(rng) * count) % count;
                    if (tri[k] != tri[0] && (k < 2 || tri[k] != tri[1])) continue;
                }
                const glm::dvec3 anchor = k == 0 ? centre + glm::dvec3(u(rng), u(rng), u(rng))
                                                 : soup.mesh.vertices[tri[0]];
                tri[k] = std::uint32_t(soup.mesh.vertices.size());
                soup.mesh.vertices.push_back(anchor + glm::dvec3(d(rng), d(rng), d(rng)));
            }
            soup.mesh.triangles.push_back(tri);
        }
        soup.clusters.emplace_back(first, std::uint32_t(soup.mesh.triangles.size()));
    }
    return soup;
}

template <class Hit>
std::vector<std::array<std::uint32_t, 2>> bruteForcePairs(const Soup& soup, Hit&& hit)
{
    std::vector<std::array<std::uint32_t, 2>> out;
    const Mesh& m = soup.mesh;
    for (const auto& [first, last] : soup.clusters)
        for (std::uint32_t s = first; s < last; ++s)
            for (std::uint32_t t = s + 1; t < last; ++t) {
                const Tri &A = m.triangles[s], &B = m.triangles[t];
                const glm::dvec3 a[3] = {m.vertices[A[0]], m.vertices[A[1]], m.vertices[A[2]]};
                const glm::dvec3 b[3] = {m.vertices[B[0]], m.vertices[B[1]], m.vertices[B[2]]};
                if (hit(A, a, B, b)) out.push_back({s, t});
            }
    return out;
}

TEST(WrittenFileChecks, TheHierarchyFindsEveryPairBruteForceFinds)
{
    const Soup soup = clusteredSoup(150, 250, 17); // 37,500 triangles
    const auto crossing = bruteForcePairs(soup, [](const Tri& A, const glm::dvec3* a, const Tri& B,
                                                   const glm::dvec3* b) { return trianglesCross(A, a, B, b); });
    constexpr double kClearance = 0.02;
    const auto close = bruteForcePairs(soup, [&](const Tri& A, const glm::dvec3* a, const Tri& B, const glm::dvec3* b) {
        return mesher::trianglesTooClose(A, a, B, b, kClearance);
    });
    ASSERT_GT(crossing.size(), 1000u);
    for (const int threads : {1, 2}) {
        tbb::task_arena arena(threads);
        arena.execute([&] {
            const SelfIntersections found = findSelfIntersections(soup.mesh, crossing.size() + 1);
            EXPECT_EQ(found.pairs, crossing.size()) << threads << " threads";
            EXPECT_EQ(found.examples, crossing) << threads << " threads";
            const SelfIntersections near = findTrianglesCloserThan(soup.mesh, kClearance, close.size() + 1);
            EXPECT_EQ(near.pairs, close.size()) << threads << " threads";
            EXPECT_EQ(near.examples, close) << threads << " threads";
            // Fewer examples than pairs: the lowest, whatever order the
            // threads met them in.
            const std::vector<std::array<std::uint32_t, 2>> lowest(crossing.begin(), crossing.begin() + 10);
            EXPECT_EQ(findSelfIntersections(soup.mesh, 10).examples, lowest) << threads << " threads";
        });
    }
    EXPECT_GT(close.size(), crossing.size());
}

// The search reports how far it is, in steps, from its threads, up to 1;
// cancelled, it stops and says so.
TEST(WrittenFileChecks, TheCrossingSearchReportsProgressAndStops)
{
    const Soup soup = clusteredSoup(600, 250, 23); // 150,000 triangles
    for (const int threads : {1, 2}) {
        tbb::task_arena arena(threads);
        arena.execute([&] {
            std::vector<double> seen;
            const SelfIntersections all =
                findSelfIntersections(soup.mesh, 0, Progress([&](double f) { seen.push_back(f); }));
            EXPECT_FALSE(all.stopped);
            ASSERT_FALSE(seen.empty());
            EXPECT_EQ(seen.back(), 1.0);
            EXPECT_GE(std::count_if(seen.begin(), seen.end(), [](double f) { return f > 0.0 && f < 1.0; }), 4)
                << threads << " threads";

            // Cancelled once the search is a quarter through.
            std::atomic<bool> quarter{false};
            const SelfIntersections part = findSelfIntersections(
                soup.mesh, 0, Progress([&](double f) { quarter = quarter || f >= 0.25; }, [&] { return quarter.load(); }));
            EXPECT_TRUE(part.stopped) << threads << " threads";
            EXPECT_LT(part.pairs, all.pairs) << threads << " threads";
        });
    }
}

// The weld of an STL reader: vertices whose float32 points are the same
// are one, numbered in the order a reader meets them.
TEST(WrittenFileChecks, ReadBackWeldsByTheFloat32Points)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-500.0, 500.0), tiny(-1e-6, 1e-6);
    std::uniform_int_distribution<int> pick(0, 2999);
    std::vector<glm::dvec3> points(3000);
    for (glm::dvec3& p : points)
        p = glm::dvec3(u(rng), u(rng), u(rng));
    Mesh mesh;
    for (int v = 0; v < 20000; ++v) {
        // The same point again, or one that rounds to the same float32 (or
        // to its neighbour: a millionth of a millimetre at 500 mm is below
        // float32's step there, 3e-5 mm, most of the time).
        const glm::dvec3 p = points[std::size_t(pick(rng))];
        mesh.vertices.push_back(v % 3 == 0 ? p : p + glm::dvec3(tiny(rng), tiny(rng), tiny(rng)));
    }
    std::uniform_int_distribution<std::uint32_t> any(0, 19999);
    for (int t = 0; t < 30000; ++t)
        mesh.triangles.push_back({any(rng), any(rng), any(rng)});
    const glm::dvec3 offset(12.5, -3.0, 0.0);

    // The reader: a map from the float32 point to the first number given.
    std::map<std::tuple<float, float, float>, std::uint32_t> seen;
    std::vector<std::uint32_t> number(mesh.vertices.size());
    std::vector<glm::dvec3> expected;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const glm::dvec3 local = mesh.vertices[v] - offset;
        const auto key = std::make_tuple(float(local.x), float(local.y), float(local.z));
        const auto [it, added] = seen.emplace(key, std::uint32_t(expected.size()));
        if (added)
            expected.push_back(glm::dvec3(double(std::get<0>(key)), double(std::get<1>(key)),
                                          double(std::get<2>(key))) +
                               offset);
        number[v] = it->second;
    }
    ASSERT_LT(expected.size(), 19000u); // welds happened
    ASSERT_GT(expected.size(), 3000u);  // and not only of equal doubles

    const Mesh read = readBack(mesh, WrittenFormat::Float32, true, offset);
    ASSERT_EQ(read.vertices.size(), expected.size());
    for (std::size_t v = 0; v < expected.size(); ++v)
        ASSERT_EQ(read.vertices[v], expected[v]) << v;
    ASSERT_EQ(read.triangles.size(), mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::size_t k = 0; k < 3; ++k)
            ASSERT_EQ(read.triangles[t][k], number[mesh.triangles[t][k]]) << t;

    // Without the weld (3MF keeps its indices): every vertex, in its order.
    const Mesh kept = readBack(mesh, WrittenFormat::Float32, false, offset);
    ASSERT_EQ(kept.vertices.size(), mesh.vertices.size());
    EXPECT_EQ(kept.triangles, mesh.triangles);
}

// Far from the origin float32 writes whole regions of a part to one point:
// the weld takes the vertices of one point together, each numbered as the
// first written there, in a sort (compared pairwise, these three runs of
// 66,667 equal points would be 6.7 billion comparisons).
// A 3MF coordinate as a reader gets it: lib3mf prints the float32 value
// with "%f" and the reader parses the decimals. The fast conversion must
// give exactly what printf and strtod give, for every magnitude a part
// reaches, negative ones, the values halfway between two sixth decimals
// (printf rounds them to even) and those that round to zero.
TEST(WrittenFileChecks, SixDecimalsAreWhatPrintfAndStrtodGive)
{
    auto reference = [](double x) {
        char text[64];
        std::snprintf(text, sizeof text, "%f", double(float(x)));
        return std::strtod(text, nullptr);
    };
    std::mt19937_64 random(11);
    std::vector<double> values = {0.0, -0.0, 0.0000005, -0.0000005, 0.0000015, 0.0000025, 1.0000005, 2.5e-7,
                                  123.4567895, 99999999.0, -1e8, 3.4e38, 1e-30};
    for (int e = -8; e <= 9; ++e)
        for (int i = 0; i < 20000; ++i) {
            const double x = std::ldexp(std::uniform_real_distribution<double>(0.5, 1.0)(random),
                                        int(std::lround(e * 3.3219)));
            values.push_back(i % 2 ? -x : x);
            // Halfway between two sixth decimals, as near as float32 gets.
            values.push_back(std::round(x * 1e6) / 1e6 + 5e-7);
        }
    std::size_t differ = 0;
    for (const double x : values) {
        const double fast = writtenCoordinate(x, WrittenFormat::Float32SixDecimals), slow = reference(x);
        if (!(fast == slow) || std::signbit(fast) != std::signbit(slow)) {
            if (++differ < 5) ADD_FAILURE() << x << ": " << fast << " against " << slow;
        }
    }
    EXPECT_EQ(differ, 0u) << "of " << values.size();
    EXPECT_EQ(writtenCoordinate(1.5, WrittenFormat::Float32), 1.5);
}

TEST(WrittenFileChecks, ReadBackWeldsManyVerticesWrittenToFewPoints)
{
    Mesh mesh;
    const glm::dvec3 far(1e9, 0.0, 0.0); // float32's step there: 64 mm
    for (int v = 0; v < 200000; ++v)
        mesh.vertices.push_back(far + glm::dvec3(double(v % 3) * 100.0 + 1e-3 * double(v % 1000), 0.0, 0.0));
    for (std::uint32_t v = 0; v + 2 < mesh.vertices.size(); v += 3)
        mesh.triangles.push_back({v, v + 1, v + 2});
    const Mesh read = readBack(mesh, WrittenFormat::Float32, true);
    ASSERT_EQ(read.vertices.size(), 3u); // 1e9, 1e9 + 128 and 1e9 + 192 mm
    for (std::size_t t = 0; t < read.triangles.size(); ++t)
        ASSERT_EQ(read.triangles[t], (Tri{0, 1, 2})) << t;
}

// A mesh that writing does not break is only compacted: the vertices the
// triangles use, in the order they first use them, nothing moved.
TEST(WrittenFileChecks, AMeshWritingDoesNotBreakIsOnlyCompacted)
{
    // Away from 0, where float32's step (8e-6 mm at 100 mm) is larger
    // than a nanometre.
    const glm::dvec3 o(100.0);
    Mesh tetrahedron;
    tetrahedron.vertices = {o, o + 7.0, o + glm::dvec3(10, 0, 0), o + glm::dvec3(0, 10, 0), o + glm::dvec3(0, 0, 10)};
    tetrahedron.triangles = {{3, 2, 0}, {2, 4, 0}, {4, 3, 0}, {2, 3, 4}}; // vertex 1 unused
    const WrittenFit fit = fitToWritten(tetrahedron, WrittenFormat::Float32);
    EXPECT_EQ(fit.collapses, 0u);
    EXPECT_EQ(fit.nudges, 0u);
    EXPECT_EQ(fit.unresolved, 0u);
    EXPECT_EQ(fit.largestMove, 0.0);
    const std::vector<glm::dvec3> corners = {o + glm::dvec3(0, 10, 0), o + glm::dvec3(10, 0, 0), o,
                                             o + glm::dvec3(0, 0, 10)};
    EXPECT_EQ(tetrahedron.vertices, corners);
    const std::vector<Tri> faces = {{0, 1, 2}, {1, 3, 2}, {3, 0, 2}, {1, 0, 3}};
    EXPECT_EQ(tetrahedron.triangles, faces);

    // Its edge (0, 1) split a nanometre from corner 0: the two round to one
    // float32 point, and the edge between them is collapsed.
    Mesh pinched = tetrahedron;
    pinched.vertices.push_back(corners[0] + 1e-9 * glm::normalize(corners[1] - corners[0]));
    pinched.triangles = {{0, 4, 2}, {4, 1, 2}, {1, 3, 2}, {3, 0, 2}, {1, 4, 3}, {4, 0, 3}};
    const WrittenFit mended = fitToWritten(pinched, WrittenFormat::Float32);
    EXPECT_EQ(mended.collapses, 1u);
    EXPECT_EQ(mended.nudges, 0u);
    EXPECT_EQ(mended.unresolved, 0u);
    EXPECT_EQ(pinched.triangles.size(), 4u);
    EXPECT_EQ(pinched.vertices.size(), 4u);
}

} // namespace
} // namespace kerf

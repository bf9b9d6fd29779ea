// The clearance guard of simplification and refinement
// (mesher/src/TriangleClearance.hpp): distances against brute force, and
// the touching configuration that the crossing test alone let through.

#include "TriangleClearance.hpp"

#include "kerf/mesher/SelfIntersections.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <random>

namespace kerf::mesher {
namespace {

// The least distance between points of the two sets, sampled finely: an
// upper bound of the true distance, close to it.
double sampledDistance(const glm::dvec3* a, int na, const glm::dvec3* b, int nb)
{
    auto points = [](const glm::dvec3* v, int n) {
        std::vector<glm::dvec3> out;
        constexpr int k = 60;
        if (n == 2) {
            for (int i = 0; i <= k; ++i)
                out.push_back(v[0] + (v[1] - v[0]) * (double(i) / k));
        } else {
            for (int i = 0; i <= k; ++i)
                for (int j = 0; i + j <= k; ++j)
                    out.push_back(v[0] + (v[1] - v[0]) * (double(i) / k) + (v[2] - v[0]) * (double(j) / k));
        }
        return out;
    };
    double best = 1e300;
    for (const glm::dvec3& p : points(a, na))
        for (const glm::dvec3& q : points(b, nb))
            best = std::min(best, glm::length(p - q));
    return best;
}

TEST(TriangleClearance, DistancesAgreeWithSampling)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto point = [&] { return glm::dvec3(u(rng), u(rng), u(rng)); };
    for (int trial = 0; trial < 200; ++trial) {
        const glm::dvec3 t[3] = {point(), point(), point()};
        const glm::dvec3 s[2] = {point() + glm::dvec3(0.5), point()};
        const double exact = segmentTriangleDistance(s[0], s[1], t[0], t[1], t[2]);
        const double sampled = sampledDistance(s, 2, t, 3);
        // Sampling overestimates by at most a sample spacing (the edges
        // here are at most about 3.5 long: 3.5 / 60).
        EXPECT_LE(exact, sampled + 1e-12) << trial;
        EXPECT_GE(exact, sampled - 0.06) << trial;
        const glm::dvec3 r[2] = {point(), point()};
        const double segments = segmentSegmentDistance(s[0], s[1], r[0], r[1]);
        EXPECT_LE(segments, sampledDistance(s, 2, r, 2) + 1e-12) << trial;
        EXPECT_GE(segments, sampledDistance(s, 2, r, 2) - 0.06) << trial;
    }
}

// The quick plane test around a shared vertex: whenever it says a segment
// clears a triangle, the exact distance says so too; and it does decide the
// common cases it is there for (a neighbour's far edge on a gently curved
// sheet, and on the same flat face).
TEST(TriangleClearance, TheQuickPlaneTestNeverClearsWhatIsClose)
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0), scale(1e-6, 1.0);
    auto point = [&] { return glm::dvec3(u(rng), u(rng), u(rng)); };
    int cleared = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const glm::dvec3 t[3] = {point(), point(), point()};
        // Half the segments start at one of t's corners (a shared vertex),
        // some nearly in t's plane (the flat face's neighbours).
        glm::dvec3 p = point(), q = point();
        if (trial % 2 == 0) p = t[trial % 3];
        if (trial % 4 < 2) {
            const glm::dvec3 n = glm::normalize(glm::cross(t[1] - t[0], t[2] - t[0]));
            q -= n * glm::dot(n, q - t[0]) * (1.0 - 1e-3 * u(rng));
        }
        const double clearance = scale(rng) * scale(rng);
        if (segmentClearOf(p, q, t, clearance)) {
            ++cleared;
            EXPECT_GT(segmentTriangleDistance(p, q, t[0], t[1], t[2]), clearance) << trial;
        }
    }
    EXPECT_GT(cleared, 2000); // it decides many of them (3,682 of these)

    // A strip of a cylinder of radius 20 (2 mm triangles around a shared
    // vertex) and two neighbours on one flat face: cleared by the quick test.
    const double clearance = 2.4e-4;
    auto onCylinder = [](double angle, double z) { return glm::dvec3(20.0 * std::cos(angle), 20.0 * std::sin(angle), z); };
    const glm::dvec3 s[3] = {onCylinder(0.0, 0.0), onCylinder(0.1, 0.0), onCylinder(0.0, 2.0)};
    // The neighbour (s[1], at 0.2 low, at 0.2 high): its edge away from s[1].
    EXPECT_TRUE(segmentClearOf(onCylinder(0.2, 0.0), onCylinder(0.2, 2.0), s, clearance));
    const glm::dvec3 f[3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    // The neighbour ((2, 0, 0), (4, -1, 0), (3, 1.5, 0)) on f's face.
    EXPECT_TRUE(segmentClearOf({4, -1, 0}, {3, 1.5, 0}, f, clearance));
    EXPECT_FALSE(segmentClearOf({2, 0, 0}, {2, -2, 0}, f, clearance)); // touches f's corner
    // The far edge of a neighbour folded back over the triangle: not cleared.
    EXPECT_FALSE(segmentClearOf({0.5, 0.5, 1e-5}, {0.2, 1.2, 1e-5}, f, clearance));
}

TEST(TriangleClearance, ParallelAndDegenerateCases)
{
    const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    EXPECT_DOUBLE_EQ(pointTriangleDistance(glm::dvec3(0.25, 0.25, 0.3), a, b, c), 0.3);
    EXPECT_DOUBLE_EQ(pointTriangleDistance(glm::dvec3(2, 0, 0), a, b, c), 1.0);
    // A segment parallel to the plane above it, and one through it.
    EXPECT_DOUBLE_EQ(segmentTriangleDistance(glm::dvec3(0.1, 0.1, 0.5), glm::dvec3(0.2, 0.2, 0.5), a, b, c), 0.5);
    EXPECT_NEAR(segmentTriangleDistance(glm::dvec3(0.2, 0.2, -1), glm::dvec3(0.2, 0.2, 1), a, b, c), 0.0, 1e-15);
    // Parallel segments.
    EXPECT_DOUBLE_EQ(segmentSegmentDistance(glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0.5, 0.2, 0),
                                            glm::dvec3(2, 0.2, 0)),
                     0.2);
    // A triangle without area.
    EXPECT_NEAR(pointTriangleDistance(glm::dvec3(0.5, 1, 0), a, b, glm::dvec3(2, 0, 0)), 1.0, 1e-12);
}

TEST(TriangleClearance, SharedVerticesAreNotContacts)
{
    // Two triangles of a fan around vertex 0, apart by 90 degrees: the
    // shared vertex is no contact; the edges away from it are far.
    const std::array<std::uint32_t, 3> A{0, 1, 2}, B{0, 3, 4};
    const glm::dvec3 a[3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
    const glm::dvec3 b[3] = {{0, 0, 0}, {-1, 1, 0}, {-1, 0, 0}};
    EXPECT_FALSE(trianglesTooClose(A, a, B, b, 0.01));
    // Neighbours across an edge are the crossing test's alone.
    const std::array<std::uint32_t, 3> C{1, 0, 5};
    const glm::dvec3 cc[3] = {{1, 0, 0}, {0, 0, 0}, {0.5, -1, 0}};
    EXPECT_FALSE(trianglesTooClose(A, a, C, cc, 0.01));
    // A fan triangle whose far edge passes within 1e-4 of the other.
    const glm::dvec3 near[3] = {{0, 0, 0}, {1, 1e-4, 0.5}, {1, 1e-4, -0.5}};
    const std::array<std::uint32_t, 3> D{0, 6, 7};
    const glm::dvec3 flat[3] = {{0, 0, 0}, {2, 0, 0}, {2, -1, 0}};
    EXPECT_TRUE(trianglesTooClose(D, near, std::array<std::uint32_t, 3>{0, 8, 9}, flat, 1e-3));
    EXPECT_FALSE(trianglesTooClose(D, near, std::array<std::uint32_t, 3>{0, 8, 9}, flat, 1e-5));
}

TEST(TriangleClearance, TheTableTopsTouchingPairIsTooClose)
{
    // Two triangles of the table top's simplified mesh at 4 mm and 0.1 mm
    // (a face triangle of the underside and a sliver at a mortise's corner,
    // in double as the simplification left them): the sliver's edge lies
    // in the face's plane and runs across the face's edge. The crossing
    // test calls this apart in double and crossing once the coordinates are
    // float32; the clearance guard refuses it either way.
    const std::array<std::uint32_t, 3> A{0, 1, 2}, B{3, 4, 5};
    const glm::dvec3 a[3] = {{-729.60009765625, -380, 0}, {-756, -440, 0}, {-732, -376, 0}};
    const glm::dvec3 b[3] = {
        {-730.5, -378.37507629394531, 0}, {-730.25, -379.06255340576172, 0}, {-729.800048828125, -380, 0.0625}};
    EXPECT_FALSE(trianglesCross(A, a, B, b));
    glm::dvec3 rounded[3];
    for (int k = 0; k < 3; ++k)
        rounded[k] = glm::dvec3(glm::vec3(b[k]));
    EXPECT_TRUE(trianglesCross(A, a, B, rounded));
    const double clearance = 4.0 * 6.103515625e-05; // four float32 spacings at 1,000 mm
    EXPECT_TRUE(trianglesTooClose(A, a, B, b, clearance));
    EXPECT_TRUE(trianglesTooClose(A, a, B, rounded, clearance));
}

TEST(TriangleClearance, ZeroClearanceIsTheCrossingTest)
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const std::array<std::uint32_t, 3> A{0, 1, 2}, B{3, 4, 5};
    int crossing = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        glm::dvec3 a[3], b[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = glm::dvec3(u(rng), u(rng), u(rng));
            b[k] = glm::dvec3(u(rng), u(rng), u(rng));
        }
        const bool cross = trianglesCross(A, a, B, b);
        crossing += cross;
        EXPECT_EQ(trianglesTooClose(A, a, B, b, 0.0), cross) << trial;
        // A clearance refuses at least what crossing does.
        if (cross) {
            EXPECT_TRUE(trianglesTooClose(A, a, B, b, 0.01)) << trial;
        }
    }
    EXPECT_GT(crossing, 100); // the cases include crossing pairs
}

// The quick rejections (a plane, or an edge within one triangle's plane,
// with the other beyond it by the margin) never let a pair through that
// the distances refuse: random pairs in one plane (a flat face's
// neighbours, where every pair passes the plane test), nearly in one plane,
// and anywhere, against the crossing test and the six edge-triangle
// distances alone.
TEST(TriangleClearance, QuickRejectionsAgreeWithTheDistances)
{
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1.0, 1.0), c(0.0, 0.4), tilt(-1e-3, 1e-3);
    const std::array<std::uint32_t, 3> A{0, 1, 2}, B{3, 4, 5};
    auto reference = [&](const glm::dvec3* a, const glm::dvec3* b, double clearance) {
        if (trianglesCross(A, a, B, b)) return true;
        for (int i = 0; i < 3; ++i)
            if (segmentTriangleDistance(a[i], a[(i + 1) % 3], b[0], b[1], b[2]) < clearance ||
                segmentTriangleDistance(b[i], b[(i + 1) % 3], a[0], a[1], a[2]) < clearance)
                return true;
        return false;
    };
    int refused = 0, clear = 0;
    for (int trial = 0; trial < 30000; ++trial) {
        const int kind = trial % 3; // in one plane, nearly, anywhere
        glm::dvec3 a[3], b[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = glm::dvec3(u(rng), u(rng), kind == 2 ? u(rng) : 0.0);
            b[k] = glm::dvec3(u(rng) + 1.0, u(rng), kind == 2 ? u(rng) : kind == 1 ? tilt(rng) : 0.0);
        }
        const double clearance = c(rng);
        const bool expected = reference(a, b, clearance);
        refused += expected;
        clear += !expected;
        ASSERT_EQ(trianglesTooClose(A, a, B, b, clearance), expected) << trial << " clearance " << clearance;
    }
    EXPECT_GT(refused, 3000);
    EXPECT_GT(clear, 3000);
}

} // namespace
} // namespace kerf::mesher

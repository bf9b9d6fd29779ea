// The accuracy metrics `kerf bench` reports, on cases with known answers:
// error summaries, picture comparison (an image against itself, a known
// shift, hand-made pixels), the mesh's distance to the exact surface (a
// sphere against its closed form, a box's exact distances, a CSG crease
// where |f| is only a lower bound) and the exact volume integral (closed
// forms within the stated uncertainty).

#include "kerf/accuracy/ErrorStats.hpp"
#include "kerf/accuracy/ExactVolume.hpp"
#include "kerf/accuracy/ImageError.hpp"
#include "kerf/accuracy/SurfaceDistance.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/tracer/ExactTracer.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

namespace kerf {
namespace {

Tape tapeOf(const std::string& root)
{
    return compileTape(Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf"));
}

std::string sphere(double radius, const glm::dvec3& at = glm::dvec3(0.0), const std::string& id = "s")
{
    return R"({"id":")" + id + R"(","type":"sphere","radius":)" + std::to_string(radius) +
           R"(,"transform":{"translate":[)" + std::to_string(at.x) + "," + std::to_string(at.y) + "," +
           std::to_string(at.z) + "]}}";
}

TEST(ErrorStats, MeanNearestRankPercentileAndMax)
{
    std::vector<double> v(100);
    std::iota(v.begin(), v.end(), 1.0); // 1..100
    std::reverse(v.begin(), v.end());
    const ErrorStats s = summarizeErrors(v);
    EXPECT_EQ(s.count, 100u);
    EXPECT_DOUBLE_EQ(s.mean, 50.5);
    EXPECT_DOUBLE_EQ(s.p99, 99.0);
    EXPECT_DOUBLE_EQ(s.max, 100.0);

    std::vector<double> one{7.0};
    const ErrorStats t = summarizeErrors(one);
    EXPECT_DOUBLE_EQ(t.p99, 7.0);
    std::vector<double> none;
    const ErrorStats u = summarizeErrors(none);
    EXPECT_EQ(u.count, 0u);
    EXPECT_EQ(u.max, 0.0);
}

TEST(ImageError, HandMadePixelsGiveTheirErrors)
{
    TraceImage a(2, 2), b(2, 2);
    // Pixel 0: both hit, 0.5 mm apart, normals 90 degrees apart.
    a.depth[0] = 10.0f;
    b.depth[0] = 10.5f;
    a.normal[0] = {1, 0, 0};
    b.normal[0] = {0, 1, 0};
    // Pixel 1: both hit, same depth, normals 60 degrees apart (unnormalised on purpose).
    a.depth[1] = b.depth[1] = 20.0f;
    a.normal[1] = {2, 0, 0};
    b.normal[1] = {0.5f, float(std::sqrt(3.0) / 2.0), 0};
    // Pixel 2: only the image hits; pixel 3: only the reference.
    a.depth[2] = 5.0f;
    a.normal[2] = {0, 0, 1};
    b.depth[3] = 5.0f;
    b.normal[3] = {0, 0, 1};
    const ImageError e = compareImages(a, b);
    EXPECT_EQ(e.pixels, 4u);
    EXPECT_EQ(e.bothHit, 2u);
    EXPECT_EQ(e.onlyImage, 1u);
    EXPECT_EQ(e.onlyReference, 1u);
    EXPECT_DOUBLE_EQ(e.mismatchFraction(), 0.5);
    EXPECT_DOUBLE_EQ(e.depthMm.max, 0.5);
    EXPECT_DOUBLE_EQ(e.depthMm.mean, 0.25);
    EXPECT_NEAR(e.normalDegrees.max, 90.0, 1e-4);
    EXPECT_NEAR(e.normalDegrees.mean, 75.0, 1e-4);

    EXPECT_THROW(compareImages(TraceImage(2, 2), TraceImage(2, 3)), std::invalid_argument);
}

TEST(ImageError, AnExactImageAgainstItselfHasNoError)
{
    const Tape tape = tapeOf(sphere(10.0));
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 64, 48);
    const TraceImage image = traceExact(tape, camera, 1e-4, 2);
    const ImageError e = compareImages(image, image);
    EXPECT_GT(e.bothHit, 300u);
    EXPECT_EQ(e.onlyImage + e.onlyReference, 0u);
    EXPECT_EQ(e.depthMm.max, 0.0);
    EXPECT_EQ(e.normalDegrees.max, 0.0);
}

TEST(ImageError, ASphereMovedAlongTheViewIsOffByTheMove)
{
    // An orthographic front view looks along +y: moving the sphere by 0.75 mm
    // along y moves every hit 0.75 mm deeper and leaves normals and silhouette alone.
    const Tape near = tapeOf(sphere(10.0)), far = tapeOf(sphere(10.0, {0.0, 0.75, 0.0}));
    const Aabb frame{glm::dvec3(-11.0), glm::dvec3(11.0)};
    const Camera camera = Camera::standardView(frame, "front", 80, 80, Projection::Orthographic);
    const ImageError e = compareImages(traceExact(far, camera, 1e-6, 2), traceExact(near, camera, 1e-6, 2));
    EXPECT_GT(e.bothHit, 2000u);
    EXPECT_EQ(e.onlyImage + e.onlyReference, 0u);
    EXPECT_NEAR(e.depthMm.mean, 0.75, 1e-4);
    EXPECT_NEAR(e.depthMm.max, 0.75, 1e-4);
    EXPECT_GT(e.depthMm.p99, 0.749);
    EXPECT_LT(e.normalDegrees.max, 0.1);
}

// The sampled points, as SurfaceDistance.hpp lists them, with the sphere's
// closed-form distance ||p| - r|.
struct SphereTruth {
    double max = 0.0, mean = 0.0;
};
SphereTruth sphereTruth(const Mesh& mesh, double r)
{
    auto d = [&](const glm::dvec3& p) { return std::abs(glm::length(p) - r); };
    SphereTruth t;
    double weighted = 0.0, area = 0.0;
    for (const glm::dvec3& v : mesh.vertices)
        t.max = std::max(t.max, d(v));
    for (const auto& tri : mesh.triangles) {
        const glm::dvec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
        const double mids[3] = {d(0.5 * (a + b)), d(0.5 * (b + c)), d(0.5 * (c + a))};
        const double centre = d((a + b + c) / 3.0);
        t.max = std::max({t.max, mids[0], mids[1], mids[2], centre});
        const double w = 0.5 * glm::length(glm::cross(b - a, c - a));
        weighted +=
            w * ((d(a) + d(b) + d(c)) / 20.0 + (mids[0] + mids[1] + mids[2]) * 2.0 / 15.0 + centre * 9.0 / 20.0);
        area += w;
    }
    t.mean = weighted / area;
    return t;
}

TEST(SurfaceDistance, ASphereMeshMatchesTheClosedForm)
{
    const double r = 10.0;
    const Tape tape = tapeOf(sphere(r));
    MeshOptions options;
    options.featureSize = 0.8;
    options.threads = 2;
    const Mesh mesh = *meshTape(tape, options);
    const SphereTruth truth = sphereTruth(mesh, r);
    const SurfaceDistance d = measureSurfaceDistance(mesh, tape, 2);
    EXPECT_EQ(d.unresolved, 0u);
    EXPECT_EQ(d.samples, mesh.vertices.size() + 4 * mesh.triangles.size());
    // The sphere's field is an exact distance: both bounds are the distance.
    EXPECT_NEAR(d.max, truth.max, 2e-6);
    EXPECT_NEAR(d.maxLowerBound, truth.max, 1e-9);
    EXPECT_NEAR(d.mean, truth.mean, 2e-6);
    // Chords of a 10 mm sphere across 0.8 mm cells sag by a few micrometres to tens of them.
    EXPECT_GT(truth.max, 1e-3);
    EXPECT_LT(truth.max, 0.1);
    EXPECT_LT(d.vertexMax, 1e-5); // vertices are root-found on the surface
    EXPECT_NEAR(d.area, 4.0 * std::numbers::pi * r * r, 0.01 * 4.0 * std::numbers::pi * r * r);

    // The same figures whatever the thread count.
    const SurfaceDistance one = measureSurfaceDistance(mesh, tape, 1);
    EXPECT_EQ(one.max, d.max);
    EXPECT_EQ(one.mean, d.mean);
}

TEST(SurfaceDistance, PointsAtKnownDistancesFromABox)
{
    // Box 20 x 10 x 6 centred at the origin: its field is the exact distance.
    const Tape tape = tapeOf(R"({"id":"b","type":"box","size":[20,10,6]})");
    const std::vector<glm::dvec3> points{
        {13.0, 0.0, 0.0}, // 3 mm off the +x face
        {0.0, 0.0, -2.0}, // inside, 1 mm under the -z face
        {12.0, 9.0, 0.0}, // off the +x+y edge: sqrt(2^2 + 4^2)
        {11.0, 6.0, 4.0}, // off the corner: sqrt(1 + 1 + 1)
        {10.0, 1.0, 1.0}, // on the +x face
    };
    const double truth[] = {3.0, 1.0, std::sqrt(20.0), std::sqrt(3.0), 0.0};
    const std::vector<PointDistance> d = distancesToSurface(tape, points);
    for (std::size_t i = 0; i < points.size(); ++i) {
        SCOPED_TRACE(i);
        ASSERT_TRUE(d[i].resolved);
        EXPECT_NEAR(d[i].lower, truth[i], 1e-9);
        EXPECT_NEAR(d[i].upper, truth[i], 2e-6);
    }
}

TEST(SurfaceDistance, AtACreaseTheFieldIsOnlyALowerBoundAndTheWalkFindsTheDistance)
{
    // Two spheres of radius 10 at x = -6 and x = +6 meet on a crease circle of
    // radius 8 in the plane x = 0. Inside the union just under the crease,
    // |f| (0.08 mm) understates the distance to the surface (0.1 mm: the
    // nearest surface point is the crease's, each sphere's own nearest point
    // lying inside the other). The walk's end is a surface point near the
    // crease, not the nearest one: its bound is sound and within about 10%.
    const Tape tape = tapeOf(R"({"id":"u","type":"union","children":[)" + sphere(10.0, {-6.0, 0.0, 0.0}, "a") + "," +
                             sphere(10.0, {6.0, 0.0, 0.0}, "b") + "]}");
    const glm::dvec3 p(0.0, 0.0, 7.9);
    const double lower = 10.0 - std::sqrt(36.0 + 7.9 * 7.9);
    const PointDistance d = distancesToSurface(tape, {p})[0];
    ASSERT_TRUE(d.resolved);
    EXPECT_NEAR(d.lower, lower, 1e-12);
    EXPECT_LT(d.lower, 0.09);
    EXPECT_GE(d.upper, 0.1 - 1e-9); // an upper bound is never below the distance
    EXPECT_LT(d.upper, 0.12);
}

TEST(SurfaceDistance, InAHolesMouthTheWalkIsStuckAndAMarchFindsTheRim)
{
    // A 20 x 20 x 10 block with a hole of radius 2 that pierces its bottom
    // face (z = -5) by 1 mm. On the bottom plane inside the hole, 0.75 mm off
    // the axis, the field is 1 (the hole's cap, 1 mm below) and steps along
    // its gradient go back and forth between the cap and the face; the
    // surface nearest is the hole's rim, 1.25 mm away.
    const Tape tape = tapeOf(R"({"id":"d","type":"difference","children":[
        {"id":"b","type":"box","size":[20,20,10]},
        {"id":"h","type":"cylinder","radius":2,"height":8,"transform":{"translate":[0,0,-2]}}]})");
    const PointDistance d = distancesToSurface(tape, {glm::dvec3(0.75, 0.0, -5.0)})[0];
    ASSERT_TRUE(d.resolved);
    EXPECT_NEAR(d.lower, 1.0, 1e-12);
    EXPECT_GE(d.upper, 1.25 - 1e-9);
    EXPECT_LT(d.upper, 1.25 + 1e-5);
}

TEST(SurfaceDistance, AnEmptyPartResolvesNothing)
{
    const Tape empty =
        tapeOf(R"({"id":"u","type":"union","children":[{"id":"a","type":"sphere","radius":5,"visible":false}]})");
    const PointDistance d = distancesToSurface(empty, {glm::dvec3(1.0)})[0];
    EXPECT_FALSE(d.resolved);
}

TEST(ExactVolume, AnAlignedBoxIsDecidedExactly)
{
    // The box's faces lie on cell planes: interval arithmetic decides every
    // cell but those along the faces, whose samples are all inside.
    const Tape tape = tapeOf(R"({"id":"b","type":"box","size":[10,20,30]})");
    const VolumeEstimate v = integrateVolume(tape, 1.0, 2);
    EXPECT_DOUBLE_EQ(v.volume, 6000.0);
    EXPECT_EQ(v.uncertainty, 0.0);
    EXPECT_GT(v.provenInside, 0.5 * 6000.0);
}

TEST(ExactVolume, ASphereLiesWithinTheStatedUncertainty)
{
    const double r = 10.0, exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const Tape tape = tapeOf(sphere(r, {0.3, -0.2, 0.1}));
    for (double cell : {1.0, 0.5, 0.25}) {
        SCOPED_TRACE(cell);
        const VolumeEstimate v = integrateVolume(tape, cell, 2);
        EXPECT_GT(v.uncertainty, 0.0);
        EXPECT_LT(std::abs(v.volume - exact), v.uncertainty);
        // Proven inside, plus what was sampled, brackets the truth with certainty.
        EXPECT_LT(v.provenInside, exact);
        EXPECT_GT(v.provenInside + v.undecided, exact);
    }
    // The uncertainty shrinks about as the square of the cell size.
    const double coarse = integrateVolume(tape, 1.0, 2).uncertainty, fine = integrateVolume(tape, 0.25, 2).uncertainty;
    EXPECT_LT(fine, coarse / 8.0);
}

TEST(ExactVolume, TheThreadCountChangesNothing)
{
    const Tape tape = tapeOf(R"({"id":"u","type":"union","blend":2,"children":[)" + sphere(5.0, {-3.0, 0.0, 0.0}, "a") +
                             "," + sphere(4.0, {3.0, 1.0, 0.0}, "b") + "]}");
    const VolumeEstimate one = integrateVolume(tape, 0.5, 1), two = integrateVolume(tape, 0.5, 2);
    EXPECT_EQ(one.volume, two.volume);
    EXPECT_EQ(one.uncertainty, two.uncertainty);
    EXPECT_THROW(integrateVolume(tape, 0.0), std::invalid_argument);
}

} // namespace
} // namespace kerf

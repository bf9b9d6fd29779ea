// The viewport's camera navigation (tracer/ViewController.hpp): standard
// views agree with Camera::standardView, zoom keeps the point under the
// cursor in place, orbit keeps its pivot in place, pan follows the cursor;
// and the single exact ray used for picking and measuring.

#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/tracer/ViewController.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

namespace kerf {
namespace {

constexpr int kW = 800, kH = 600;

// Pixel position of a world point in `camera`'s image.
glm::dvec2 project(const Camera& c, const glm::dvec3& p)
{
    const glm::dvec3 d = p - c.eye();
    const double z = glm::dot(d, c.forward());
    const double aspect = double(c.width()) / double(c.height());
    double u, v;
    if (c.projection() == Projection::Perspective) {
        u = glm::dot(d, c.right()) / (z * c.halfHeight());
        v = glm::dot(d, c.up()) / (z * c.halfHeight());
    } else {
        u = glm::dot(d, c.right()) / c.halfHeight();
        v = glm::dot(d, c.up()) / c.halfHeight();
    }
    return {(u / aspect + 1.0) * 0.5 * c.width(), (1.0 - v) * 0.5 * c.height()};
}

const Aabb kBox{{-200, -150, 0}, {250, 150, 900}};

TEST(ViewController, StandardViewsLookLikeTheHeadlessOnes)
{
    for (const char* name : {"iso", "front", "back", "left", "right", "top", "bottom"}) {
        ViewController v;
        v.setStandardView(name, kBox, double(kW) / kH);
        const Camera mine = v.camera(kW, kH);
        const Camera reference = Camera::standardView(kBox, name, kW, kH);
        EXPECT_LT(glm::length(mine.forward() - reference.forward()), 1e-9) << name;
        EXPECT_LT(glm::length(mine.up() - reference.up()), 1e-9) << name;
        // The whole box is in the picture.
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p(c & 1 ? kBox.max.x : kBox.min.x, c & 2 ? kBox.max.y : kBox.min.y,
                               c & 4 ? kBox.max.z : kBox.min.z);
            const glm::dvec2 px = project(mine, p);
            EXPECT_GE(px.x, 0.0) << name;
            EXPECT_LE(px.x, kW) << name;
            EXPECT_GE(px.y, 0.0) << name;
            EXPECT_LE(px.y, kH) << name;
        }
    }
    ViewController v;
    EXPECT_THROW(v.setStandardView("sideways", kBox, 1.0), std::invalid_argument);
}

TEST(ViewController, ZoomKeepsThePointUnderTheCursor)
{
    for (Projection projection : {Projection::Perspective, Projection::Orthographic}) {
        ViewController v;
        v.setStandardView("iso", kBox, double(kW) / kH);
        v.setProjection(projection);
        const glm::dvec3 p(120, -40, 700);
        const glm::dvec2 before = project(v.camera(kW, kH, kBox), p);
        const double d0 = v.distance();
        v.zoom(0.5, p);
        EXPECT_NEAR(v.distance(), 0.5 * d0, 1e-9 * d0);
        const glm::dvec2 after = project(v.camera(kW, kH, kBox), p);
        EXPECT_NEAR(after.x, before.x, 1e-6);
        EXPECT_NEAR(after.y, before.y, 1e-6);
    }
}

TEST(ViewController, OrbitKeepsItsPivotAndClampsPitch)
{
    ViewController v;
    v.setStandardView("front", kBox, double(kW) / kH);
    const glm::dvec3 pivot(100, -150, 300);
    const glm::dvec2 before = project(v.camera(kW, kH), pivot);
    v.orbit(37.0, -21.0, pivot);
    const glm::dvec2 after = project(v.camera(kW, kH), pivot);
    EXPECT_NEAR(after.x, before.x, 1e-6);
    EXPECT_NEAR(after.y, before.y, 1e-6);
    v.orbit(0.0, 10000.0);
    EXPECT_EQ(v.pitchDegrees(), 90.0);
    EXPECT_NO_THROW(v.camera(kW, kH)); // looking straight down is well defined
    // Dragging right turns the part to the right: the eye moves to its left.
    ViewController w;
    w.setStandardView("front", kBox, 1.0);
    const glm::dvec3 eye0 = w.eye();
    const glm::dvec3 left = -w.right();
    w.orbit(10.0, 0.0);
    EXPECT_GT(glm::dot(w.eye() - eye0, left), 0.0);
}

TEST(ViewController, PanFollowsTheCursorAtTheTargetDepth)
{
    ViewController v;
    v.setStandardView("iso", kBox, double(kW) / kH);
    const glm::dvec3 onPlane = v.pointOnTargetPlane(300, 200, kW, kH);
    v.pan(25.0, -10.0, kH);
    const glm::dvec2 moved = project(v.camera(kW, kH), onPlane);
    EXPECT_NEAR(moved.x, 325.0, 1e-6);
    EXPECT_NEAR(moved.y, 190.0, 1e-6);
}

TEST(ViewController, OrthographicEyeStaysBehindTheScene)
{
    ViewController v;
    v.setStandardView("iso", kBox, 1.0);
    v.zoom(0.01, v.target()); // very close
    v.setProjection(Projection::Orthographic);
    const Camera c = v.camera(kW, kH, kBox);
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 p(k & 1 ? kBox.max.x : kBox.min.x, k & 2 ? kBox.max.y : kBox.min.y,
                           k & 4 ? kBox.max.z : kBox.min.z);
        EXPECT_GT(glm::dot(p - c.eye(), c.forward()), 0.0);
    }
    EXPECT_NEAR(c.orthoHeight(), v.heightAtTarget(), 1e-9);
}

TEST(ExactRay, HitsASphereWhereGeometrySays)
{
    const Document doc = Document::parse(
        R"({"format":"kerf","version":1,"root":{"id":"s","type":"sphere","radius":10,"transform":{"translate":[100000,0,0]}}})",
        "far.kerf");
    const Tape tape = compileTape(doc);
    const Ray ray{{100000.0 - 50.0, 3.0, 4.0}, {1.0, 0.0, 0.0}};
    const ExactHit h = castExactRay(tape, ray, 1e-6);
    ASSERT_TRUE(h.hit);
    const double expected = 50.0 - std::sqrt(100.0 - 25.0);
    EXPECT_NEAR(h.depth, expected, 2e-6);
    EXPECT_NEAR(glm::length(h.point - glm::dvec3(100000, 0, 0)), 10.0, 2e-6);
    EXPECT_LT(glm::length(h.normal - glm::normalize(h.point - glm::dvec3(100000, 0, 0))), 1e-6);
    EXPECT_EQ(tape.features().at(h.feature).nodeId, "s");
    EXPECT_FALSE(castExactRay(tape, Ray{{100000.0 - 50.0, 30.0, 0.0}, {1.0, 0.0, 0.0}}, 1e-6).hit);
}

} // namespace
} // namespace kerf

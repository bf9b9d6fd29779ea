// Snapping for measuring: corners, hole centres and edges that lie on the
// part's surface, exact to the document; hidden or cut-away candidates are
// no snaps.

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/SnapPoint.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <filesystem>

namespace kerf {
namespace {

Tape tapeOf(const std::string& root)
{
    return compileTape(Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf"));
}

constexpr const char* kBox = R"({"id":"b","type":"box","size":[40,20,10]})";

// Looking at the box's +X, -Y and +Z faces.
Camera isoCamera() { return Camera::standardView(Aabb{glm::dvec3(-20, -10, -5), glm::dvec3(20, 10, 5)}, "iso", 800, 600); }

TEST(CameraProject, IsTheInverseOfRay)
{
    for (Projection p : {Projection::Perspective, Projection::Orthographic}) {
        const Camera c = Camera::standardView(Aabb{glm::dvec3(-20), glm::dvec3(20)}, "iso", 640, 480, p);
        for (const glm::dvec2 px : {glm::dvec2(0.5, 0.5), glm::dvec2(320.25, 100.75), glm::dvec2(639, 479)}) {
            const Ray r = c.ray(px.x, px.y);
            const auto back = c.project(r.origin + 37.0 * r.direction);
            ASSERT_TRUE(back.has_value());
            EXPECT_NEAR(back->x, px.x, 1e-9);
            EXPECT_NEAR(back->y, px.y, 1e-9);
            // One pixel over is millimetresPerPixel away at that depth.
            const glm::dvec3 q = r.origin + 37.0 * r.direction;
            const Ray r2 = c.ray(px.x + 1.0, px.y);
            const glm::dvec3 q2 = r2.origin + r2.direction * (glm::dot(q - r2.origin, c.forward()) /
                                                              glm::dot(r2.direction, c.forward()));
            EXPECT_NEAR(glm::length(q2 - q), c.millimetresPerPixel(q), 1e-9 * glm::length(q2 - q) + 1e-12);
        }
    }
    const Camera c = Camera::standardView(Aabb{glm::dvec3(-20), glm::dvec3(20)}, "front", 640, 480);
    EXPECT_FALSE(c.project(c.eye() - c.forward()).has_value()); // behind the eye
}

TEST(SnapPoint, ACursorNearAVisibleCornerTakesTheExactCorner)
{
    const Tape tape = tapeOf(kBox);
    const Camera cam = isoCamera();
    const glm::dvec3 corner(20, -10, 5); // on the three faces the camera sees
    const glm::dvec2 at = *cam.project(corner) + glm::dvec2(4, -3);
    const auto s = snapAt(tape, cam, at);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->kind, SnapKind::Vertex);
    EXPECT_EQ(s->point, corner);
}

TEST(SnapPoint, AHiddenCornerIsNoSnap)
{
    const Tape tape = tapeOf(kBox);
    const Camera cam = isoCamera();
    const glm::dvec3 back(-20, 10, -5); // behind the box from this side
    const auto s = snapAt(tape, cam, *cam.project(back));
    ASSERT_TRUE(s.has_value());
    EXPECT_NE(s->kind, SnapKind::Vertex);
    EXPECT_GT(glm::length(s->point - back), 1.0);
}

TEST(SnapPoint, ACornerCutAwayIsNoSnapButTheCutsCornerIs)
{
    // The box with a 6 mm cube taken off its (+X, -Y, +Z) corner: that corner
    // is air now; the cut leaves a corner of its own at (14, -4, -1).
    const Tape tape = tapeOf(R"({"id":"d","type":"difference","children":[)" + std::string(kBox) +
                             R"(,{"id":"c","type":"box","size":[12,12,12],"transform":{"translate":[20,-10,5]}}]})");
    const Camera cam = isoCamera();
    const auto gone = snapAt(tape, cam, *cam.project(glm::dvec3(20, -10, 5)), SnapOptions{3.0});
    ASSERT_TRUE(!gone || gone->kind != SnapKind::Vertex || glm::length(gone->point - glm::dvec3(20, -10, 5)) > 1.0);
    const auto inner = snapAt(tape, cam, *cam.project(glm::dvec3(14, -4, -1)) + glm::dvec2(2, 2));
    ASSERT_TRUE(inner.has_value());
    EXPECT_EQ(inner->kind, SnapKind::Vertex);
    EXPECT_EQ(inner->point, glm::dvec3(14, -4, -1));
}

TEST(SnapPoint, NearAnEdgeThePointLiesOnTheEdge)
{
    const Tape tape = tapeOf(kBox);
    const Camera cam = isoCamera();
    // The top face's front edge: y = -10, z = 5, x from -20 to 20.
    const glm::dvec2 at = *cam.project(glm::dvec3(3, -10, 5)) + glm::dvec2(0, 4);
    const auto s = snapAt(tape, cam, at);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->kind, SnapKind::Edge);
    EXPECT_NEAR(s->point.y, -10.0, 1e-9);
    EXPECT_NEAR(s->point.z, 5.0, 1e-9);
    EXPECT_NEAR(s->point.x, 3.0, 1.0);
}

TEST(SnapPoint, FarFromEveryEdgeTheFaceUnderTheCursor)
{
    const Tape tape = tapeOf(kBox);
    const Camera cam = isoCamera();
    const auto s = snapAt(tape, cam, *cam.project(glm::dvec3(0, 0, 5)));
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->kind, SnapKind::Face);
    EXPECT_NEAR(s->point.z, 5.0, 1e-9); // on the face, not where the ray stopped
    EXPECT_FALSE(snapAt(tape, cam, glm::dvec2(2, 2)).has_value()); // the empty corner of the image
}

TEST(SnapPoint, ShelfPinHolesMeasureTheirPitchExactly)
{
    // The bundled bookshelf side: two columns of 5 mm holes, 32 mm apart,
    // seen from the drilled face (+X). A click a few pixels off each rim takes
    // the hole's centre in the face.
    const Tape tape = compileTape(Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side.kerf"));
    const Camera cam = Camera::orthographic(glm::dvec3(500, 37, 176), glm::dvec3(0, 37, 176), glm::dvec3(0, 0, 1),
                                            80.0, 800, 800);
    std::vector<glm::dvec3> centres;
    for (double z : {160.0, 192.0}) {
        const glm::dvec3 rim(9.0, 37.0 + 2.5, z); // a point of the rim in the face x = 9
        const auto s = snapAt(tape, cam, *cam.project(rim) + glm::dvec2(3, 1));
        ASSERT_TRUE(s.has_value());
        EXPECT_EQ(s->kind, SnapKind::CircleCentre);
        centres.push_back(s->point);
    }
    EXPECT_NEAR(centres[0].x, 9.0, 1e-9);
    EXPECT_NEAR(centres[0].y, 37.0, 1e-9);
    EXPECT_NEAR(glm::length(centres[1] - centres[0]), 32.0, 1e-9);
}

TEST(SnapPoint, ACircleWhoseRimIsInTheAirIsNoSnap)
{
    // A cylinder standing on a box: its top rim is an edge; a tool's end
    // above the board (where the hole's tool sticks out) is not.
    const Tape tape = tapeOf(
        R"({"id":"d","type":"difference","children":[{"id":"b","type":"box","size":[40,40,10]},)"
        R"({"id":"h","type":"cylinder","radius":4,"height":30,"transform":{"translate":[0,0,5]}}]})");
    const Camera cam = Camera::orthographic(glm::dvec3(0, 0, 200), glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0), 60.0, 600,
                                            600);
    // Straight down onto the hole: the face z = 5 holds the rim.
    const auto s = snapAt(tape, cam, *cam.project(glm::dvec3(4.0, 0, 5)) + glm::dvec2(4, 0));
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->kind, SnapKind::CircleCentre);
    EXPECT_NEAR(s->point.z, 5.0, 1e-9);
    EXPECT_NEAR(glm::length(glm::dvec2(s->point)), 0.0, 1e-9);
}

} // namespace
} // namespace kerf

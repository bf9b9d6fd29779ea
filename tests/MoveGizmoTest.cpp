// The move gizmo's handles and drags, apart from drawing.

#include "kerf/tracer/MoveGizmo.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

namespace kerf {
namespace {

Camera iso() { return Camera::standardView(Aabb{glm::dvec3(-50), glm::dvec3(50)}, "iso", 800, 600); }

TEST(MoveGizmo, ArmsAreAFixedNumberOfPixelsLong)
{
    const Camera c = iso();
    const MoveGizmo g = MoveGizmo::at(glm::dvec3(0), c);
    const glm::dvec2 o = *c.project(g.origin);
    // Along the view's right direction an arm is exactly kArmPixels long.
    const glm::dvec2 r = *c.project(g.origin + g.armLength * c.right());
    EXPECT_NEAR(glm::length(r - o), MoveGizmo::kArmPixels, 1e-6);
}

TEST(MoveGizmo, TheCursorFindsArrowsAndSquares)
{
    const Camera c = iso();
    const MoveGizmo g = MoveGizmo::at(glm::dvec3(0), c);
    const auto px = [&](glm::dvec3 p) { return *c.project(p); };
    EXPECT_EQ(g.handleAt(c, px(0.8 * g.armLength * glm::dvec3(1, 0, 0)) + glm::dvec2(2, 2)), GizmoHandle::X);
    EXPECT_EQ(g.handleAt(c, px(0.9 * g.armLength * glm::dvec3(0, 1, 0))), GizmoHandle::Y);
    EXPECT_EQ(g.handleAt(c, px(0.7 * g.armLength * glm::dvec3(0, 0, 1))), GizmoHandle::Z);
    EXPECT_EQ(g.handleAt(c, px(0.35 * g.armLength * glm::dvec3(1, 1, 0))), GizmoHandle::PlaneXY);
    EXPECT_EQ(g.handleAt(c, px(0.35 * g.armLength * glm::dvec3(0, 1, 1))), GizmoHandle::PlaneYZ);
    EXPECT_EQ(g.handleAt(c, px(glm::dvec3(0)) + glm::dvec2(200, 0)), GizmoHandle::None);
}

TEST(MoveGizmo, ADragAlongAnArrowMovesAlongItsAxisOnly)
{
    const Camera c = iso();
    const MoveGizmo g = MoveGizmo::at(glm::dvec3(10, 20, 30), c);
    const glm::dvec2 from = *c.project(g.origin), to = *c.project(g.origin + glm::dvec3(32, 0, 0));
    const auto d = g.displacement(c, GizmoHandle::X, from, to);
    ASSERT_TRUE(d.has_value());
    EXPECT_NEAR(d->x, 32.0, 1e-9);
    EXPECT_EQ(d->y, 0.0);
    EXPECT_EQ(d->z, 0.0);
    const auto plane = g.displacement(c, GizmoHandle::PlaneXY, from, *c.project(g.origin + glm::dvec3(10, -5, 0)));
    ASSERT_TRUE(plane.has_value());
    EXPECT_NEAR(plane->x, 10.0, 1e-9);
    EXPECT_NEAR(plane->y, -5.0, 1e-9);
    EXPECT_EQ(plane->z, 0.0);
}

TEST(MoveGizmo, AnArrowSeenEndOnCannotBeTaken)
{
    const Camera top = Camera::standardView(Aabb{glm::dvec3(-50), glm::dvec3(50)}, "top", 800, 600,
                                            Projection::Orthographic);
    const MoveGizmo g = MoveGizmo::at(glm::dvec3(0), top);
    EXPECT_FALSE(g.usable(top, GizmoHandle::Z));
    EXPECT_FALSE(g.usable(top, GizmoHandle::PlaneYZ));
    EXPECT_TRUE(g.usable(top, GizmoHandle::PlaneXY));
    EXPECT_NE(g.handleAt(top, *top.project(glm::dvec3(0))), GizmoHandle::Z);
}

} // namespace
} // namespace kerf

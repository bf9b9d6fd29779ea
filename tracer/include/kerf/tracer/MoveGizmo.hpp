#pragma once
// The move gizmo's geometry, apart from any drawing: three arrows along the
// world axes from the selected feature, and three small squares between
// them for moves in a plane. Which handle a cursor is on, and what world
// displacement a drag from one image position to another means: along an
// axis, the change of the point of the axis nearest the cursor's ray; in a
// plane, the change of where the ray meets the plane. Sizes are in pixels,
// so the gizmo looks the same at any zoom.
//
// A value type; pure functions; safe from any thread.

#include "kerf/tracer/Camera.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace kerf {

enum class GizmoHandle { None, X, Y, Z, PlaneYZ, PlaneZX, PlaneXY };

/// The world axis of an arrow handle, or the normal of a plane handle.
glm::dvec3 gizmoAxis(GizmoHandle handle);
/// 0, 1, 2 for X / PlaneYZ, Y / PlaneZX, Z / PlaneXY; -1 for None.
int gizmoAxisIndex(GizmoHandle handle);
bool isPlaneHandle(GizmoHandle handle);

struct MoveGizmo {
    glm::dvec3 origin{0.0};
    double armLength = 1.0; // mm in the world

    static constexpr double kArmPixels = 90.0;
    static constexpr double kPlaneFrom = 0.25, kPlaneTo = 0.45; // the squares, as fractions of an arm

    /// A gizmo at `origin` whose arms are kArmPixels long on screen.
    static MoveGizmo at(const glm::dvec3& origin, const Camera& camera);

    /// The handle under the image position (within `tolerancePixels` of an
    /// arrow; inside a square). Arrows seen nearly end on, and squares seen
    /// nearly edge on, cannot be taken: their drags would be unstable.
    GizmoHandle handleAt(const Camera& camera, glm::dvec2 pixel, double tolerancePixels = 7.0) const;

    /// Whether the handle can be dragged in this view (see handleAt).
    bool usable(const Camera& camera, GizmoHandle handle) const;

    /// The world displacement of dragging `handle` from `from` to `to`
    /// (image positions): along the arrow's axis or in the square's plane.
    /// None when the view makes the drag meaningless.
    std::optional<glm::dvec3> displacement(const Camera& camera, GizmoHandle handle, glm::dvec2 from,
                                           glm::dvec2 to) const;
};

} // namespace kerf

#pragma once
// How a person moves the viewport's camera: orbit about a pivot, pan, zoom
// towards the point under the cursor, standard views, fit all, perspective
// or orthographic. A small value type (copied to the render thread each
// frame); Camera is what it produces for a given image size.
//
// State: the target (the point the view is centred on), the distance from
// the eye to it, and the view direction as yaw and pitch (degrees; Z up,
// yaw 0 looks from +X towards -X, pitch 90 looks straight down). The
// camera's up vector is the direction of increasing pitch, so the top and
// bottom views have a well-defined image orientation. An orthographic view
// shows the same height at the target as the perspective one (the field of
// view's height at the target distance), so switching keeps the framing;
// its eye is moved back behind the scene so nothing is clipped.

#include "kerf/document/Aabb.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/voxelizer/RefinementPlan.hpp"

#include <glm/vec3.hpp>

#include <optional>
#include <string_view>

namespace kerf {

class ViewController {
public:
    static constexpr double kFovYDegrees = 30.0;
    static constexpr double kOrbitDegreesPerPixel = 0.4;

    ViewController();

    /// A standard view (the names of Camera::standardView: iso, front, back,
    /// left, right, top, bottom) framing `bounds`. Throws
    /// std::invalid_argument naming an unknown view.
    void setStandardView(std::string_view name, const Aabb& bounds, double aspect);
    /// Keeps the direction; centres `bounds` and fits its bounding sphere.
    void fit(const Aabb& bounds, double aspect);
    /// Whether a part framed when it was `framed` across and now `now`
    /// across (largest extents, mm) changed scale enough to be framed again:
    /// by a factor of four or more either way. A board grown from 20 mm to
    /// 1800 mm would otherwise fill the view a hundred times over; edits at
    /// one scale never move the view.
    static bool rescaled(double framed, double now) { return framed > 0.0 && (now > 4.0 * framed || 4.0 * now < framed); }

    /// Rotates the view by a mouse drag (pixels): yaw about world Z, pitch
    /// about the image's right axis, both about `pivot` (the target when
    /// none). Pitch stays within [-90, 90].
    void orbit(double dxPixels, double dyPixels, std::optional<glm::dvec3> pivot = std::nullopt);
    /// Moves the view with the drag, so that the point under the cursor at
    /// the target's depth follows it.
    void pan(double dxPixels, double dyPixels, int imageHeight);
    /// Moves towards `about` (factor < 1) or away (factor > 1), keeping the
    /// point `about` at the same place in the image.
    void zoom(double factor, const glm::dvec3& about);
    /// The point under image position (x, y) on the plane through the target
    /// facing the view: where zoom goes when the cursor is over nothing.
    glm::dvec3 pointOnTargetPlane(double x, double y, int width, int height) const;

    void setProjection(Projection p) { projection_ = p; }
    Projection projection() const { return projection_; }

    /// The camera for an image of this size; `scene` (bounded, or empty)
    /// keeps an orthographic eye behind everything drawn.
    Camera camera(int width, int height, const Aabb& scene = Aabb::empty()) const;

    const glm::dvec3& target() const { return target_; }
    double distance() const { return distance_; }
    double yawDegrees() const { return yaw_; }
    double pitchDegrees() const { return pitch_; }
    /// Unit vectors of the view frame.
    glm::dvec3 forward() const;
    glm::dvec3 up() const;
    glm::dvec3 right() const;
    glm::dvec3 eye() const { return target_ - forward() * distance_; }
    /// Image height in mm at the target's distance.
    double heightAtTarget() const;

    bool operator==(const ViewController&) const = default;

private:
    glm::dvec3 target_{0.0};
    double distance_ = 1000.0;
    double yaw_ = -45.0, pitch_ = 35.26438968275465;
    Projection projection_ = Projection::Perspective;
};

/// What a camera needs from the voxelizer (RefinementPlan.hpp): voxels
/// that project to at most `pixelsPerVoxel` pixels.
ViewRequirement viewRequirement(const Camera& camera, double pixelsPerVoxel = 1.0);

} // namespace kerf

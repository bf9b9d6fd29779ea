#pragma once
// Cameras that turn pixels into rays, in world coordinates (mm, Z up).
//
// Image convention: pixel (0, 0) is the top-left one, x grows to the right
// and y downwards; rays pass through pixel centres. A ray's depth is the
// distance along its unit direction from its origin, in mm: the eye for a
// perspective camera, the point of the eye's plane (the plane through the eye
// facing the view direction) that the ray starts from for an orthographic
// one.
//
// A Camera is a small value type: immutable after construction, safe to share
// between threads.

#include "kerf/document/Aabb.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

#include <string_view>

namespace kerf {

/// A ray in world coordinates: origin in mm, direction of unit length.
struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, 1.0};
};

enum class Projection { Perspective, Orthographic };

class Camera {
public:
    Camera() = default;

    /// A pinhole camera at `eye` looking at `target`; `up` need not be
    /// orthogonal to the view direction but must not be parallel to it.
    /// `fovYDegrees` is the full vertical field of view, in (0, 180).
    /// Throws std::invalid_argument on a degenerate frame or image size.
    static Camera perspective(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double fovYDegrees,
                              int width, int height);

    /// A parallel projection: rays start on the eye's plane and all go along
    /// the view direction; `heightMm` is the image's height in the world.
    static Camera orthographic(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double heightMm,
                               int width, int height);

    /// A camera framing the whole of `partBounds` (which must be bounded and
    /// not empty) from one of the standard directions, Z up:
    ///   front  eye at -Y looking along +Y (X to the right, Z up)
    ///   back   eye at +Y looking along -Y
    ///   left   eye at -X looking along +X
    ///   right  eye at +X looking along -X
    ///   top    eye at +Z looking down -Z (X to the right, +Y up in the image)
    ///   bottom eye at -Z looking up +Z (X to the right, -Y up in the image)
    ///   iso    eye along (+1, -1, +1) from the centre: front, right and top
    ///          faces visible, Z up
    /// The bounding sphere of the box fits both fields of view, with a small
    /// margin; a perspective view uses a 30 degree vertical field of view.
    /// Throws std::invalid_argument naming an unknown view.
    static Camera standardView(const Aabb& partBounds, std::string_view name, int width, int height,
                               Projection projection = Projection::Perspective);

    /// The ray through the centre of pixel (px, py); pixels outside the image
    /// are allowed (their rays continue the projection).
    Ray ray(int px, int py) const { return ray(px + 0.5, py + 0.5); }
    /// The ray through image position (x, y) in pixels (0, 0 = top-left corner).
    Ray ray(double x, double y) const;

    /// Where a world point appears in the image, in pixels (the inverse of
    /// ray()); none for a point on or behind the eye of a perspective camera.
    std::optional<glm::dvec2> project(const glm::dvec3& world) const;
    /// The width in mm of one pixel at `world` (on the plane through it
    /// facing the camera): how far a pixel tolerance reaches there.
    double millimetresPerPixel(const glm::dvec3& world) const;

    Projection projection() const { return projection_; }
    int width() const { return width_; }
    int height() const { return height_; }
    const glm::dvec3& eye() const { return eye_; }
    /// Unit view direction, and the image's right and up directions (an
    /// orthonormal, right-handed frame: right x up = -forward).
    const glm::dvec3& forward() const { return forward_; }
    const glm::dvec3& right() const { return right_; }
    const glm::dvec3& up() const { return up_; }
    /// Vertical field of view (degrees) of a perspective camera.
    double fovYDegrees() const { return fovY_; }
    /// Image height in mm of an orthographic camera.
    double orthoHeight() const { return orthoHeight_; }
    /// Half the image height on the plane one unit ahead (perspective:
    /// tan(fovY / 2)) or in mm (orthographic: orthoHeight / 2).
    double halfHeight() const { return halfHeight_; }

private:
    void setFrame(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, int width, int height);

    Projection projection_ = Projection::Perspective;
    int width_ = 1, height_ = 1;
    glm::dvec3 eye_{0.0};
    glm::dvec3 forward_{0.0, 1.0, 0.0};
    glm::dvec3 right_{1.0, 0.0, 0.0};
    glm::dvec3 up_{0.0, 0.0, 1.0};
    double fovY_ = 30.0;
    double orthoHeight_ = 1.0;
    double halfHeight_ = 0.0; // tan(fovY / 2) for perspective, orthoHeight / 2 for orthographic
};

} // namespace kerf

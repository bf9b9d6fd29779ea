#include "kerf/tracer/Camera.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace kerf {

namespace {

constexpr double kStandardFovY = 30.0; // degrees: mild perspective, like a photograph of furniture
constexpr double kFrameMargin = 1.08;  // the part fills about 92% of the tighter image dimension

struct ViewDirection {
    std::string_view name;
    glm::dvec3 forward; // view direction
    glm::dvec3 up;
};

// Front, top and bottom keep X to the right: top and bottom are the front
// view rotated about X, as in a drawing's third-angle projection.
constexpr std::array<ViewDirection, 7> kViews{{
    {"front", {0, 1, 0}, {0, 0, 1}},
    {"back", {0, -1, 0}, {0, 0, 1}},
    {"left", {1, 0, 0}, {0, 0, 1}},
    {"right", {-1, 0, 0}, {0, 0, 1}},
    {"top", {0, 0, -1}, {0, 1, 0}},
    {"bottom", {0, 0, 1}, {0, -1, 0}},
    {"iso", {-1, 1, -1}, {0, 0, 1}},
}};

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

} // namespace

void Camera::setFrame(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, int width, int height)
{
    if (width <= 0 || height <= 0) throw std::invalid_argument("camera: image size must be positive");
    const glm::dvec3 f = target - eye;
    const double fl = glm::length(f);
    if (!(fl > 0.0) || !std::isfinite(fl)) throw std::invalid_argument("camera: eye and target coincide");
    forward_ = f / fl;
    const glm::dvec3 r = glm::cross(forward_, up);
    const double rl = glm::length(r);
    if (!(rl > 1e-9 * glm::length(up))) throw std::invalid_argument("camera: up is parallel to the view direction");
    right_ = r / rl;
    up_ = glm::cross(right_, forward_);
    eye_ = eye;
    width_ = width;
    height_ = height;
}

Camera Camera::perspective(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double fovYDegrees,
                           int width, int height)
{
    if (!(fovYDegrees > 0.0 && fovYDegrees < 180.0))
        throw std::invalid_argument("camera: field of view must lie in (0, 180) degrees");
    Camera c;
    c.setFrame(eye, target, up, width, height);
    c.projection_ = Projection::Perspective;
    c.fovY_ = fovYDegrees;
    c.halfHeight_ = std::tan(0.5 * radians(fovYDegrees));
    return c;
}

Camera Camera::orthographic(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double heightMm,
                            int width, int height)
{
    if (!(heightMm > 0.0) || !std::isfinite(heightMm))
        throw std::invalid_argument("camera: orthographic height must be positive");
    Camera c;
    c.setFrame(eye, target, up, width, height);
    c.projection_ = Projection::Orthographic;
    c.orthoHeight_ = heightMm;
    c.halfHeight_ = 0.5 * heightMm;
    return c;
}

Ray Camera::ray(double x, double y) const
{
    // Image plane coordinates: u to the right, v up, each in [-1, 1] across
    // the image's height (u spans the aspect ratio).
    const double aspect = double(width_) / double(height_);
    const double u = (2.0 * x / width_ - 1.0) * aspect;
    const double v = 1.0 - 2.0 * y / height_;
    Ray r;
    if (projection_ == Projection::Perspective) {
        r.origin = eye_;
        r.direction = glm::normalize(forward_ + (u * halfHeight_) * right_ + (v * halfHeight_) * up_);
    } else {
        r.origin = eye_ + (u * halfHeight_) * right_ + (v * halfHeight_) * up_;
        r.direction = forward_;
    }
    return r;
}

std::optional<glm::dvec2> Camera::project(const glm::dvec3& world) const
{
    const glm::dvec3 rel = world - eye_;
    double u = glm::dot(rel, right_), v = glm::dot(rel, up_);
    if (projection_ == Projection::Perspective) {
        const double z = glm::dot(rel, forward_);
        if (!(z > 0.0)) return std::nullopt;
        u /= z;
        v /= z;
    }
    u /= halfHeight_;
    v /= halfHeight_;
    const double aspect = double(width_) / double(height_);
    return glm::dvec2((u / aspect + 1.0) * 0.5 * width_, (1.0 - v) * 0.5 * height_);
}

double Camera::millimetresPerPixel(const glm::dvec3& world) const
{
    // The image's height spans 2 * halfHeight at unit depth (perspective) or in mm.
    const double perUnit = 2.0 * halfHeight_ / height_;
    if (projection_ == Projection::Orthographic) return perUnit;
    return perUnit * std::max(glm::dot(world - eye_, forward_), 0.0);
}

Camera Camera::standardView(const Aabb& partBounds, std::string_view name, int width, int height, Projection projection)
{
    const auto it = std::find_if(kViews.begin(), kViews.end(), [&](const ViewDirection& v) { return v.name == name; });
    if (it == kViews.end())
        throw std::invalid_argument("camera: unknown view '" + std::string(name) +
                                    "' (iso, front, back, top, bottom, left, right)");
    if (partBounds.isEmpty() || !partBounds.isBounded())
        throw std::invalid_argument("camera: a standard view needs a bounded, non-empty part");
    if (width <= 0 || height <= 0) throw std::invalid_argument("camera: image size must be positive");

    const glm::dvec3 centre = partBounds.center();
    const glm::dvec3 forward = glm::normalize(it->forward);
    // The frame the camera will have, to project the box's corners.
    const glm::dvec3 right = glm::normalize(glm::cross(forward, it->up));
    const glm::dvec3 up = glm::cross(right, forward);
    const double aspect = double(width) / double(height);
    // Never closer than the bounding sphere, so that every ray starts outside the part.
    const double radius = 0.5 * glm::length(partBounds.size());
    const double minSize = 1e-3; // mm: a point-like part still gets a finite frame

    if (projection == Projection::Orthographic) {
        double half = minSize;
        for (int k = 0; k < 8; ++k) {
            const glm::dvec3 p{k & 1 ? partBounds.max.x : partBounds.min.x, k & 2 ? partBounds.max.y : partBounds.min.y,
                               k & 4 ? partBounds.max.z : partBounds.min.z};
            const glm::dvec3 q = p - centre;
            half = std::max({half, std::abs(glm::dot(q, up)), std::abs(glm::dot(q, right)) / aspect});
        }
        const double distance = 2.0 * radius + 1.0;
        return orthographic(centre - distance * forward, centre, it->up, 2.0 * kFrameMargin * half, width, height);
    }

    // Perspective: the smallest distance at which every corner of the box
    // projects inside the (margin-shrunk) image.
    const double tanY = std::tan(0.5 * radians(kStandardFovY));
    const double tanX = tanY * aspect;
    double distance = radius * 1.01 + minSize;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 p{k & 1 ? partBounds.max.x : partBounds.min.x, k & 2 ? partBounds.max.y : partBounds.min.y,
                           k & 4 ? partBounds.max.z : partBounds.min.z};
        const glm::dvec3 q = p - centre;
        const double depthOffset = glm::dot(q, forward); // the corner is this much farther than the centre
        distance = std::max({distance, kFrameMargin * std::abs(glm::dot(q, up)) / tanY - depthOffset,
                             kFrameMargin * std::abs(glm::dot(q, right)) / tanX - depthOffset});
    }
    return perspective(centre - distance * forward, centre, it->up, kStandardFovY, width, height);
}

} // namespace kerf

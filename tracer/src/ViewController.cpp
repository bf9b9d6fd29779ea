#include "kerf/tracer/ViewController.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace kerf {

namespace {

constexpr double kDegrees = 3.14159265358979323846 / 180.0;
// Smallest and largest distance a zoom may reach: a micrometre to 100 km.
constexpr double kMinDistance = 1e-3, kMaxDistance = 1e8;

// Where a standard view looks from: yaw and pitch of the eye as seen from the target.
bool standardAngles(std::string_view name, double& yaw, double& pitch)
{
    struct View {
        std::string_view name;
        double yaw, pitch;
    };
    static constexpr View views[] = {
        {"iso", -45.0, 35.26438968275465}, // eye along (1, -1, 1)
        {"front", -90.0, 0.0},
        {"back", 90.0, 0.0},
        {"left", 180.0, 0.0},
        {"right", 0.0, 0.0},
        {"top", -90.0, 90.0},
        {"bottom", -90.0, -90.0},
    };
    for (const View& v : views)
        if (v.name == name) {
            yaw = v.yaw;
            pitch = v.pitch;
            return true;
        }
    return false;
}

double fitDistance(const Aabb& bounds, double aspect)
{
    const double radius = std::max(0.5 * glm::length(bounds.size()), 1e-3);
    const double halfY = 0.5 * ViewController::kFovYDegrees * kDegrees;
    const double halfX = std::atan(std::tan(halfY) * std::max(aspect, 1e-3));
    return 1.08 * radius / std::sin(std::min(halfX, halfY));
}

} // namespace

ViewController::ViewController() = default;

glm::dvec3 ViewController::forward() const
{
    const double y = yaw_ * kDegrees, p = pitch_ * kDegrees;
    // The eye sits at target + distance * (cos p cos y, cos p sin y, sin p).
    return -glm::dvec3(std::cos(p) * std::cos(y), std::cos(p) * std::sin(y), std::sin(p));
}

glm::dvec3 ViewController::up() const
{
    const double y = yaw_ * kDegrees, p = pitch_ * kDegrees;
    return {-std::sin(p) * std::cos(y), -std::sin(p) * std::sin(y), std::cos(p)};
}

glm::dvec3 ViewController::right() const { return glm::cross(forward(), up()); }

double ViewController::heightAtTarget() const
{
    return 2.0 * distance_ * std::tan(0.5 * kFovYDegrees * kDegrees);
}

void ViewController::setStandardView(std::string_view name, const Aabb& bounds, double aspect)
{
    double yaw = 0.0, pitch = 0.0;
    if (!standardAngles(name, yaw, pitch))
        throw std::invalid_argument("unknown view '" + std::string(name) +
                                    "' (iso, front, back, left, right, top, bottom)");
    yaw_ = yaw;
    pitch_ = pitch;
    fit(bounds, aspect);
}

void ViewController::fit(const Aabb& bounds, double aspect)
{
    if (bounds.isEmpty() || !bounds.isBounded()) return;
    target_ = bounds.center();
    distance_ = std::clamp(fitDistance(bounds, aspect), kMinDistance, kMaxDistance);
}

void ViewController::orbit(double dxPixels, double dyPixels, std::optional<glm::dvec3> pivot)
{
    const glm::dvec3 oldForward = forward(), oldUp = up(), oldRight = right();
    yaw_ = std::remainder(yaw_ - dxPixels * kOrbitDegreesPerPixel, 360.0);
    pitch_ = std::clamp(pitch_ + dyPixels * kOrbitDegreesPerPixel, -90.0, 90.0);
    if (!pivot) return;
    // The rotation taking the old view frame to the new one, applied to the
    // target about the pivot: the pivot stays where it is in the image.
    const glm::dmat3 oldFrame(oldRight, oldUp, -oldForward);
    const glm::dmat3 newFrame(right(), up(), -forward());
    const glm::dmat3 q = newFrame * glm::transpose(oldFrame);
    target_ = *pivot + q * (target_ - *pivot);
}

void ViewController::pan(double dxPixels, double dyPixels, int imageHeight)
{
    const double mmPerPixel = heightAtTarget() / double(std::max(imageHeight, 1));
    target_ += (-dxPixels * mmPerPixel) * right() + (dyPixels * mmPerPixel) * up();
}

void ViewController::zoom(double factor, const glm::dvec3& about)
{
    if (!(factor > 0.0) || !std::isfinite(factor)) return;
    factor = std::clamp(factor, kMinDistance / distance_, kMaxDistance / distance_);
    // Scaling eye and target about `about` keeps the direction and the
    // point's place in the image (perspective: same ray; ortho: the image
    // height scales with the distance).
    target_ = about + (target_ - about) * factor;
    distance_ *= factor;
}

glm::dvec3 ViewController::pointOnTargetPlane(double x, double y, int width, int height) const
{
    const Ray r = camera(width, height).ray(x, y);
    const glm::dvec3 f = forward();
    const double along = glm::dot(r.direction, f);
    if (std::fabs(along) < 1e-12) return target_;
    return r.origin + r.direction * (glm::dot(target_ - r.origin, f) / along);
}

Camera ViewController::camera(int width, int height, const Aabb& scene) const
{
    const glm::dvec3 f = forward();
    if (projection_ == Projection::Perspective)
        return Camera::perspective(eye(), target_, up(), kFovYDegrees, width, height);
    // Orthographic: the eye's plane goes behind the farthest scene point
    // towards the viewer, so that rays starting there see all of it.
    double back = distance_;
    if (!scene.isEmpty() && scene.isBounded()) {
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p(c & 1 ? scene.max.x : scene.min.x, c & 2 ? scene.max.y : scene.min.y,
                               c & 4 ? scene.max.z : scene.min.z);
            back = std::max(back, glm::dot(target_ - p, f) + 1.0);
        }
    }
    return Camera::orthographic(target_ - f * back, target_, up(), heightAtTarget(), width, height);
}

ViewRequirement viewRequirement(const Camera& camera, double pixelsPerVoxel)
{
    ViewRequirement v;
    v.eye = camera.eye();
    v.forward = camera.forward();
    v.right = camera.right();
    v.up = camera.up();
    v.orthographic = camera.projection() == Projection::Orthographic;
    v.halfHeight = camera.halfHeight();
    v.aspect = double(camera.width()) / double(camera.height());
    v.imageHeight = camera.height();
    v.pixelsPerVoxel = pixelsPerVoxel;
    return v;
}

} // namespace kerf

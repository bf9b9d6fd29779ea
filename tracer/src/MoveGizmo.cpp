#include "kerf/tracer/MoveGizmo.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace kerf {

namespace {

constexpr std::array<GizmoHandle, 3> kArrows{GizmoHandle::X, GizmoHandle::Y, GizmoHandle::Z};
constexpr std::array<GizmoHandle, 3> kPlanes{GizmoHandle::PlaneYZ, GizmoHandle::PlaneZX, GizmoHandle::PlaneXY};
// An arrow shorter than this on screen is seen end on; a plane whose normal
// is this close to perpendicular to the view is seen edge on.
constexpr double kMinArrowPixels = 18.0;
constexpr double kMinPlaneFacing = 0.2;

double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b)
{
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

// Point in a convex quadrilateral (corners in order, either winding).
bool insideQuad(glm::dvec2 p, const std::array<glm::dvec2, 4>& q)
{
    int sign = 0;
    for (int i = 0; i < 4; ++i) {
        const glm::dvec2 e = q[(i + 1) % 4] - q[i], v = p - q[i];
        const double c = e.x * v.y - e.y * v.x;
        const int s = c > 0.0 ? 1 : (c < 0.0 ? -1 : 0);
        if (s == 0) continue;
        if (sign == 0) sign = s;
        else if (s != sign) return false;
    }
    return true;
}

// Parameter of the point of line origin + s * axis nearest the ray.
std::optional<double> nearestOnAxis(const Ray& ray, const glm::dvec3& origin, const glm::dvec3& axis)
{
    const glm::dvec3 w = origin - ray.origin;
    const double b = glm::dot(axis, ray.direction);
    const double denom = 1.0 - b * b;
    if (denom < 1e-6) return std::nullopt; // the axis along the line of sight
    return (b * glm::dot(ray.direction, w) - glm::dot(axis, w)) / denom;
}

std::optional<glm::dvec3> onPlane(const Ray& ray, const glm::dvec3& origin, const glm::dvec3& normal)
{
    const double along = glm::dot(ray.direction, normal);
    if (std::abs(along) < 1e-9) return std::nullopt;
    const double t = glm::dot(origin - ray.origin, normal) / along;
    return ray.origin + t * ray.direction;
}

} // namespace

glm::dvec3 gizmoAxis(GizmoHandle handle)
{
    switch (gizmoAxisIndex(handle)) {
    case 0: return {1, 0, 0};
    case 1: return {0, 1, 0};
    case 2: return {0, 0, 1};
    default: return {0, 0, 0};
    }
}

int gizmoAxisIndex(GizmoHandle handle)
{
    switch (handle) {
    case GizmoHandle::X:
    case GizmoHandle::PlaneYZ: return 0;
    case GizmoHandle::Y:
    case GizmoHandle::PlaneZX: return 1;
    case GizmoHandle::Z:
    case GizmoHandle::PlaneXY: return 2;
    default: return -1;
    }
}

bool isPlaneHandle(GizmoHandle handle)
{
    return handle == GizmoHandle::PlaneYZ || handle == GizmoHandle::PlaneZX || handle == GizmoHandle::PlaneXY;
}

MoveGizmo MoveGizmo::at(const glm::dvec3& origin, const Camera& camera)
{
    return MoveGizmo{origin, kArmPixels * std::max(camera.millimetresPerPixel(origin), 1e-9)};
}

bool MoveGizmo::usable(const Camera& camera, GizmoHandle handle) const
{
    if (handle == GizmoHandle::None) return false;
    const glm::dvec3 axis = gizmoAxis(handle);
    if (isPlaneHandle(handle)) return std::abs(glm::dot(axis, camera.forward())) >= kMinPlaneFacing;
    const auto a = camera.project(origin), b = camera.project(origin + armLength * axis);
    return a && b && glm::length(*b - *a) >= kMinArrowPixels;
}

GizmoHandle MoveGizmo::handleAt(const Camera& camera, glm::dvec2 pixel, double tolerancePixels) const
{
    const auto o = camera.project(origin);
    if (!o) return GizmoHandle::None;
    // Squares first: they sit between the arrows, nearer the cursor's intent.
    for (GizmoHandle h : kPlanes) {
        if (!usable(camera, h)) continue;
        const int n = gizmoAxisIndex(h);
        const glm::dvec3 u = gizmoAxis(kArrows[(n + 1) % 3]), v = gizmoAxis(kArrows[(n + 2) % 3]);
        std::array<glm::dvec2, 4> quad;
        const double a = kPlaneFrom * armLength, b = kPlaneTo * armLength;
        const std::array<glm::dvec3, 4> corners{origin + a * u + a * v, origin + b * u + a * v, origin + b * u + b * v,
                                                origin + a * u + b * v};
        bool ok = true;
        for (int i = 0; i < 4 && ok; ++i) {
            const auto p = camera.project(corners[i]);
            ok = p.has_value();
            if (ok) quad[i] = *p;
        }
        if (ok && insideQuad(pixel, quad)) return h;
    }
    GizmoHandle best = GizmoHandle::None;
    double bestDistance = tolerancePixels;
    for (GizmoHandle h : kArrows) {
        if (!usable(camera, h)) continue;
        const auto tip = camera.project(origin + armLength * gizmoAxis(h));
        const double d = distanceToSegment(pixel, *o, *tip);
        if (d <= bestDistance) {
            bestDistance = d;
            best = h;
        }
    }
    return best;
}

std::optional<glm::dvec3> MoveGizmo::displacement(const Camera& camera, GizmoHandle handle, glm::dvec2 from,
                                                  glm::dvec2 to) const
{
    if (handle == GizmoHandle::None) return std::nullopt;
    const glm::dvec3 axis = gizmoAxis(handle);
    const Ray a = camera.ray(from.x, from.y), b = camera.ray(to.x, to.y);
    if (isPlaneHandle(handle)) {
        const auto pa = onPlane(a, origin, axis), pb = onPlane(b, origin, axis);
        if (!pa || !pb) return std::nullopt;
        glm::dvec3 d = *pb - *pa;
        d[gizmoAxisIndex(handle)] = 0.0; // in the plane, exactly
        return d;
    }
    const auto sa = nearestOnAxis(a, origin, axis), sb = nearestOnAxis(b, origin, axis);
    if (!sa || !sb) return std::nullopt;
    return (*sb - *sa) * axis;
}

} // namespace kerf

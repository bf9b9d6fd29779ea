#include "kerf/document/ProfileCheck.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace kerf {

namespace {
double cross(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

// Orientation of c relative to the line a->b, with a tolerance scaled to the
// coordinates so that nearly collinear points count as collinear.
int orientation(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, double eps)
{
    const double v = cross(b - a, c - a);
    if (v > eps) return 1;
    if (v < -eps) return -1;
    return 0;
}

bool onSegment(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p)
{
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

bool segmentsTouch(const glm::dvec2& p1, const glm::dvec2& p2, const glm::dvec2& q1, const glm::dvec2& q2,
                   double eps)
{
    const int o1 = orientation(p1, p2, q1, eps), o2 = orientation(p1, p2, q2, eps);
    const int o3 = orientation(q1, q2, p1, eps), o4 = orientation(q1, q2, p2, eps);
    if (o1 != o2 && o3 != o4 && o1 != 0 && o2 != 0 && o3 != 0 && o4 != 0) return true;
    if (o1 == 0 && onSegment(p1, p2, q1)) return true;
    if (o2 == 0 && onSegment(p1, p2, q2)) return true;
    if (o3 == 0 && onSegment(q1, q2, p1)) return true;
    if (o4 == 0 && onSegment(q1, q2, p2)) return true;
    return false;
}
} // namespace

double signedArea(const std::vector<glm::dvec2>& profile)
{
    double a = 0.0;
    for (std::size_t i = 0, n = profile.size(); i < n; ++i) a += cross(profile[i], profile[(i + 1) % n]);
    return 0.5 * a;
}

std::optional<std::string> findProfileDefect(const std::vector<glm::dvec2>& p)
{
    const std::size_t n = p.size();
    if (n < 3) return "needs at least 3 points, has " + std::to_string(n);
    glm::dvec2 lo = p[0], hi = p[0];
    for (const auto& v : p) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
    const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
    if (!(extent > 0.0)) return "all points coincide";
    // Tolerances relative to the profile's size: cross products scale with extent^2.
    const double eps = extent * extent * 1e-12;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        if (glm::length(p[j] - p[i]) <= extent * 1e-9)
            return "point " + std::to_string(j) + " repeats point " + std::to_string(i) +
                   " (the profile closes itself; do not repeat the first point)";
    }
    if (std::fabs(signedArea(p)) <= extent * extent * 1e-9) return "the polygon has no area (degenerate)";
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = p[i], b = p[(i + 1) % n], c = p[(i + 2) % n];
        // Neighbouring edges may only share their common point: a spike that
        // folds back along itself overlaps.
        if (orientation(a, b, c, eps) == 0 && glm::dot(b - a, c - b) < 0.0)
            return "edges " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                   " fold back over each other at point " + std::to_string((i + 1) % n);
    }
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = p[i], b = p[(i + 1) % n];
        for (std::size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue; // neighbours through the closing edge
            if (segmentsTouch(a, b, p[j], p[(j + 1) % n], eps))
                return "self-intersecting: edge " + std::to_string(i) + " (points " + std::to_string(i) + "-" +
                       std::to_string((i + 1) % n) + ") meets edge " + std::to_string(j) + " (points " +
                       std::to_string(j) + "-" + std::to_string((j + 1) % n) + ")";
        }
    }
    return std::nullopt;
}

} // namespace kerf

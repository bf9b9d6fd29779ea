#include "TriangleClearance.hpp"

#include "kerf/mesher/SelfIntersections.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace kerf::mesher {

double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    // The closest point by Voronoi regions of the corners, edges and face.
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return glm::length(p - a);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return glm::length(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return glm::length(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double sum = va + vb + vc;
    if (!(sum > 0.0)) { // a triangle without area: its longest edge stands for it
        return std::min({segmentSegmentDistance(p, p, a, b), segmentSegmentDistance(p, p, b, c),
                         segmentSegmentDistance(p, p, c, a)});
    }
    return glm::length(p - (a + ab * (vb / sum) + ac * (vc / sum)));
}

double segmentSegmentDistance(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r, const glm::dvec3& s)
{
    const glm::dvec3 d1 = q - p, d2 = s - r, w = p - r;
    const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, w);
    double u = 0.0, v = 0.0;
    if (a <= 0.0 && e <= 0.0) return glm::length(w);
    if (a <= 0.0) {
        v = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = glm::dot(d1, w);
        if (e <= 0.0) {
            u = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = glm::dot(d1, d2), denominator = a * e - b * b;
            u = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
            v = (b * u + f) / e;
            if (v < 0.0) {
                v = 0.0;
                u = std::clamp(-c / a, 0.0, 1.0);
            } else if (v > 1.0) {
                v = 1.0;
                u = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return glm::length((p + d1 * u) - (r + d2 * v));
}

double segmentTriangleDistance(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b,
                               const glm::dvec3& c)
{
    double d = std::min({pointTriangleDistance(p, a, b, c), pointTriangleDistance(q, a, b, c),
                         segmentSegmentDistance(p, q, a, b), segmentSegmentDistance(p, q, b, c),
                         segmentSegmentDistance(p, q, c, a)});
    // Through the face: the ends on either side of the plane, and the point
    // where the segment meets it as close to the triangle as anything.
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double sp = glm::dot(n, p - a), sq = glm::dot(n, q - a);
    if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0))
        d = std::min(d, pointTriangleDistance(p + (q - p) * (sp / (sp - sq)), a, b, c));
    return d;
}

bool segmentClearOf(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3* t, double clearance)
{
    const glm::dvec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
    const double length = glm::length(n);
    if (!(length > 0.0)) return false;
    const double slack = 1.0 + 1e-9;
    const double margin = clearance * length * slack;
    const double dp = glm::dot(n, p - t[0]), dq = glm::dot(n, q - t[0]);
    if ((dp > margin && dq > margin) || (dp < -margin && dq < -margin)) return true;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3& a = t[i];
        const glm::dvec3 axis = glm::cross(t[(i + 1) % 3] - a, n);
        const double axisLength = glm::length(axis);
        if (!(axisLength > 0.0)) return false;
        if (glm::dot(axis, t[(i + 2) % 3] - a) > 0.0) continue; // t on the other side: not its outer plane
        const double m = clearance * axisLength * slack;
        if (glm::dot(axis, p - a) > m && glm::dot(axis, q - a) > m) return true;
    }
    return false;
}

namespace {

// Whether t's corners all lie further than `clearance` from s's plane, on
// one side: then the triangles neither cross nor come close (most pairs a
// box query returns end here).
bool separatedByPlane(const glm::dvec3* s, const glm::dvec3* t, double clearance)
{
    const glm::dvec3 n = glm::cross(s[1] - s[0], s[2] - s[0]);
    const double length = glm::length(n);
    if (!(length > 0.0)) return false;
    const double margin = clearance * length;
    const double d0 = glm::dot(n, t[0] - s[0]), d1 = glm::dot(n, t[1] - s[0]), d2 = glm::dot(n, t[2] - s[0]);
    return (d0 > margin && d1 > margin && d2 > margin) || (d0 < -margin && d1 < -margin && d2 < -margin);
}

// Whether an axis in s's plane, across one of its edges, has t's corners
// all more than `clearance` beyond that edge (then the triangles are that
// far apart). Neighbours on one flat face pass the plane test above; most
// of them fail this one, at a fraction of the distance computations.
bool separatedAcrossAnEdge(const glm::dvec3* s, const glm::dvec3* t, double clearance)
{
    const glm::dvec3 n = glm::cross(s[1] - s[0], s[2] - s[0]);
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3& a = s[i];
        const glm::dvec3 axis = glm::cross(s[(i + 1) % 3] - a, n); // outward for counter-clockwise s
        const double length = glm::length(axis);
        if (!(length > 0.0)) return false;
        const double margin = clearance * length;
        // s lies on the inner side (the opposite corner at <= 0).
        if (glm::dot(axis, s[(i + 2) % 3] - a) > 0.0) continue; // (not expected: a clockwise corner order)
        if (glm::dot(axis, t[0] - a) > margin && glm::dot(axis, t[1] - a) > margin && glm::dot(axis, t[2] - a) > margin)
            return true;
    }
    return false;
}

} // namespace

bool trianglesTooClose(const std::array<std::uint32_t, 3>& A, const glm::dvec3* a,
                       const std::array<std::uint32_t, 3>& B, const glm::dvec3* b, double clearance)
{
    // The margin of the plane test is twice the clearance: the crossing
    // test's own coplanarity tolerance must not see a pair it lets go.
    if (separatedByPlane(a, b, 2.0 * clearance) || separatedByPlane(b, a, 2.0 * clearance)) return false;
    if (separatedAcrossAnEdge(a, b, 2.0 * clearance) || separatedAcrossAnEdge(b, a, 2.0 * clearance)) return false;
    if (trianglesCross(A, a, B, b)) return true;
    if (!(clearance > 0.0)) return false;
    int shared = 0;
    for (const std::uint32_t u : A)
        for (const std::uint32_t v : B)
            if (u == v) ++shared;
    if (shared >= 2) return false;
    auto hasIndex = [](const std::array<std::uint32_t, 3>& T, std::uint32_t v) {
        return T[0] == v || T[1] == v || T[2] == v;
    };
    // Each edge of one that does not touch a shared vertex, against the
    // other triangle (with none shared, that is every edge, and the least
    // of these is the triangles' distance).
    auto edgesClear = [&](const std::array<std::uint32_t, 3>& S, const glm::dvec3* s,
                          const std::array<std::uint32_t, 3>& T, const glm::dvec3* t) {
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t u = S[std::size_t(i)], v = S[std::size_t(i + 1) % 3];
            if (hasIndex(T, u) || hasIndex(T, v)) continue;
            if (segmentClearOf(s[i], s[(i + 1) % 3], t, clearance)) continue;
            if (segmentTriangleDistance(s[i], s[(i + 1) % 3], t[0], t[1], t[2]) < clearance) return false;
        }
        return true;
    };
    return !edgesClear(A, a, B, b) || !edgesClear(B, b, A, a);
}

} // namespace kerf::mesher

#include "kerf/document/Affine.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace kerf {

namespace {
// sin and cos of an angle in degrees, exact at multiples of 90 degrees so that
// a part rotated by 90 degrees stays exactly axis-aligned.
void sinCosDegrees(double deg, double& s, double& c)
{
    const double quarter = deg / 90.0;
    if (quarter == std::floor(quarter) && std::fabs(quarter) < 1e15) {
        const auto q = static_cast<long long>(quarter);
        const int m = static_cast<int>(((q % 4) + 4) % 4);
        constexpr double sins[4] = {0, 1, 0, -1};
        constexpr double coss[4] = {1, 0, -1, 0};
        s = sins[m];
        c = coss[m];
        return;
    }
    const double r = deg * (3.14159265358979323846 / 180.0);
    s = std::sin(r);
    c = std::cos(r);
}
} // namespace

glm::dmat3 rotationFromDegrees(const glm::dvec3& degrees)
{
    double sx, cx, sy, cy, sz, cz;
    sinCosDegrees(degrees.x, sx, cx);
    sinCosDegrees(degrees.y, sy, cy);
    sinCosDegrees(degrees.z, sz, cz);
    // glm is column-major: m[col][row].
    const glm::dmat3 rx(1, 0, 0, 0, cx, sx, 0, -sx, cx);
    const glm::dmat3 ry(cy, 0, -sy, 0, 1, 0, sy, 0, cy);
    const glm::dmat3 rz(cz, sz, 0, -sz, cz, 0, 0, 0, 1);
    return rz * ry * rx;
}

namespace {
double snapped(double degrees)
{
    const double quarter = std::round(degrees / 90.0) * 90.0;
    return std::fabs(degrees - quarter) < 1e-9 ? quarter : degrees;
}
} // namespace

Transform transformFromAffine(const Affine& placement)
{
    // R = Rz(c) Ry(b) Rx(a); with R(i, j) = row i, column j = linear[j][i]:
    // R(2, 0) = -sin b, R(2, 1) = cos b sin a, R(2, 2) = cos b cos a,
    // R(1, 0) = sin c cos b, R(0, 0) = cos c cos b.
    const glm::dmat3& m = placement.linear;
    constexpr double toDegrees = 180.0 / 3.14159265358979323846;
    const double sb = std::clamp(-m[0][2], -1.0, 1.0);
    double a, b, c;
    if (std::fabs(sb) < 1.0 - 1e-12) {
        b = std::asin(sb);
        a = std::atan2(m[1][2], m[2][2]);
        c = std::atan2(m[0][1], m[0][0]);
    } else {
        // Gimbal lock (b = +-90 degrees): only a -+ c is determined; take c = 0.
        // Then R = Ry(b) Rx(a): R(1, 1) = cos a, R(1, 2) = -sin a.
        b = sb > 0.0 ? 3.14159265358979323846 / 2.0 : -3.14159265358979323846 / 2.0;
        a = std::atan2(-m[2][1], m[1][1]);
        c = 0.0;
    }
    Transform t;
    t.translate = placement.translation;
    t.rotate = {snapped(a * toDegrees), snapped(b * toDegrees), snapped(c * toDegrees)};
    return t;
}

Affine Affine::fromTransform(const Transform& t)
{
    return {rotationFromDegrees(t.rotate), t.translate};
}

Affine Affine::reflection(const glm::dvec3& n, double offset)
{
    // p' = p - 2 (n.p - offset) n
    const glm::dmat3 m = glm::dmat3(1.0) - 2.0 * glm::outerProduct(n, n);
    return {m, 2.0 * offset * n};
}

Affine Affine::inverseOrthogonal() const
{
    const glm::dmat3 inv = glm::transpose(linear);
    return {inv, -(inv * translation)};
}

Aabb Affine::apply(const Aabb& box) const
{
    if (box.isEmpty()) return box;
    Aabb r;
    for (int i = 0; i < 3; ++i) {
        double lo = translation[i], hi = translation[i];
        for (int j = 0; j < 3; ++j) {
            const double m = linear[j][i]; // row i, column j
            if (m == 0.0) continue;         // keeps 0 * inf out
            const double a = m * box.min[j], b = m * box.max[j];
            lo += std::min(a, b);
            hi += std::max(a, b);
        }
        r.min[i] = lo;
        r.max[i] = hi;
    }
    return r;
}

} // namespace kerf

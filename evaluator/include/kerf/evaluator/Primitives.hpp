#pragma once
// Exact signed distance functions of Kerf's primitives, each in its local
// frame, written once for every scalar type the evaluators use: float and
// double (points), Dual<float/double> (gradients) and, where the formula has
// no data-dependent branch, Interval (natural interval extension).
//
// Parameter layout of ShapeInstance::param per kind:
//   Box:       bx, by, bz (half size minus round), round
//   Sphere:    radius
//   Cylinder:  radius, half height
//   Cone:      radius bottom, radius top, half height, r_top - r_bottom, height, 1 / (dr^2 + height^2)
//   Torus:     major radius, minor radius
//   Extrude:   half height (profile in ShapeInstance::polygon)
//   Halfspace: nx, ny, nz, offset

#include "kerf/evaluator/Dual.hpp"
#include "kerf/evaluator/Interval.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <type_traits>

namespace kerf {

template <class T> struct BaseScalar {
    using type = T;
};
template <class T> struct BaseScalar<Dual<T>> {
    using type = T;
};
template <> struct BaseScalar<Interval> {
    using type = double;
};
template <class T> using BaseScalarT = typename BaseScalar<T>::type;

namespace sdf {

using std::abs;
using std::max;
using std::min;
using std::sqrt;

template <class T> inline T sq(const T& a) { return a * a; }
inline Interval sq(const Interval& a) { return square(a); }

template <class T> inline T clamp01(const T& v) { return min(max(v, T(0)), T(1)); }

template <class T> T box(T x, T y, T z, T bx, T by, T bz, T round)
{
    const T qx = abs(x) - bx, qy = abs(y) - by, qz = abs(z) - bz;
    const T outside = sqrt(sq(max(qx, T(0))) + sq(max(qy, T(0))) + sq(max(qz, T(0))));
    const T inside = min(max(qx, max(qy, qz)), T(0));
    return outside + inside - round;
}

template <class T> T sphere(T x, T y, T z, T radius) { return sqrt(sq(x) + sq(y) + sq(z)) - radius; }

template <class T> T cylinder(T x, T y, T z, T radius, T halfHeight)
{
    const T dr = sqrt(sq(x) + sq(y)) - radius;
    const T dz = abs(z) - halfHeight;
    return min(max(dr, dz), T(0)) + sqrt(sq(max(dr, T(0))) + sq(max(dz, T(0))));
}

template <class T> T torus(T x, T y, T z, T major, T minor)
{
    const T q = sqrt(sq(x) + sq(y)) - major;
    return sqrt(sq(q) + sq(z)) - minor;
}

template <class T> T halfspace(T x, T y, T z, T nx, T ny, T nz, T offset) { return nx * x + ny * y + nz * z - offset; }

/// Capped cone along Z (after Inigo Quilez's exact capped cone).
template <class T> T cone(T x, T y, T z, T r1, T r2, T h, T k2x, T k2y, T invK2)
{
    const T qx = sqrt(sq(x) + sq(y));
    const T qy = z;
    const T rr = qy < T(0) ? r1 : r2;
    const T cax = qx - min(qx, rr);
    const T cay = abs(qy) - h;
    const T t = clamp01(((r2 - qx) * k2x + (h - qy) * k2y) * invK2);
    const T cbx = qx - r2 + k2x * t;
    const T cby = qy - h + k2y * t;
    const T s = (cbx < T(0) && cay < T(0)) ? T(-1) : T(1);
    return s * sqrt(min(sq(cax) + sq(cay), sq(cbx) + sq(cby)));
}

/// Combines a 2D signed distance with the extrusion's half height.
template <class T> T extrusion(T d2, T z, T halfHeight)
{
    const T wz = abs(z) - halfHeight;
    return min(max(d2, wz), T(0)) + sqrt(sq(max(d2, T(0))) + sq(max(wz, T(0))));
}

/// Signed distance to a simple polygon in XY (negative inside), exact.
/// `v`: the points in order, anything with size() and [i].x, [i].y.
template <class T, class Points> T polygon2d(T x, T y, const Points& v)
{
    using B = BaseScalarT<T>;
    const std::size_t n = v.size();
    T d = sq(x - T(B(v[0].x))) + sq(y - T(B(v[0].y)));
    bool inside = false;
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        // The edge is a constant: scale by it (plain numbers, no product rule).
        const B ex = B(v[j].x - v[i].x), ey = B(v[j].y - v[i].y);
        const T wx = x - T(B(v[i].x)), wy = y - T(B(v[i].y));
        const T t = clamp01((wx * ex + wy * ey) / (ex * ex + ey * ey));
        d = min(d, sq(wx - t * ex) + sq(wy - t * ey));
        // Crossing test (winding parity) on the edge's vertical span.
        const bool c1 = y >= T(B(v[i].y)), c2 = y < T(B(v[j].y)), c3 = wy * ex > wx * ey;
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    }
    const T dist = sqrt(d);
    return inside ? -dist : dist;
}

} // namespace sdf

/// The field of a primitive of `kind` at (x, y, z) of its local frame, for
/// scalar-like T (float, double, Dual<float>, Dual<double>): `p(i)` gives
/// its i-th parameter as T (ShapeInstance::param's layout, above), `profile`
/// an extrusion's points (polygon2d's `v`). Every evaluator of points goes
/// through here (the document's tape and the tiles' encoded tapes alike).
/// A kind this switch does not name is NaN, never a plane; a kind added to
/// ShapeKind and left out here does not compile (-Wswitch, -Werror in CI).
template <class T, class Param, class Profile>
T primitiveDistance(ShapeKind kind, T x, T y, T z, const Param& p, const Profile& profile)
{
    switch (kind) {
    case ShapeKind::Box: return sdf::box(x, y, z, p(0), p(1), p(2), p(3));
    case ShapeKind::Sphere: return sdf::sphere(x, y, z, p(0));
    case ShapeKind::Cylinder: return sdf::cylinder(x, y, z, p(0), p(1));
    case ShapeKind::Cone: return sdf::cone(x, y, z, p(0), p(1), p(2), p(3), p(4), p(5));
    case ShapeKind::Torus: return sdf::torus(x, y, z, p(0), p(1));
    case ShapeKind::Halfspace: return sdf::halfspace(x, y, z, p(0), p(1), p(2), p(3));
    case ShapeKind::Extrude: return sdf::extrusion(sdf::polygon2d(x, y, profile), z, p(0));
    }
    return T(std::numeric_limits<BaseScalarT<T>>::quiet_NaN());
}

/// Distance to a placed primitive at a point of its local frame (float
/// evaluation takes the float copies of parameters and profile).
template <class T> T shapeDistanceLocal(const ShapeInstance& s, T x, T y, T z)
{
    using B = BaseScalarT<T>;
    if constexpr (std::is_same_v<B, float>) {
        static const std::vector<glm::vec2> none;
        const auto& profile = s.polygon ? s.polygon->pointsF : none;
        return primitiveDistance(s.kind, x, y, z, [&](int i) { return T(s.paramF[static_cast<std::size_t>(i)]); },
                                 profile);
    } else {
        static const std::vector<glm::dvec2> none;
        const auto& profile = s.polygon ? s.polygon->points : none;
        return primitiveDistance(s.kind, x, y, z, [&](int i) { return T(s.param[static_cast<std::size_t>(i)]); },
                                 profile);
    }
}

} // namespace kerf

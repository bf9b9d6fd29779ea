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
//   Revolve:   none (profile of [r, z] points in ShapeInstance::polygon)

#include "kerf/evaluator/Dual.hpp"
#include "kerf/evaluator/Interval.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

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

/// A profile's points with their index (PolygonIndex.hpp): what the
/// evaluators pass for a placed extrusion or revolve, so that polygon2d
/// visits only the edges that can matter. The encoded tiles' profiles
/// (voxelizer) come without one and take the loop over every edge.
template <class P> struct IndexedProfile {
    const std::vector<P>& points;
    const PolygonIndex<P>& index;
    std::size_t size() const { return points.size(); }
    const P& operator[](std::size_t i) const { return points[i]; }
};

/// Signed distance to a simple polygon in XY (negative inside), exact.
/// `v`: the points in order, anything with size() and [i].x, [i].y.
/// `axisEdges`: false for a revolve's profile, whose edges on the axis
/// (x = 0 at both ends) are inside the solid, not surface: they count
/// neither for the distance nor for the crossing parity (which they would
/// decide either way for a point on the axis itself).
template <class T, class Points> T polygon2d(T x, T y, const Points& v, bool axisEdges = true)
{
    using B = BaseScalarT<T>;
    const std::size_t n = v.size();
    T d = axisEdges ? sq(x - T(B(v[0].x))) + sq(y - T(B(v[0].y))) : T(std::numeric_limits<B>::max());
    bool inside = false;
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        if (!axisEdges && v[i].x == 0 && v[j].x == 0) continue;
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

/// The same through the profile's index: the same value, to the bit, from
/// the edges that can decide it.
template <class T, class P>
    requires std::is_floating_point_v<T>
T polygon2d(T x, T y, const IndexedProfile<P>& profile, bool axisEdges = true)
{
    const auto& v = profile.points;
    if (!(std::isfinite(x) && std::isfinite(y))) return polygon2d(x, y, v, axisEdges);
    auto skip = [&](std::size_t i, std::size_t j) { return !axisEdges && v[i].x == 0 && v[j].x == 0; };
    auto squared = [&](std::size_t i, std::size_t j) {
        const T ex = T(v[j].x - v[i].x), ey = T(v[j].y - v[i].y);
        const T wx = x - T(v[i].x), wy = y - T(v[i].y);
        const T t = clamp01((wx * ex + wy * ey) / (ex * ex + ey * ey));
        return sq(wx - t * ex) + sq(wy - t * ey);
    };
    T d = axisEdges ? sq(x - T(v[0].x)) + sq(y - T(v[0].y)) : std::numeric_limits<T>::max();
    visitNearEdges(v, profile.index, x, y, d, squared, skip,
                   [&](std::size_t i, std::size_t j) { d = min(d, squared(i, j)); });
    bool inside = false;
    visitEdgesAcross(v, profile.index, y, [&](std::size_t i, std::size_t j) {
        if (skip(i, j)) return;
        const T ex = T(v[j].x - v[i].x), ey = T(v[j].y - v[i].y);
        const T wx = x - T(v[i].x), wy = y - T(v[i].y);
        const bool c1 = y >= T(v[i].y), c2 = y < T(v[j].y), c3 = wy * ex > wx * ey;
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    });
    const T dist = sqrt(d);
    return inside ? -dist : dist;
}

namespace detail {

/// polygon2d's distance with its gradient, over the edges that the
/// visitors give (every edge, or those the index leaves): see below.
template <class B, class Points, class Near, class Across>
Dual<B> polygonDual(const Dual<B>& x, const Dual<B>& y, const Points& v, bool axisEdges, B area, const Near& visitNear,
                    const Across& visitAcross)
{
    const B px = x.v, py = y.v;
    B d = std::numeric_limits<B>::max(), qx = 0, qy = 0; // the nearest so far, and p - q for it
    B edgeX = 0, edgeY = 0;                               // its edge, when q lies inside it (else 0)
    if (axisEdges) {
        qx = px - B(v[0].x);
        qy = py - B(v[0].y);
        d = qx * qx + qy * qy;
    }
    auto skip = [&](std::size_t i, std::size_t j) { return !axisEdges && v[i].x == 0 && v[j].x == 0; };
    auto squared = [&](std::size_t i, std::size_t j) {
        const B ex = B(v[j].x - v[i].x), ey = B(v[j].y - v[i].y);
        const B wx = px - B(v[i].x), wy = py - B(v[i].y);
        const B t = std::min(std::max((wx * ex + wy * ey) / (ex * ex + ey * ey), B(0)), B(1));
        const B bx = wx - t * ex, by = wy - t * ey;
        return bx * bx + by * by;
    };
    visitNear(d, squared, skip, [&](std::size_t i, std::size_t j) {
        const B ex = B(v[j].x - v[i].x), ey = B(v[j].y - v[i].y);
        const B wx = px - B(v[i].x), wy = py - B(v[i].y);
        const B raw = (wx * ex + wy * ey) / (ex * ex + ey * ey);
        const B t = std::min(std::max(raw, B(0)), B(1));
        const B bx = wx - t * ex, by = wy - t * ey;
        const B di = bx * bx + by * by;
        if (di < d) {
            d = di;
            qx = bx;
            qy = by;
            const bool within = B(0) < raw && raw < B(1);
            edgeX = within ? ex : B(0);
            edgeY = within ? ey : B(0);
        }
    });
    bool inside = false;
    visitAcross([&](std::size_t i, std::size_t j) {
        if (skip(i, j)) return;
        const B ex = B(v[j].x - v[i].x), ey = B(v[j].y - v[i].y);
        const B wx = px - B(v[i].x), wy = py - B(v[i].y);
        const bool c1 = py >= B(v[i].y), c2 = py < B(v[j].y), c3 = wy * ex > wx * ey;
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    });
    const B dist = std::sqrt(d);
    B gx = 0, gy = 0;
    if (edgeX != B(0) || edgeY != B(0)) {
        // The edge vector points from v[i] back to v[j], against the
        // profile's order: (-ey, ex), to its right as travelled, is outside
        // of a counter-clockwise profile.
        const B k = (area < B(0) ? B(-1) : B(1)) / std::sqrt(edgeX * edgeX + edgeY * edgeY);
        gx = -edgeY * k;
        gy = edgeX * k;
    } else if (dist > B(0)) {
        const B k = (inside ? B(-1) : B(1)) / dist;
        gx = qx * k;
        gy = qy * k;
    }
    return {inside ? -dist : dist, gx * x.d[0] + gy * y.d[0], gx * x.d[1] + gy * y.d[1], gx * x.d[2] + gy * y.d[2]};
}

} // namespace detail

/// The same distance with its gradient. The generic form carries the three
/// derivatives through every edge's arithmetic, and the exporter's walks to
/// the surface spent a fifth of their time there on the side chair's rails
/// (32 points each). Here the nearest edge is found in plain numbers and the
/// gradient taken once, from it: the edge's outward normal where the nearest
/// point lies inside the edge, (p - q) / |p - q| (signed) where it is a
/// vertex q. Not (p - q) / |p - q| everywhere, nor the generic form's
/// product rule: on the surface p - q is rounding noise, and both turned
/// the tracer's normals at its hits by degrees, or inwards where the
/// crossing parity and the noise disagree (Gradient.OnAProfilesFace...).
/// The outward side comes from the profile's turning (its signed area). The
/// value is the generic form's to the bit (the same operations on the
/// values).
template <class B, class Points> Dual<B> polygon2d(const Dual<B>& x, const Dual<B>& y, const Points& v, bool axisEdges = true)
{
    const std::size_t n = v.size();
    B area = 0; // twice the signed area, positive for a counter-clockwise profile
    for (std::size_t i = 0, j = n - 1; i < n; j = i++)
        area += B(v[j].x) * B(v[i].y) - B(v[i].x) * B(v[j].y);
    auto everyEdge = [&](const auto& visit) {
        for (std::size_t i = 0, j = n - 1; i < n; j = i++)
            visit(i, j);
    };
    return detail::polygonDual(
        x, y, v, axisEdges, area,
        [&](B, const auto&, const auto& skip, const auto& visit) {
            everyEdge([&](std::size_t i, std::size_t j) {
                if (!skip(i, j)) visit(i, j);
            });
        },
        everyEdge);
}

/// The same through the profile's index (the same value and gradient, to
/// the bit).
template <class B, class P>
Dual<B> polygon2d(const Dual<B>& x, const Dual<B>& y, const IndexedProfile<P>& profile, bool axisEdges = true)
{
    const auto& v = profile.points;
    if (!(std::isfinite(x.v) && std::isfinite(y.v))) return polygon2d(x, y, v, axisEdges);
    return detail::polygonDual(
        x, y, v, axisEdges, B(profile.index.twiceArea),
        [&](B bound, const auto& squared, const auto& skip, const auto& visit) {
            visitNearEdges(v, profile.index, x.v, y.v, bound, squared, skip, visit);
        },
        [&](const auto& visit) { visitEdgesAcross(v, profile.index, y.v, visit); });
}

/// A profile of [r, z] points turned about Z, at (length(x, y), z).
/// Exact: the solid is symmetric about the axis, so the nearest point lies
/// in the point's own half-plane, at the profile's distance there.
template <class T, class Points> T revolution(T x, T y, T z, const Points& v)
{
    return polygon2d(sqrt(sq(x) + sq(y)), z, v, false);
}

} // namespace sdf

/// Kerf's primitives, one unit each: the node type it comes from, how the
/// node's parameters are packed into ShapeInstance::param (the layout at the
/// top of this file, also what the GPU reads), its distance (the sdf::
/// template above, for every scalar type), and a sound interval enclosure
/// over a box of its local frame. A new primitive is a unit here, its place
/// in the two lists below, its number in ShapeKinds.h, its GLSL function in
/// shaders/tape_shapes.glsl (with its enclosure in enclosureT) and its row
/// in the node type table
/// (document/src/NodeTypes.cpp); docs/architecture.md has the list.
namespace primitive {

/// The profile of an extrude or a revolve, packed once for every copy.
inline std::shared_ptr<const Polygon> packPolygon(const std::vector<glm::dvec2>& points)
{
    auto poly = std::make_shared<Polygon>();
    poly->points = points;
    for (const auto& v : points) {
        poly->pointsF.emplace_back(static_cast<float>(v.x), static_cast<float>(v.y));
        poly->min = glm::min(poly->min, v);
        poly->max = glm::max(poly->max, v);
    }
    poly->index = buildPolygonIndex(poly->points);
    poly->indexF = buildPolygonIndex(poly->pointsF);
    return poly;
}

/// No enclosure tighter than the Lipschitz bound the interval evaluator
/// always has.
inline Interval unbounded() { return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()}; }

struct Box {
    static constexpr ShapeKind kind = ShapeKind::Box;
    static constexpr NodeType node = NodeType::Box;
    static void pack(const Node& n, ShapeInstance& s)
    {
        const auto& b = n.as<BoxParams>();
        s.param = {0.5 * b.size.x - b.round, 0.5 * b.size.y - b.round, 0.5 * b.size.z - b.round, b.round, 0, 0};
    }
    template <class T, class P, class Profile> static T distance(T x, T y, T z, const P& p, const Profile&)
    {
        return sdf::box(x, y, z, p(0), p(1), p(2), p(3));
    }
    static Interval enclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
    {
        const auto& p = s.param;
        return sdf::box<Interval>(x, y, z, p[0], p[1], p[2], p[3]); // natural extension
    }
};

struct Sphere {
    static constexpr ShapeKind kind = ShapeKind::Sphere;
    static constexpr NodeType node = NodeType::Sphere;
    static void pack(const Node& n, ShapeInstance& s) { s.param[0] = n.as<SphereParams>().radius; }
    template <class T, class P, class Profile> static T distance(T x, T y, T z, const P& p, const Profile&)
    {
        return sdf::sphere(x, y, z, p(0));
    }
    static Interval enclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
    {
        return sdf::sphere<Interval>(x, y, z, s.param[0]);
    }
};

struct Cylinder {
    static constexpr ShapeKind kind = ShapeKind::Cylinder;
    static constexpr NodeType node = NodeType::Cylinder;
    static void pack(const Node& n, ShapeInstance& s)
    {
        s.param[0] = n.as<CylinderParams>().radius;
        s.param[1] = 0.5 * n.as<CylinderParams>().height;
    }
    template <class T, class P, class Profile> static T distance(T x, T y, T z, const P& p, const Profile&)
    {
        return sdf::cylinder(x, y, z, p(0), p(1));
    }
    static Interval enclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
    {
        return sdf::cylinder<Interval>(x, y, z, s.param[0], s.param[1]);
    }
};

struct Cone {
    static constexpr ShapeKind kind = ShapeKind::Cone;
    static constexpr NodeType node = NodeType::Cone;
    static void pack(const Node& n, ShapeInstance& s)
    {
        const auto& c = n.as<ConeParams>();
        const double dr = c.radiusTop - c.radiusBottom;
        s.param = {c.radiusBottom, c.radiusTop, 0.5 * c.height, dr, c.height, 1.0 / (dr * dr + c.height * c.height)};
    }
    template <class T, class P, class Profile> static T distance(T x, T y, T z, const P& p, const Profile&)
    {
        return sdf::cone(x, y, z, p(0), p(1), p(2), p(3), p(4), p(5));
    }
    // No natural extension (the formula branches on the point), but a
    // containment enclosure: a solid inside another has a field at least as
    // large everywhere (farther from its surface outside, nearer to it
    // inside), one containing another a field at most as large. A cone lies
    // between the cylinders of its smaller and larger radius (the smaller
    // may be 0: a segment).
    static Interval enclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
    {
        const auto& p = s.param;
        const Interval outer = sdf::cylinder<Interval>(x, y, z, std::max(p[0], p[1]), p[2]);
        const Interval inner = sdf::cylinder<Interval>(x, y, z, std::min(p[0], p[1]), p[2]);
        return {outer.lo, inner.hi};
    }
};

struct Torus {
    static constexpr ShapeKind kind = ShapeKind::Torus;
    static constexpr NodeType node = NodeType::Torus;
    static void pack(const Node& n, ShapeInstance& s)
    {
        s.param[0] = n.as<TorusParams>().majorRadius;
        s.param[1] = n.as<TorusParams>().minorRadius;
    }
    template <class T, class P, class Profile> static T distance(T x, T y, T z, const P& p, const Profile&)
    {
        return sdf::torus(x, y, z, p(0), p(1));
    }
    static Interval enclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
    {
        return sdf::torus<Interval>(x, y, z, s.param[0], s.param[1]);
    }
};

struct Extrude {
    static constexpr ShapeKind kind = ShapeKind::Extrude;
    static constexpr NodeType node = NodeType::Extrude;
    static void pack(const Node& n, ShapeInstance& s)
    {
        s.param[0] = 0.5 * n.as<ExtrudeParams>().height;
        s.polygon = packPolygon(n.as<ExtrudeParams>().profile);
    }
    template <class T, class P, class Profile> static T distance(T x, T y, T z, const P& p, const Profile& profile)
    {
        return sdf::extrusion(sdf::polygon2d(x, y, profile), z, p(0));
    }
    // Containment: the extrusion lies inside its profile's bounding box swept over its height.
    static Interval enclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
    {
        const glm::dvec2 mid = 0.5 * (s.polygon->min + s.polygon->max), half = 0.5 * (s.polygon->max - s.polygon->min);
        const Interval outer = sdf::box<Interval>(x - Interval(mid.x), y - Interval(mid.y), z, half.x, half.y, s.param[0], 0.0);
        return {outer.lo, unbounded().hi};
    }
};

struct Halfspace {
    static constexpr ShapeKind kind = ShapeKind::Halfspace;
    static constexpr NodeType node = NodeType::Halfspace;
    static void pack(const Node& n, ShapeInstance& s)
    {
        const auto& h = n.as<HalfspaceParams>();
        s.param = {h.normal.x, h.normal.y, h.normal.z, h.offset, 0, 0};
    }
    template <class T, class P, class Profile> static T distance(T x, T y, T z, const P& p, const Profile&)
    {
        return sdf::halfspace(x, y, z, p(0), p(1), p(2), p(3));
    }
    static Interval enclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
    {
        const auto& p = s.param;
        return sdf::halfspace<Interval>(x, y, z, p[0], p[1], p[2], p[3]);
    }
};

/// A profile of [r, z] points (r >= 0) turned about Z. The solid is
/// symmetric about the axis, so the nearest point to p lies in p's own
/// half-plane: the distance is the profile's 2D distance at
/// (length(p.xy), p.z), exact.
struct Revolve {
    static constexpr ShapeKind kind = ShapeKind::Revolve;
    static constexpr NodeType node = NodeType::Revolve;
    static void pack(const Node& n, ShapeInstance& s) { s.polygon = packPolygon(n.as<RevolveParams>().profile); }
    template <class T, class P, class Profile> static T distance(T x, T y, T z, const P&, const Profile& profile)
    {
        return sdf::revolution(x, y, z, profile);
    }
    // Containment: the solid lies inside the cylinder of its largest radius over its height.
    static Interval enclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
    {
        const double zMid = 0.5 * (s.polygon->min.y + s.polygon->max.y);
        const double halfHeight = 0.5 * (s.polygon->max.y - s.polygon->min.y);
        const Interval outer = sdf::cylinder<Interval>(x, y, z - Interval(zMid), std::max(s.polygon->max.x, 0.0), halfHeight);
        return {outer.lo, unbounded().hi};
    }
};

/// Every unit, in ShapeKind's order.
using All = std::tuple<Box, Sphere, Cylinder, Cone, Torus, Extrude, Halfspace, Revolve>;
static_assert(std::tuple_size_v<All> == KERF_SHAPE_KINDS, "a shape kind without its unit in primitive::All");

/// Calls f(Unit{}) with the unit of `kind`; false for a kind no unit has
/// (out of ShapeKind's range). A switch, so that it compiles to a jump table
/// on the evaluators' hot paths; a kind added to ShapeKind and left out here
/// does not compile (-Wswitch, -Werror in CI).
template <class F> inline bool with(ShapeKind kind, F&& f)
{
    switch (kind) {
    case ShapeKind::Box: f(Box{}); return true;
    case ShapeKind::Sphere: f(Sphere{}); return true;
    case ShapeKind::Cylinder: f(Cylinder{}); return true;
    case ShapeKind::Cone: f(Cone{}); return true;
    case ShapeKind::Torus: f(Torus{}); return true;
    case ShapeKind::Extrude: f(Extrude{}); return true;
    case ShapeKind::Halfspace: f(Halfspace{}); return true;
    case ShapeKind::Revolve: f(Revolve{}); return true;
    }
    return false;
}

} // namespace primitive

/// Packs a primitive node's kind and parameters (and profile) into `s`.
/// Throws std::logic_error for a node type no unit comes from.
inline void packPrimitive(const Node& n, ShapeInstance& s)
{
    const bool packed = std::apply(
        [&](auto... unit) {
            return ((n.type == decltype(unit)::node ? (s.kind = decltype(unit)::kind, decltype(unit)::pack(n, s), true)
                                                    : false) ||
                    ...);
        },
        primitive::All{});
    if (!packed) throw std::logic_error("no primitive unit for node type " + std::string(nodeTypeName(n.type)));
    for (std::size_t i = 0; i < s.param.size(); ++i) s.paramF[i] = static_cast<float>(s.param[i]);
}

/// The field of a primitive of `kind` at (x, y, z) of its local frame, for
/// scalar-like T (float, double, Dual<float>, Dual<double>): `p(i)` gives
/// its i-th parameter as T (ShapeInstance::param's layout, above), `profile`
/// an extrusion's or revolve's points (polygon2d's `v`). Every evaluator of
/// points goes through here (the document's tape and the tiles' encoded
/// tapes alike). A kind no unit has is NaN, never a plane.
template <class T, class Param, class Profile>
T primitiveDistance(ShapeKind kind, T x, T y, T z, const Param& p, const Profile& profile)
{
    T r = T(std::numeric_limits<BaseScalarT<T>>::quiet_NaN());
    primitive::with(kind, [&](auto unit) { r = decltype(unit)::distance(x, y, z, p, profile); });
    return r;
}

/// A sound enclosure of the primitive's field over the local-frame box
/// (x, y, z): its natural interval extension or a containment bound.
inline Interval primitiveEnclosure(const ShapeInstance& s, const Interval& x, const Interval& y, const Interval& z)
{
    Interval r = primitive::unbounded();
    primitive::with(s.kind, [&](auto unit) { r = decltype(unit)::enclosure(s, x, y, z); });
    return r;
}

/// Distance to a placed primitive at a point of its local frame (float
/// evaluation takes the float copies of parameters and profile).
template <class T> T shapeDistanceLocal(const ShapeInstance& s, T x, T y, T z)
{
    using B = BaseScalarT<T>;
    if constexpr (std::is_same_v<B, float>) {
        static const Polygon none;
        const Polygon& polygon = s.polygon ? *s.polygon : none;
        return primitiveDistance(s.kind, x, y, z, [&](int i) { return T(s.paramF[static_cast<std::size_t>(i)]); },
                                 sdf::IndexedProfile<glm::vec2>{polygon.pointsF, polygon.indexF});
    } else {
        static const Polygon none;
        const Polygon& polygon = s.polygon ? *s.polygon : none;
        return primitiveDistance(s.kind, x, y, z, [&](int i) { return T(s.param[static_cast<std::size_t>(i)]); },
                                 sdf::IndexedProfile<glm::dvec2>{polygon.points, polygon.index});
    }
}

} // namespace kerf

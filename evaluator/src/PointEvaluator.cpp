#include "kerf/evaluator/PointEvaluator.hpp"

#include "kerf/evaluator/FeatureTie.h"

#include "kerf/evaluator/Combine.hpp"
#include "kerf/evaluator/Primitives.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace kerf {

namespace {

template <class S> const std::array<S, 12>& frameOf(const ShapeInstance& s)
{
    if constexpr (std::is_same_v<S, float>)
        return s.frameF;
    else
        return s.frame;
}

// Local coordinate `row` of a tape-relative point. For dual numbers the
// derivative of the local coordinate with respect to the tape frame is the
// frame's row: gradients come out in the tape (= world) frame.
template <class V, class S> inline V localCoordinate(const std::array<S, 12>& f, int row, S x, S y, S z)
{
    const auto r = static_cast<std::size_t>(row);
    const S v = f[r * 3] * x + f[r * 3 + 1] * y + f[r * 3 + 2] * z + f[9 + r];
    if constexpr (std::is_same_v<V, S>)
        return v;
    else
        return V(v, f[r * 3], f[r * 3 + 1], f[r * 3 + 2]);
}

// Applies a per-point distance function over a block, with the shape's kind
// already decided: the loop body has no dispatch, so it vectorizes.
template <class V, class S, class F>
inline void forEachPoint(const std::array<S, 12>& f, const S* x, const S* y, const S* z, std::size_t n, V* dst, F&& sdfAt)
{
    for (std::size_t i = 0; i < n; ++i) {
        const V lx = localCoordinate<V>(f, 0, x[i], y[i], z[i]);
        const V ly = localCoordinate<V>(f, 1, x[i], y[i], z[i]);
        const V lz = localCoordinate<V>(f, 2, x[i], y[i], z[i]);
        dst[i] = sdfAt(lx, ly, lz);
    }
}

constexpr std::size_t kMaxBlock = 64;

// Profiles (extrusions, revolves) in plain floating point: edges in the
// outer loop, points in the inner one, so the per-edge work vectorizes
// across points. The profile's plane coordinates (u, v) of each point are
// (x, y) for an extrusion and (length(x, y), z) for a revolve.
//
// A block's points lie close together (a tile's corners, a triangle's
// samples), and most edges of a long profile are far from all of them: an
// edge whose box is further from the points' box than some edge is from
// every point of it (at the box's corners: the distance to a segment is
// convex) cannot be the nearest to any point, and its parity flip only
// matters where its vertical span meets the points'. Such edges are
// skipped or only counted for the parity; the values are the same to the
// bit (the minimum is taken over the same numbers, less some that cannot
// be it). The side chair's curved rails (32 edges) were a fifth of the
// export's marching cubes.
template <class S>
void profileBlock(const ShapeInstance& s, const S* x, const S* y, const S* z, std::size_t n, S* dst)
{
    const auto& f = frameOf<S>(s);
    const bool revolve = s.kind == ShapeKind::Revolve;
    S pu[kMaxBlock], pv[kMaxBlock], lz[kMaxBlock], d[kMaxBlock], sign[kMaxBlock];
    S uLo = std::numeric_limits<S>::infinity(), uHi = -uLo, vLo = uLo, vHi = -uLo;
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) {
        const S lx = localCoordinate<S>(f, 0, x[i], y[i], z[i]);
        const S ly = localCoordinate<S>(f, 1, x[i], y[i], z[i]);
        lz[i] = localCoordinate<S>(f, 2, x[i], y[i], z[i]);
        pu[i] = revolve ? std::sqrt(lx * lx + ly * ly) : lx;
        pv[i] = revolve ? lz[i] : ly;
        d[i] = std::numeric_limits<S>::max();
        sign[i] = S(1);
        uLo = std::min(uLo, pu[i]);
        uHi = std::max(uHi, pu[i]);
        vLo = std::min(vLo, pv[i]);
        vHi = std::max(vHi, pv[i]);
        finite = finite && std::isfinite(pu[i]) && std::isfinite(pv[i]);
    }
    const auto& v = [&]() -> const auto& {
        if constexpr (std::is_same_v<S, float>) return s.polygon->pointsF;
        else return s.polygon->points;
    }();
    const std::size_t m = v.size();
    auto skipped = [&](std::size_t e, std::size_t j) { return revolve && v[e].x == 0 && v[j].x == 0; }; // on the axis: inside the solid (sdf::polygon2d)
    auto squaredDistance = [](S px, S py, S vx, S vy, S ex, S ey, S invLen2) {
        const S wx = px - vx, wy = py - vy;
        const S t = std::min(std::max((wx * ex + wy * ey) * invLen2, S(0)), S(1));
        const S bx = wx - ex * t, by = wy - ey * t;
        return bx * bx + by * by;
    };
    // An edge's largest squared distance to a point of the points' box: at
    // one of its corners (the distance to a segment is convex).
    auto farthest = [&](std::size_t e, std::size_t j) {
        const S vx = S(v[e].x), vy = S(v[e].y), ex = S(v[j].x) - vx, ey = S(v[j].y) - vy;
        const S invLen2 = S(1) / (ex * ex + ey * ey);
        return std::max(std::max(squaredDistance(uLo, vLo, vx, vy, ex, ey, invLen2),
                                 squaredDistance(uLo, vHi, vx, vy, ex, ey, invLen2)),
                        std::max(squaredDistance(uHi, vLo, vx, vy, ex, ey, invLen2),
                                 squaredDistance(uHi, vHi, vx, vy, ex, ey, invLen2)));
    };
    const auto& index = [&]() -> const auto& {
        if constexpr (std::is_same_v<S, float>) return s.polygon->indexF;
        else return s.polygon->index;
    }();
    const bool indexed = finite && index.indexed();
    // Without an index (a short profile), the pruning pays for itself from
    // a few points on (two passes over the edges instead of one over edges
    // and points); every value is finite.
    const bool prune = n >= 8 && m > 8 && finite && !indexed;
    S reach = std::numeric_limits<S>::infinity(); // every point has an edge within this (squared)
    if (prune)
        for (std::size_t e = 0, j = m - 1; e < m; j = e++) {
            if (skipped(e, j)) continue;
            reach = std::min(reach, farthest(e, j));
        }
    if (indexed) {
        // A long profile (PolygonIndex.hpp): the leaves of edges near the
        // points' box against their box, the same test per edge within
        // them, and the parity of each point from its slab's edges; the same
        // formulas as the loop below.
        S gap[kPolygonIndexMaxLeaves];
        const S cutoff = nearEdgesCutoff(index, m, ProfileBox<S>{uLo, uHi, vLo, vHi}, reach, farthest, skipped, gap);
        for (std::size_t k = 0; k < index.leafMin.size(); ++k) {
            if (gap[k] > cutoff) continue;
            forEdgesOfLeaf(index, m, k, skipped, [&](std::size_t e, std::size_t j) {
                const S vx = S(v[e].x), vy = S(v[e].y), vjx = S(v[j].x), vjy = S(v[j].y);
                const S gu = std::max({std::min(vx, vjx) - uHi, uLo - std::max(vx, vjx), S(0)});
                const S gv = std::max({std::min(vy, vjy) - vHi, vLo - std::max(vy, vjy), S(0)});
                if (gu * gu + gv * gv > cutoff) return;
                const S ex = vjx - vx, ey = vjy - vy;
                const S invLen2 = S(1) / (ex * ex + ey * ey);
                for (std::size_t i = 0; i < n; ++i)
                    d[i] = std::min(d[i], squaredDistance(pu[i], pv[i], vx, vy, ex, ey, invLen2));
            });
        }
        for (std::size_t i = 0; i < n; ++i)
            visitEdgesAcross(v, index, pv[i], [&](std::size_t e, std::size_t j) {
                if (skipped(e, j)) return;
                const S vx = S(v[e].x), vy = S(v[e].y), ex = S(v[j].x) - vx, ey = S(v[j].y) - vy;
                const S wx = pu[i] - vx, wy = pv[i] - vy;
                const bool c1 = pv[i] >= vy, c2 = pv[i] < S(v[j].y), c3 = ex * wy > ey * wx;
                if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) sign[i] = -sign[i];
            });
    }
    // (A margin far above the rounding of either side.)
    const S cutoff = reach * S(1.001) + S(1e-12);
    for (std::size_t e = 0, j = m - 1; e < m && !indexed; j = e++) {
        if (skipped(e, j)) continue;
        const S vx = S(v[e].x), vy = S(v[e].y);
        const S ex = S(v[j].x) - vx, ey = S(v[j].y) - vy;
        const S vjx = S(v[j].x), vjy = S(v[j].y);
        bool nearest = true, crosses = true;
        if (prune) {
            const S gapU = std::max({std::min(vx, vjx) - uHi, uLo - std::max(vx, vjx), S(0)});
            const S gapV = std::max({S(std::min(vy, vjy)) - vHi, vLo - S(std::max(vy, vjy)), S(0)});
            nearest = !(gapU * gapU + gapV * gapV > cutoff);
            crosses = !(vHi < std::min(vy, vjy) || vLo >= std::max(vy, vjy));
            if (!nearest && !crosses) continue;
        }
        if (nearest) {
            const S invLen2 = S(1) / (ex * ex + ey * ey);
            for (std::size_t i = 0; i < n; ++i) {
                const S wx = pu[i] - vx, wy = pv[i] - vy;
                const S t = std::min(std::max((wx * ex + wy * ey) * invLen2, S(0)), S(1));
                const S bx = wx - ex * t, by = wy - ey * t;
                d[i] = std::min(d[i], bx * bx + by * by);
                const bool c1 = pv[i] >= vy, c2 = pv[i] < vjy, c3 = ex * wy > ey * wx;
                const bool flip = (c1 && c2 && c3) || (!c1 && !c2 && !c3);
                sign[i] = flip ? -sign[i] : sign[i];
            }
        } else {
            for (std::size_t i = 0; i < n; ++i) {
                const S wx = pu[i] - vx, wy = pv[i] - vy;
                const bool c1 = pv[i] >= vy, c2 = pv[i] < vjy, c3 = ex * wy > ey * wx;
                const bool flip = (c1 && c2 && c3) || (!c1 && !c2 && !c3);
                sign[i] = flip ? -sign[i] : sign[i];
            }
        }
    }
    if (revolve) {
        for (std::size_t i = 0; i < n; ++i) dst[i] = sign[i] * std::sqrt(d[i]);
    } else {
        const S h = S(s.param[0]);
        for (std::size_t i = 0; i < n; ++i) dst[i] = sdf::extrusion(sign[i] * std::sqrt(d[i]), lz[i], h);
    }
}

template <class V, class S>
void evaluateShape(const ShapeInstance& s, const S* x, const S* y, const S* z, std::size_t n, V* dst)
{
    if constexpr (std::is_same_v<V, S>)
        if (s.kind == ShapeKind::Extrude || s.kind == ShapeKind::Revolve) return profileBlock(s, x, y, z, n, dst);
    const auto& f = frameOf<S>(s);
    // The parameters in locals: loads from the shape could alias dst, and
    // would be repeated for every point.
    V param[6];
    for (std::size_t i = 0; i < 6; ++i) {
        if constexpr (std::is_same_v<S, float>)
            param[i] = V(s.paramF[i]);
        else
            param[i] = V(s.param[i]);
    }
    const auto p = [&](int i) { return param[i]; };
    static const Polygon none;
    const Polygon& polygon = s.polygon ? *s.polygon : none;
    const auto profile = [&] {
        if constexpr (std::is_same_v<S, float>) return sdf::IndexedProfile<glm::vec2>{polygon.pointsF, polygon.indexF};
        else return sdf::IndexedProfile<glm::dvec2>{polygon.points, polygon.index};
    }();
    // The kind is decided once per block: the loop body has no dispatch.
    const bool known = primitive::with(s.kind, [&](auto unit) {
        forEachPoint(f, x, y, z, n, dst, [&](V a, V b, V c) { return decltype(unit)::distance(a, b, c, p, profile); });
    });
    // A kind no unit has (out of ShapeKind's range): NaN, never a plane.
    if (!known)
        for (std::size_t i = 0; i < n; ++i) dst[i] = V(std::numeric_limits<S>::quiet_NaN());
}

template <class V> inline bool lessThan(const V& a, const V& b)
{
    if constexpr (std::is_arithmetic_v<V>)
        return a < b;
    else
        return a.v < b.v;
}

} // namespace

template <class V>
void PointEvaluator<V>::evaluate(const Tape& tape, const Scalar* x, const Scalar* y, const Scalar* z, std::size_t n,
                                 V* out, std::uint32_t* features)
{
    if (tape.empty()) {
        std::fill(out, out + n, V(std::numeric_limits<Scalar>::infinity()));
        if (features) std::fill(features, features + n, std::numeric_limits<std::uint32_t>::max());
        return;
    }
    const std::size_t slots = std::size_t(tape.maxStack()) * kBlock;
    if (stack_.size() < slots) stack_.resize(slots);
    if (features && featureStack_.size() < slots) featureStack_.resize(slots);
    for (std::size_t start = 0; start < n; start += kBlock) {
        const std::size_t count = std::min(kBlock, n - start);
        evaluateBlock(tape, x + start, y + start, z + start, count, out + start, features ? features + start : nullptr);
    }
}

template <class V>
void PointEvaluator<V>::evaluateBlock(const Tape& tape, const Scalar* x, const Scalar* y, const Scalar* z,
                                      std::size_t n, V* out, std::uint32_t* features)
{
    using S = Scalar;
    using std::max;
    using std::min;
    V* const st = stack_.data();
    std::uint32_t* const fs = featureStack_.data();
    std::size_t sp = 0; // number of occupied slots
    for (const Instruction& ins : tape.code()) {
        switch (ins.op) {
        case Op::Primitive: {
            const ShapeInstance& s = tape.shapes()[ins.shape];
            evaluateShape(s, x, y, z, n, st + sp * kBlock);
            if (features) std::fill(fs + sp * kBlock, fs + sp * kBlock + n, s.feature);
            ++sp;
            break;
        }
        case Op::Min:
        case Op::Max:
        case Op::SmoothMin:
        case Op::SmoothMax: {
            V* a = st + (sp - 2) * kBlock;
            const V* b = st + (sp - 1) * kBlock;
            if (features) {
                // The deciding feature: the operand the exact min/max would pick.
                std::uint32_t* fa = fs + (sp - 2) * kBlock;
                const std::uint32_t* fb = fs + (sp - 1) * kBlock;
                const bool isMin = ins.op == Op::Min || ins.op == Op::SmoothMin;
                // Within the tie band the left operand keeps it (FeatureTie.h).
                const S tie = static_cast<S>(KERF_FEATURE_TIE);
                for (std::size_t i = 0; i < n; ++i)
                    if (isMin ? lessThan(b[i] + V(tie), a[i]) : lessThan(a[i] + V(tie), b[i])) fa[i] = fb[i];
            }
            const S k = static_cast<S>(ins.k);
            switch (ins.op) {
            case Op::Min:
                for (std::size_t i = 0; i < n; ++i) a[i] = min(a[i], b[i]);
                break;
            case Op::Max:
                for (std::size_t i = 0; i < n; ++i) a[i] = max(a[i], b[i]);
                break;
            case Op::SmoothMin:
                for (std::size_t i = 0; i < n; ++i) a[i] = combine::smoothMin(a[i], b[i], k);
                break;
            default:
                for (std::size_t i = 0; i < n; ++i) a[i] = combine::smoothMax(a[i], b[i], k);
                break;
            }
            --sp;
            break;
        }
        case Op::Negate: {
            V* a = st + (sp - 1) * kBlock;
            for (std::size_t i = 0; i < n; ++i) a[i] = -a[i];
            break;
        }
        case Op::Offset: {
            V* a = st + (sp - 1) * kBlock;
            const V k(static_cast<S>(ins.k));
            for (std::size_t i = 0; i < n; ++i) a[i] = a[i] - k;
            break;
        }
        case Op::Shell: {
            V* a = st + (sp - 1) * kBlock;
            const S t = static_cast<S>(ins.k);
            for (std::size_t i = 0; i < n; ++i) a[i] = combine::shell(a[i], t);
            break;
        }
        }
    }
    std::copy(st, st + n, out);
    if (features) std::copy(fs, fs + n, features);
}

template <class S>
void GradientEvaluator<S>::evaluate(const Tape& tape, const S* x, const S* y, const S* z, std::size_t n, S* distance,
                                    S* gx, S* gy, S* gz, std::uint32_t* features)
{
    if (scratch_.size() < n) scratch_.resize(n);
    points_.evaluate(tape, x, y, z, n, scratch_.data(), features);
    for (std::size_t i = 0; i < n; ++i) {
        distance[i] = scratch_[i].v;
        gx[i] = scratch_[i].d[0];
        gy[i] = scratch_[i].d[1];
        gz[i] = scratch_[i].d[2];
    }
}

template class PointEvaluator<float>;
template class PointEvaluator<double>;
template class PointEvaluator<Dual<float>>;
template class PointEvaluator<Dual<double>>;
template class GradientEvaluator<float>;
template class GradientEvaluator<double>;

} // namespace kerf

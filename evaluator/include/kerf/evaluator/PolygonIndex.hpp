#pragma once
// An index of a long profile's edges, so that the distance and the crossing
// parity at a point need not visit every edge (an extrusion's or revolve's
// profile may have up to 100,000 points; the side chair's curved rails have
// 32, and their edge loops were a fifth of the export's time at 0.01 mm).
//
// - Distance: the edges in runs of consecutive edges ("leaves", about
//   sqrt(n) each, with their boxes). The leaf whose box is nearest gives an
//   upper bound of the distance; a leaf whose box lies further than that
//   holds no edge that can be the nearest, and is skipped. The others are
//   visited in the profile's order, so that whatever the caller keeps (the
//   first nearest edge, for a gradient) is what a visit of every edge keeps.
// - Parity: an edge flips the point's crossing parity only where the
//   point's y lies in [min, max) of its two ends' y, so only the edges that
//   span the horizontal slab between two consecutive vertex heights that
//   holds the point can. Each slab lists those edges.
//
// Both give the values of a loop over every edge to the bit: the same
// operations on the same numbers, less some that cannot change the result.
// Only for finite points (a NaN coordinate flips every edge's parity in
// that loop: callers fall back to it). P is glm::dvec2 or glm::vec2: the
// float evaluation has its own index of its rounded points.

#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace kerf {

template <class P> struct PolygonIndex {
    using S = typename P::value_type;
    /// Edge i runs from point i - 1 (n - 1 for i = 0) to point i, as the
    /// loops over edges take them. 0: no index (a short profile).
    std::size_t leafSize = 0;
    std::vector<P> leafMin, leafMax; // the box of leaf k: edges [k * leafSize, (k + 1) * leafSize)
    std::vector<S> slabY;            // distinct vertex heights, ascending
    std::vector<std::uint32_t> slabStart, slabEdges; // slab k (slabY[k] <= y < slabY[k + 1]): slabEdges[slabStart[k] ..]
    bool hasSlabs = false;           // false where the lists would be too long (every edge is then tested)
    S twiceArea = 0;                 // signed, positive counter-clockwise; summed as polygon2d does

    bool indexed() const { return leafSize != 0; }
};

/// At most this many leaves (their gaps live on the stack of a query).
inline constexpr std::size_t kPolygonIndexMaxLeaves = 512;

template <class P> PolygonIndex<P> buildPolygonIndex(const std::vector<P>& v)
{
    using S = typename P::value_type;
    PolygonIndex<P> index;
    const std::size_t n = v.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++)
        index.twiceArea += S(v[j].x) * S(v[i].y) - S(v[i].x) * S(v[j].y);
    // Below this, the loop over every edge is as quick.
    if (n < 16) return index;
    index.leafSize = std::max<std::size_t>({4, std::size_t(std::ceil(std::sqrt(double(n)))),
                                            (n + kPolygonIndexMaxLeaves - 1) / kPolygonIndexMaxLeaves});
    for (std::size_t first = 0; first < n; first += index.leafSize) {
        P lo(std::numeric_limits<S>::infinity()), hi(-std::numeric_limits<S>::infinity());
        for (std::size_t i = first; i < std::min(n, first + index.leafSize); ++i) {
            const P& a = v[i];
            const P& b = v[i == 0 ? n - 1 : i - 1];
            lo = P(std::min({lo.x, a.x, b.x}), std::min({lo.y, a.y, b.y}));
            hi = P(std::max({hi.x, a.x, b.x}), std::max({hi.y, a.y, b.y}));
        }
        index.leafMin.push_back(lo);
        index.leafMax.push_back(hi);
    }
    for (const P& p : v)
        index.slabY.push_back(p.y);
    std::sort(index.slabY.begin(), index.slabY.end());
    index.slabY.erase(std::unique(index.slabY.begin(), index.slabY.end()), index.slabY.end());
    const std::size_t slabs = index.slabY.size();
    auto slabOf = [&](S y) { return std::size_t(std::lower_bound(index.slabY.begin(), index.slabY.end(), y) - index.slabY.begin()); };
    // Count, then fill; a profile whose edges span many slabs each (a comb
    // of long teeth) would need lists of n^2: it goes without. (At most 8
    // entries a point: the format's million profile points cost at most
    // 64 MB of lists in its two precisions; outlines need two to four.)
    std::vector<std::uint32_t> count(slabs + 1, 0);
    std::size_t total = 0;
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const std::size_t a = slabOf(std::min(v[i].y, v[j].y)), b = slabOf(std::max(v[i].y, v[j].y));
        for (std::size_t k = a; k < b; ++k)
            ++count[k];
        total += b - a;
        if (total > 8 * n + 1024) return index;
    }
    index.slabStart.assign(slabs + 1, 0);
    for (std::size_t k = 0; k < slabs; ++k)
        index.slabStart[k + 1] = index.slabStart[k] + count[k];
    index.slabEdges.resize(total);
    std::vector<std::uint32_t> fill(index.slabStart.begin(), index.slabStart.end() - 1);
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const std::size_t a = slabOf(std::min(v[i].y, v[j].y)), b = slabOf(std::max(v[i].y, v[j].y));
        for (std::size_t k = a; k < b; ++k)
            index.slabEdges[fill[k]++] = std::uint32_t(i);
    }
    index.hasSlabs = true;
    return index;
}

/// A box of the profile's plane (a point where lo == hi).
template <class S> struct ProfileBox {
    S uLo, uHi, vLo, vHi;
};

/// The squared gap between leaf k's box and `box` (0 where they meet).
template <class S, class P> S leafGap(const PolygonIndex<P>& index, std::size_t k, const ProfileBox<S>& box)
{
    const S du = std::max({S(index.leafMin[k].x) - box.uHi, box.uLo - S(index.leafMax[k].x), S(0)});
    const S dv = std::max({S(index.leafMin[k].y) - box.vHi, box.vLo - S(index.leafMax[k].y), S(0)});
    return du * du + dv * dv;
}

/// Calls visit(i, j) for each edge of leaf k of a profile of n points that
/// skip(i, j) does not rule out, in order.
template <class P, class Skip, class Visit>
void forEdgesOfLeaf(const PolygonIndex<P>& index, std::size_t n, std::size_t k, const Skip& skip, const Visit& visit)
{
    const std::size_t first = k * index.leafSize, last = std::min(n, first + index.leafSize);
    for (std::size_t i = first; i < last; ++i) {
        const std::size_t j = i == 0 ? n - 1 : i - 1;
        if (!skip(i, j)) visit(i, j);
    }
}

/// The squared distance beyond which no edge is the nearest to any point
/// of `box`: `farthest(i, j)` bounds edge i's squared distance over the box
/// from above (at a point, its distance), taken over the leaf whose box is
/// nearest, and `bound` already holds (with a margin far above the rounding
/// of either side). gap[k] is leaf k's leafGap.
template <class S, class P, class Farthest, class Skip>
S nearEdgesCutoff(const PolygonIndex<P>& index, std::size_t n, const ProfileBox<S>& box, S bound,
                  const Farthest& farthest, const Skip& skip, S* gap)
{
    std::size_t nearest = 0;
    for (std::size_t k = 0; k < index.leafMin.size(); ++k) {
        gap[k] = leafGap(index, k, box);
        if (gap[k] < gap[nearest]) nearest = k;
    }
    forEdgesOfLeaf(index, n, nearest, skip, [&](std::size_t i, std::size_t j) { bound = std::min(bound, farthest(i, j)); });
    return bound + bound * S(1e-3) + S(1e-30);
}

/// Calls visit(i, j) for every edge (v[j], v[i]) that can be the nearest to
/// (x, y) with a squared distance of at most `bound`, in the profile's
/// order; `squared(i, j)` is the caller's squared distance to an edge, and
/// `skip(i, j)` true for edges that count for nothing (a revolve's axis).
/// With the index (x, y finite); else every edge.
template <class S, class P, class Squared, class Skip, class Visit>
void visitNearEdges(const std::vector<P>& v, const PolygonIndex<P>& index, S x, S y, S bound, const Squared& squared,
                    const Skip& skip, const Visit& visit)
{
    const std::size_t n = v.size();
    if (!index.indexed()) {
        for (std::size_t i = 0, j = n - 1; i < n; j = i++)
            if (!skip(i, j)) visit(i, j);
        return;
    }
    S gap[kPolygonIndexMaxLeaves];
    const S cutoff = nearEdgesCutoff(index, n, ProfileBox<S>{x, x, y, y}, bound, squared, skip, gap);
    for (std::size_t k = 0; k < index.leafMin.size(); ++k)
        if (!(gap[k] > cutoff)) forEdgesOfLeaf(index, n, k, skip, visit);
}

/// The edges that can flip the crossing parity at height y: calls
/// visit(i, j) for each (every edge without slabs).
template <class S, class P, class Visit>
void visitEdgesAcross(const std::vector<P>& v, const PolygonIndex<P>& index, S y, const Visit& visit)
{
    const std::size_t n = v.size();
    if (!index.hasSlabs) {
        for (std::size_t i = 0, j = n - 1; i < n; j = i++)
            visit(i, j);
        return;
    }
    // The slab holding y: the last height at or below it.
    const auto above = std::upper_bound(index.slabY.begin(), index.slabY.end(), y, [](S a, S b) { return a < S(b); });
    if (above == index.slabY.begin()) return; // below every vertex
    const std::size_t k = std::size_t(above - index.slabY.begin()) - 1;
    for (std::uint32_t e = index.slabStart[k]; e < index.slabStart[k + 1]; ++e) {
        const std::size_t i = index.slabEdges[e];
        visit(i, i == 0 ? n - 1 : i - 1);
    }
}

} // namespace kerf

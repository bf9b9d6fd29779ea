#include "kerf/mesher/SelfIntersections.hpp"

#include "TriangleClearance.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <atomic>
#include <limits>

namespace kerf {

namespace {

// A box in float, rounded outwards: it holds the double box it was made
// from, so a pair whose boxes do not meet here does not meet at all. Half
// the memory of doubles (the side chair's 9.5 M marching-cubes triangles
// and their hierarchy: 0.8 GB in double), read once per visit.
struct Box {
    glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
    static float below(double v)
    {
        const float f = float(v);
        return double(f) <= v ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
    }
    static float above(double v)
    {
        const float f = float(v);
        return double(f) >= v ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
    }
    void add(const glm::dvec3& p, double grow)
    {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], below(p[a] - grow));
            hi[a] = std::max(hi[a], above(p[a] + grow));
        }
    }
    void add(const Box& b)
    {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    bool meets(const Box& b) const
    {
        return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y && lo.z <= b.hi.z &&
               b.lo.z <= hi.z;
    }
};

// 21 bits of v (below 2^21) spread to every third bit.
std::uint64_t spreadBits(std::uint64_t v)
{
    v &= 0x1FFFFF;
    v = (v | v << 32) & 0x1F00000000FFFFull;
    v = (v | v << 16) & 0x1F0000FF0000FFull;
    v = (v | v << 8) & 0x100F00F00F00F00Full;
    v = (v | v << 4) & 0x10C30C30C30C30C3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

// The boxes in the Morton order of their centres (ties by index, so the
// order does not depend on the threads).
std::vector<std::uint32_t> mortonOrder(const std::vector<Box>& boxes)
{
    const std::size_t n = boxes.size();
    auto centre = [&](std::size_t i) { return 0.5 * (glm::dvec3(boxes[i].lo) + glm::dvec3(boxes[i].hi)); };
    const Box all = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, std::size_t(1) << 14), Box(),
        [&](const tbb::blocked_range<std::size_t>& r, Box b) {
            for (std::size_t i = r.begin(); i != r.end(); ++i)
                b.add(centre(i), 0.0);
            return b;
        },
        [](Box a, const Box& b) {
            a.add(b);
            return a;
        });
    const glm::dvec3 low(all.lo), extent = glm::max(glm::dvec3(all.hi) - low, glm::dvec3(1e-30));
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::size_t(1) << 14),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const glm::dvec3 u = (centre(i) - low) / extent * 2097151.0;
            std::uint64_t key = 0;
            for (int a = 0; a < 3; ++a) // (a box that is not finite: cell 0, still found by the boxes' test)
                key |= spreadBits(u[a] >= 0.0 && u[a] <= 2097151.0 ? std::uint64_t(u[a]) : 0) << a;
            keyed[i] = {key, std::uint32_t(i)};
        }
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i)
        order[i] = keyed[i].second;
    return order;
}

// A bounding volume hierarchy: the triangles in the Morton order of their
// boxes' centres, each node over a range of that order and its children
// over the range's halves, the boxes from the leaves up. Built on the
// arena's threads: the side chair's 9.5 M marching-cubes triangles took
// 4 s on one thread with median splits of the longest axis (a pass over
// every range for its box and one for its median).
class Hierarchy {
public:
    explicit Hierarchy(const std::vector<Box>& boxes) : boxes_(boxes)
    {
        if (boxes.empty()) return;
        order_ = mortonOrder(boxes);
        std::vector<std::pair<std::uint32_t, std::uint32_t>> memo;
        nodes_.resize(nodeCount(std::uint32_t(boxes.size()), memo));
        build(0, 0, std::uint32_t(boxes.size()));
    }

    /// Calls visit(s, t) once for every unordered pair of distinct boxes
    /// that meet (s, t: their indices), from the arena's threads; stops
    /// early once `stop` returns true (asked now and then). searched(k):
    /// the pairs within k more boxes are all visited (the pairs across the
    /// largest subtrees, fewer, come on top), about once per 30,000 boxes.
    template <class Visit, class Stop, class Searched>
    void forEachMeetingPair(Visit&& visit, Stop&& stop, Searched&& searched) const
    {
        if (nodes_.empty()) return;
        within(0, visit, stop, searched);
        if (nodes_[0].size <= kParallelRange) searched(nodes_[0].size);
    }

private:
    struct Node {
        Box box;
        std::uint32_t first = 0; // leaf: first index into order_; inner: first child
        std::uint32_t count = 0; // leaf: triangles; inner: 0
        std::uint32_t size = 0;  // triangles under it
    };
    static constexpr std::uint32_t kLeaf = 4;
    static constexpr std::uint32_t kParallelRange = 1u << 15;

    // The nodes of a tree over n boxes. The ranges of one level differ in
    // size by one at most: the memo of (size, nodes) stays short.
    static std::uint32_t nodeCount(std::uint32_t n, std::vector<std::pair<std::uint32_t, std::uint32_t>>& memo)
    {
        if (n <= kLeaf) return 1;
        for (const auto& [size, count] : memo)
            if (size == n) return count;
        const std::uint32_t count = 1 + nodeCount(n / 2, memo) + nodeCount(n - n / 2, memo);
        memo.emplace_back(n, count);
        return count;
    }

    // The pairs within node n: those within each child, then those across.
    // A child searched on one thread is counted as searched when done.
    template <class Visit, class Stop, class Searched>
    void within(std::uint32_t n, Visit& visit, Stop& stop, Searched& searched) const
    {
        const Node& node = nodes_[n];
        if (node.count > 0) {
            for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
                for (std::uint32_t j = i + 1; j < node.first + node.count; ++j)
                    if (boxes_[order_[i]].meets(boxes_[order_[j]])) visit(order_[i], order_[j]);
            return;
        }
        if (stop()) return;
        const std::uint32_t l = node.first, r = node.first + 1;
        if (node.size > kParallelRange) {
            auto child = [&](std::uint32_t c) {
                within(c, visit, stop, searched);
                if (nodes_[c].size <= kParallelRange) searched(nodes_[c].size);
            };
            tbb::parallel_invoke([&] { child(l); }, [&] { child(r); }, [&] { across(l, r, visit, stop); });
        } else {
            within(l, visit, stop, searched);
            within(r, visit, stop, searched);
            across(l, r, visit, stop);
        }
    }

    // The pairs with one box under node m and the other under node n
    // (different subtrees): the larger node is opened first.
    template <class Visit, class Stop>
    void across(std::uint32_t m, std::uint32_t n, Visit& visit, Stop& stop) const
    {
        const Node &a = nodes_[m], &b = nodes_[n];
        if (!a.box.meets(b.box)) return;
        if (a.count > 0 && b.count > 0) {
            for (std::uint32_t i = a.first; i < a.first + a.count; ++i)
                for (std::uint32_t j = b.first; j < b.first + b.count; ++j)
                    if (boxes_[order_[i]].meets(boxes_[order_[j]])) visit(order_[i], order_[j]);
            return;
        }
        const bool openA = b.count > 0 || (a.count == 0 && a.size >= b.size);
        const std::uint32_t open = openA ? m : n, other = openA ? n : m;
        const std::uint32_t l = nodes_[open].first, r = l + 1;
        if (nodes_[open].size + nodes_[other].size > kParallelRange) {
            if (stop()) return;
            tbb::parallel_invoke([&] { across(l, other, visit, stop); }, [&] { across(r, other, visit, stop); });
        } else {
            across(l, other, visit, stop);
            across(r, other, visit, stop);
        }
    }

    // Node `index` over order_[begin, end): its two children side by side
    // (first names both), at the next free pair of nodes_ (sized for the
    // whole tree beforehand, so threads never move it).
    void build(std::uint32_t index, std::uint32_t begin, std::uint32_t end)
    {
        Node& node = nodes_[index];
        node.size = end - begin;
        if (end - begin <= kLeaf) {
            node.first = begin;
            node.count = end - begin;
            for (std::uint32_t i = begin; i < end; ++i)
                node.box.add(boxes_[order_[i]]);
            return;
        }
        const std::uint32_t mid = begin + (end - begin) / 2;
        const std::uint32_t children = next_.fetch_add(2, std::memory_order_relaxed);
        if (end - begin > kParallelRange)
            tbb::parallel_invoke([&] { build(children, begin, mid); }, [&] { build(children + 1, mid, end); });
        else {
            build(children, begin, mid);
            build(children + 1, mid, end);
        }
        node.first = children;
        node.count = 0;
        node.box = nodes_[children].box;
        node.box.add(nodes_[children + 1].box);
    }

    const std::vector<Box>& boxes_;
    std::vector<std::uint32_t> order_;
    std::vector<Node> nodes_;
    std::atomic<std::uint32_t> next_{1}; // the root is node 0
};

// 2D: whether segments ab and cd cross properly.
bool crosses2(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d)
{
    auto o = [](const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& r) {
        return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    };
    const double d1 = o(a, b, c), d2 = o(a, b, d), d3 = o(c, d, a), d4 = o(c, d, b);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

bool inside2(const glm::dvec2& p, const glm::dvec2* t)
{
    auto o = [](const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
        return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    };
    const double s1 = o(t[0], t[1], p), s2 = o(t[1], t[2], p), s3 = o(t[2], t[0], p);
    return (s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0);
}

// Whether the line of an edge of triangle T (indices, corners t) has every
// corner of U (indices, corners u) strictly on the side away from T's third
// corner, but the corners of U that are that edge's ends.
bool edgeSeparates(const std::array<std::uint32_t, 3>& T, const glm::dvec2* t, const std::array<std::uint32_t, 3>& U,
                   const glm::dvec2* u)
{
    auto o = [](const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
        return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    };
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        const double own = o(t[i], t[j], t[k]);
        if (own == 0.0) continue;
        bool apart = true;
        for (int m = 0; m < 3 && apart; ++m) {
            if (U[std::size_t(m)] == T[std::size_t(i)] || U[std::size_t(m)] == T[std::size_t(j)]) continue;
            const double other = o(t[i], t[j], u[m]);
            apart = own > 0.0 ? other < 0.0 : other > 0.0;
        }
        if (apart) return true;
    }
    return false;
}

// The two axes of the plane with normal n that keep its area best.
int droppedAxis(const glm::dvec3& n)
{
    const glm::dvec3 m = glm::abs(n);
    return m.x > m.y ? (m.x > m.z ? 0 : 2) : (m.y > m.z ? 1 : 2);
}
glm::dvec2 flatten(const glm::dvec3& p, int drop)
{
    return drop == 0 ? glm::dvec2(p.y, p.z) : drop == 1 ? glm::dvec2(p.x, p.z) : glm::dvec2(p.x, p.y);
}

// Whether segment pq passes through the inside of triangle abc: its ends
// on opposite sides of the plane, and the point where it meets the plane
// strictly inside the triangle (in the plane's best projection). Not
// orientations of pq against abc's edges: for a segment nearly in the
// plane those are rounding noise.
bool segmentCrosses(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b,
                    const glm::dvec3& c)
{
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double sp = glm::dot(n, p - a), sq = glm::dot(n, q - a);
    if (!((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0))) return false;
    const glm::dvec3 x = p + (q - p) * (sp / (sp - sq));
    const int drop = droppedAxis(n);
    const glm::dvec2 t[3] = {flatten(a, drop), flatten(b, drop), flatten(c, drop)};
    return inside2(flatten(x, drop), t);
}

} // namespace

namespace {

template <bool kQuickRejections>
bool crossingTest(const std::array<std::uint32_t, 3>& A, const glm::dvec3* a, const std::array<std::uint32_t, 3>& B,
                  const glm::dvec3* b)
{
    int shared = 0;
    for (const std::uint32_t u : A)
        for (const std::uint32_t v : B)
            if (u == v) ++shared;
    // In one plane to rounding (a flat face simplified into large triangles
    // is not exactly planar in double): distances of A's corners from B's
    // plane within a billionth of the triangles' size.
    const glm::dvec3 nb = glm::cross(b[1] - b[0], b[2] - b[0]);
    const double nbLength = glm::length(nb);
    const double size = std::max({glm::length(a[1] - a[0]), glm::length(a[2] - a[1]), glm::length(a[0] - a[2]),
                                  glm::length(b[1] - b[0]), glm::length(b[2] - b[1]), glm::length(b[0] - b[2])});
    const double inPlane = 1e-9 * size * nbLength;
    const double side[3] = {glm::dot(nb, a[0] - b[0]), glm::dot(nb, a[1] - b[0]), glm::dot(nb, a[2] - b[0])};
    bool coplanar = nbLength > 0.0;
    for (int i = 0; i < 3 && coplanar; ++i)
        coplanar = std::abs(side[i]) <= inPlane;
    // The corners of A that B does not share all beyond B's plane, by more
    // than the rounding above, on one side: A meets B's plane at most in
    // what they share (most pairs a mesh's boxes bring together:
    // neighbours on a curved sheet).
    bool above = true, below = true;
    for (int i = 0; i < 3; ++i) {
        if (std::find(B.begin(), B.end(), A[std::size_t(i)]) != B.end()) continue;
        above = above && side[i] > inPlane;
        below = below && side[i] < -inPlane;
    }
    if (kQuickRejections && shared < 3 && (above || below)) return false;
    if (coplanar) {
        // Project to the plane's dominant axes; overlap other than at what
        // they share.
        const int drop = droppedAxis(nb);
        auto flat = [&](const glm::dvec3& p) { return flatten(p, drop); };
        const glm::dvec2 fa[3] = {flat(a[0]), flat(a[1]), flat(a[2])}, fb[3] = {flat(b[0]), flat(b[1]), flat(b[2])};
        // Apart where the line of an edge of one has the other's corners
        // (but those it shares with that edge) strictly on its far side: two
        // triangles of a plane that do not overlap always have such an edge,
        // and the faces of a flat board give most of the pairs.
        if (kQuickRejections && (edgeSeparates(A, fa, B, fb) || edgeSeparates(B, fb, A, fa))) return false;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (crosses2(fa[i], fa[(i + 1) % 3], fb[j], fb[(j + 1) % 3])) return true;
        for (int i = 0; i < 3; ++i) {
            if (std::find(B.begin(), B.end(), A[std::size_t(i)]) == B.end() && inside2(fa[i], fb)) return true;
            if (std::find(A.begin(), A.end(), B[std::size_t(i)]) == A.end() && inside2(fb[i], fa)) return true;
        }
        return false;
    }
    if (shared >= 2) return false; // not in one plane: they meet along their edge only
    // Edges of one against the other; with a shared vertex, only the edges
    // away from it can cross (one through it meets the other's plane there).
    for (int i = 0; i < 3; ++i) {
        const std::uint32_t p = A[std::size_t(i)], q = A[std::size_t(i + 1) % 3];
        const bool touchesShared = std::find(B.begin(), B.end(), p) != B.end() || std::find(B.begin(), B.end(), q) != B.end();
        if (!touchesShared && segmentCrosses(a[i], a[(i + 1) % 3], b[0], b[1], b[2])) return true;
    }
    for (int i = 0; i < 3; ++i) {
        const std::uint32_t p = B[std::size_t(i)], q = B[std::size_t(i + 1) % 3];
        const bool touchesShared = std::find(A.begin(), A.end(), p) != A.end() || std::find(A.begin(), A.end(), q) != A.end();
        if (!touchesShared && segmentCrosses(b[i], b[(i + 1) % 3], a[0], a[1], a[2])) return true;
    }
    return false;
}

} // namespace

bool trianglesCross(const std::array<std::uint32_t, 3>& A, const glm::dvec3* a, const std::array<std::uint32_t, 3>& B,
                    const glm::dvec3* b)
{
    return crossingTest<true>(A, a, B, b);
}

bool trianglesCrossExhaustively(const std::array<std::uint32_t, 3>& A, const glm::dvec3* a,
                                const std::array<std::uint32_t, 3>& B, const glm::dvec3* b)
{
    return crossingTest<false>(A, a, B, b);
}

namespace {

// The pairs of triangles whose boxes, grown by `margin`, meet and for which
// `hit(s, t, a, b)` holds (corners a of s, b of t).
template <class Hit>
SelfIntersections findPairs(const Mesh& mesh, double margin, std::size_t examples, const Progress& work, Hit&& hit)
{
    SelfIntersections out;
    std::vector<Box> boxes(mesh.triangles.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, boxes.size(), std::size_t(1) << 14),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t t = r.begin(); t != r.end(); ++t) {
            for (const std::uint32_t v : mesh.triangles[t])
                boxes[t].add(mesh.vertices[v], 0.5 * margin);
        }
    });
    const Hierarchy hierarchy(boxes);
    std::atomic<std::size_t> pairs{0};
    std::mutex mutex;
    std::atomic<bool> stop{false};
    std::atomic<std::size_t> searched{0};
    hierarchy.forEachMeetingPair(
        [&](std::uint32_t s, std::uint32_t t) {
            const auto& A = mesh.triangles[s];
            const auto& B = mesh.triangles[t];
            const glm::dvec3 a[3] = {mesh.vertices[A[0]], mesh.vertices[A[1]], mesh.vertices[A[2]]};
            const glm::dvec3 b[3] = {mesh.vertices[B[0]], mesh.vertices[B[1]], mesh.vertices[B[2]]};
            if (!hit(A, a, B, b)) return;
            ++pairs;
            if (examples == 0) return;
            // The lowest pairs, kept in a max-heap: the same examples
            // whatever order the threads find them in.
            const std::array<std::uint32_t, 2> pair{std::min(s, t), std::max(s, t)};
            std::lock_guard lock(mutex);
            if (out.examples.size() < examples) {
                out.examples.push_back(pair);
                std::push_heap(out.examples.begin(), out.examples.end());
            } else if (pair < out.examples.front()) {
                std::pop_heap(out.examples.begin(), out.examples.end());
                out.examples.back() = pair;
                std::push_heap(out.examples.begin(), out.examples.end());
            }
        },
        [&] {
            if (stop.load(std::memory_order_relaxed)) return true;
            if (work.cancelled()) stop = true;
            return stop.load(std::memory_order_relaxed);
        },
        [&](std::uint32_t count) {
            const std::size_t done = searched.fetch_add(count, std::memory_order_relaxed) + count;
            // (the pairs across the largest subtrees may still be running)
            work.report(0.95 * double(done) / double(mesh.triangles.size()));
        });
    out.pairs = pairs;
    out.stopped = stop;
    if (!out.stopped) work.report(1.0);
    std::sort(out.examples.begin(), out.examples.end());
    return out;
}

} // namespace

SelfIntersections findSelfIntersections(const Mesh& mesh, std::size_t examples, const Progress& work)
{
    return findPairs(mesh, 0.0, examples, work, [](const auto& A, const glm::dvec3* a, const auto& B, const glm::dvec3* b) {
        return trianglesCross(A, a, B, b);
    });
}

SelfIntersections findTrianglesCloserThan(const Mesh& mesh, double clearance, std::size_t examples,
                                          const Progress& work)
{
    return findPairs(mesh, clearance, examples, work,
                     [clearance](const auto& A, const glm::dvec3* a, const auto& B, const glm::dvec3* b) {
        return mesher::trianglesTooClose(A, a, B, b, clearance);
    });
}

} // namespace kerf

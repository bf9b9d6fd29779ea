#include "kerf/mesher/SelfIntersections.hpp"

#include "TriangleClearance.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <mutex>
#include <atomic>
#include <limits>
#include <numeric>

namespace kerf {

namespace {

struct Box {
    glm::dvec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
    void add(const glm::dvec3& p)
    {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
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

// A bounding volume hierarchy: nodes over ranges of a triangle order,
// split at the median of the longest axis of the centroids' box.
class Hierarchy {
public:
    explicit Hierarchy(const std::vector<Box>& boxes) : boxes_(boxes), order_(boxes.size())
    {
        std::iota(order_.begin(), order_.end(), 0u);
        if (!boxes.empty()) build(0, std::uint32_t(boxes.size()));
    }

    template <class Visit> void query(const Box& box, Visit&& visit) const
    {
        if (nodes_.empty()) return;
        std::uint32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& n = nodes_[stack[--top]];
            if (!n.box.meets(box)) continue;
            if (n.count > 0) {
                for (std::uint32_t i = n.first; i < n.first + n.count; ++i)
                    if (boxes_[order_[i]].meets(box)) visit(order_[i]);
            } else {
                stack[top++] = n.first;
                stack[top++] = n.first + 1;
            }
        }
    }

private:
    struct Node {
        Box box;
        std::uint32_t first = 0; // leaf: first index into order_; inner: first child
        std::uint32_t count = 0; // leaf: triangles; inner: 0
    };

    std::uint32_t build(std::uint32_t begin, std::uint32_t end)
    {
        const std::uint32_t index = std::uint32_t(nodes_.size());
        nodes_.emplace_back();
        Box box, centres;
        for (std::uint32_t i = begin; i < end; ++i) {
            box.add(boxes_[order_[i]]);
            centres.add(0.5 * (boxes_[order_[i]].lo + boxes_[order_[i]].hi));
        }
        nodes_[index].box = box;
        if (end - begin <= 4) {
            nodes_[index].first = begin;
            nodes_[index].count = end - begin;
            return index;
        }
        const glm::dvec3 extent = centres.hi - centres.lo;
        const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
        const std::uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                         [&](std::uint32_t a, std::uint32_t b) {
                             return boxes_[a].lo[axis] + boxes_[a].hi[axis] < boxes_[b].lo[axis] + boxes_[b].hi[axis];
                         });
        // Children are adjacent: reserve both before building either.
        const std::uint32_t children = std::uint32_t(nodes_.size());
        nodes_.emplace_back();
        nodes_.emplace_back();
        nodes_[index].first = children;
        buildInto(children, begin, mid);
        buildInto(children + 1, mid, end);
        return index;
    }
    void buildInto(std::uint32_t slot, std::uint32_t begin, std::uint32_t end)
    {
        const std::uint32_t built = build(begin, end);
        nodes_[slot] = nodes_[built];
    }

    const std::vector<Box>& boxes_;
    std::vector<std::uint32_t> order_;
    std::vector<Node> nodes_;
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

bool trianglesCross(const std::array<std::uint32_t, 3>& A, const glm::dvec3* a, const std::array<std::uint32_t, 3>& B,
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
    bool coplanar = nbLength > 0.0;
    for (int i = 0; i < 3 && coplanar; ++i)
        coplanar = std::abs(glm::dot(nb, a[i] - b[0])) <= 1e-9 * size * nbLength;
    if (coplanar) {
        // Project to the plane's dominant axes; overlap other than at what
        // they share.
        const int drop = droppedAxis(nb);
        auto flat = [&](const glm::dvec3& p) { return flatten(p, drop); };
        const glm::dvec2 fa[3] = {flat(a[0]), flat(a[1]), flat(a[2])}, fb[3] = {flat(b[0]), flat(b[1]), flat(b[2])};
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

namespace {

// The pairs of triangles whose boxes, grown by `margin`, meet and for which
// `hit(s, t, a, b)` holds (corners a of s, b of t).
template <class Hit>
SelfIntersections findPairs(const Mesh& mesh, double margin, std::size_t examples, const Progress& work, Hit&& hit)
{
    SelfIntersections out;
    std::vector<Box> boxes(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (const std::uint32_t v : mesh.triangles[t])
            boxes[t].add(mesh.vertices[v]);
        boxes[t].lo -= glm::dvec3(0.5 * margin);
        boxes[t].hi += glm::dvec3(0.5 * margin);
    }
    const Hierarchy hierarchy(boxes);
    std::atomic<std::size_t> pairs{0};
    std::mutex mutex;
    std::atomic<bool> stop{false};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
        if (stop.load(std::memory_order_relaxed)) return;
        if (work.cancelled()) {
            stop = true;
            return;
        }
        for (std::size_t s = range.begin(); s != range.end(); ++s)
            hierarchy.query(boxes[s], [&](std::uint32_t t) {
                if (t <= s) return;
                const auto& A = mesh.triangles[s];
                const auto& B = mesh.triangles[t];
                const glm::dvec3 a[3] = {mesh.vertices[A[0]], mesh.vertices[A[1]], mesh.vertices[A[2]]};
                const glm::dvec3 b[3] = {mesh.vertices[B[0]], mesh.vertices[B[1]], mesh.vertices[B[2]]};
                if (!hit(A, a, B, b)) return;
                ++pairs;
                std::lock_guard lock(mutex);
                if (out.examples.size() < examples) out.examples.push_back({std::uint32_t(s), t});
            });
    });
    out.pairs = pairs;
    out.stopped = stop;
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

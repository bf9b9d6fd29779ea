#include "kerf/document/ProfileCheck.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <set>

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

bool lexLess(const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

// Finds two non-neighbouring edges of the closed polygon that touch, in
// O(n log n): a Shamos-Hoey sweep from left to right. Edges are kept in the
// order they cross the sweep line; two edges that touch are next to each
// other in that order just before the leftmost point where any pair touches,
// so it is enough to test each edge against its neighbours when it enters and
// the two neighbours of each edge that leaves. The order is decided where an
// edge enters, by the side of the other edge's line its left end lies on (its
// right end when the left end is on the line), so no edge is ever compared
// at a sweep position it has already passed.
class TouchingEdges {
public:
    TouchingEdges(const std::vector<glm::dvec2>& p, double eps) : p_(p), n_(p.size()), eps_(eps)
    {
        left_.resize(n_);
        right_.resize(n_);
        for (std::size_t i = 0; i < n_; ++i) {
            const glm::dvec2 a = p[i], b = p[(i + 1) % n_];
            left_[i] = lexLess(b, a) ? b : a;
            right_[i] = lexLess(b, a) ? a : b;
        }
    }

    std::optional<std::pair<std::size_t, std::size_t>> find()
    {
        struct Event {
            glm::dvec2 at;
            bool leaves; // the edge's right end: it leaves the sweep line
            std::size_t edge;
        };
        std::vector<Event> events;
        events.reserve(2 * n_);
        for (std::size_t i = 0; i < n_; ++i) {
            events.push_back({left_[i], false, i});
            events.push_back({right_[i], true, i});
        }
        // Left to right; at one point, edges enter before any leaves, so that
        // edges meeting at a point are in the line together.
        std::sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
            if (a.at != b.at) return lexLess(a.at, b.at);
            if (a.leaves != b.leaves) return !a.leaves;
            return a.edge < b.edge;
        });
        Order order{this};
        std::set<std::size_t, Order> line(order);
        std::vector<std::set<std::size_t, Order>::iterator> where(n_, line.end());
        for (const Event& e : events) {
            if (!e.leaves) {
                entering_ = e.edge;
                const auto it = line.insert(e.edge).first;
                where[e.edge] = it;
                if (it != line.begin())
                    if (auto hit = test(*std::prev(it), e.edge)) return hit;
                if (std::next(it) != line.end())
                    if (auto hit = test(e.edge, *std::next(it))) return hit;
            } else {
                const auto it = where[e.edge];
                if (it != line.begin() && std::next(it) != line.end())
                    if (auto hit = test(*std::prev(it), *std::next(it))) return hit;
                line.erase(it);
            }
        }
        return std::nullopt;
    }

private:
    // Below-to-above order of the edges on the sweep line. std::set compares
    // only the entering edge with edges already in the line.
    struct Order {
        const TouchingEdges* self;
        bool operator()(std::size_t a, std::size_t b) const
        {
            if (a == b) return false;
            if (a == self->entering_) return self->side(a, b) < 0;
            if (b == self->entering_) return self->side(b, a) > 0;
            return a < b; // never reached: the line's own order is never re-examined
        }
    };

    // Which side of edge t's line the entering edge s lies on: +1 above, -1
    // below; ties by edge index (collinear edges touch, and are reported).
    int side(std::size_t s, std::size_t t) const
    {
        const glm::dvec2 a = left_[t], b = right_[t];
        double v = cross(b - a, left_[s] - a);
        if (v == 0.0) v = cross(b - a, right_[s] - a);
        if (v > 0.0) return 1;
        if (v < 0.0) return -1;
        return s > t ? 1 : -1;
    }

    bool neighbours(std::size_t i, std::size_t j) const
    {
        const std::size_t d = i > j ? i - j : j - i;
        return d == 1 || d == n_ - 1;
    }

    std::optional<std::pair<std::size_t, std::size_t>> test(std::size_t i, std::size_t j) const
    {
        if (i == j || neighbours(i, j)) return std::nullopt;
        if (!segmentsTouch(p_[i], p_[(i + 1) % n_], p_[j], p_[(j + 1) % n_], eps_)) return std::nullopt;
        return std::make_pair(std::min(i, j), std::max(i, j));
    }

    const std::vector<glm::dvec2>& p_;
    std::size_t n_;
    double eps_;
    std::vector<glm::dvec2> left_, right_;
    std::size_t entering_ = 0;
};
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
    // Points and edges are numbered from 1, as the application's profile
    // table numbers its rows (edge k runs from point k to the next).
    const auto number = [](std::size_t i) { return std::to_string(i + 1); };
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        if (glm::length(p[j] - p[i]) <= extent * 1e-9)
            return j == 0 ? "the last point repeats the first (the profile closes itself; do not repeat the first point)"
                          : "point " + number(j) + " repeats point " + number(i) + " (two points in a row at one place)";
    }
    // Every point on one line: no area, whatever folds back along it.
    std::size_t far = 0;
    for (std::size_t i = 1; i < n; ++i)
        if (glm::length(p[i] - p[0]) > glm::length(p[far] - p[0])) far = i;
    bool onOneLine = true;
    for (std::size_t i = 0; i < n && onOneLine; ++i) onOneLine = orientation(p[0], p[far], p[i], eps) == 0;
    if (onOneLine) return "the polygon has no area (degenerate: its points lie on one line)";
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = p[i], b = p[(i + 1) % n], c = p[(i + 2) % n];
        // Neighbouring edges may only share their common point: a spike that
        // folds back along itself overlaps.
        if (orientation(a, b, c, eps) == 0 && glm::dot(b - a, c - b) < 0.0)
            return "edges " + number(i) + " and " + number((i + 1) % n) + " fold back over each other at point " +
                   number((i + 1) % n);
    }
    // Crossing first: a bow tie has no area either, and was told only that.
    if (const auto hit = TouchingEdges(p, eps).find()) {
        const auto [i, j] = *hit;
        return "self-intersecting: edge " + number(i) + " (points " + number(i) + "-" + number((i + 1) % n) +
               ") meets edge " + number(j) + " (points " + number(j) + "-" + number((j + 1) % n) + ")";
    }
    if (std::fabs(signedArea(p)) <= extent * extent * 1e-9) return "the polygon has no area (degenerate)";
    return std::nullopt;
}

} // namespace kerf

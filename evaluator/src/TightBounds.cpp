#include "kerf/evaluator/TightBounds.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>

namespace kerf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Candidate {
    double reach; // how far the box reaches along the face's direction (s * coordinate)
    Aabb box;     // tape-relative
    Interval f;   // the field over the box
    // Farthest reach first; among equal reaches (every box touching the
    // start box's face), the one whose field goes lowest, which is likeliest
    // to hold the extreme.
    bool operator<(const Candidate& o) const { return reach < o.reach || (reach == o.reach && f.lo > o.f.lo); }
};

struct FaceResult {
    double lower = -kInf; // a solid point reaches this far (s * coordinate)
    double upper = -kInf; // nothing reaches further
};

class FaceSearch {
public:
    FaceSearch(const Tape& tape, int axis, double sign) : tape_(tape), axis_(axis), sign_(sign) {}

    FaceResult run(const Aabb& start, double tolerance, std::size_t maxBoxes)
    {
        std::priority_queue<Candidate> queue;
        FaceResult r;
        std::size_t evaluated = 1;
        consider({reach(start), start, intervals_.evaluate(tape_, start)}, queue, r);
        while (!queue.empty()) {
            const Candidate top = queue.top();
            if (top.reach <= r.lower + tolerance || evaluated >= maxBoxes) {
                r.upper = std::max(top.reach, r.lower);
                return r;
            }
            queue.pop();
            witness(top.box, r, tolerance);
            evaluated += split(top, queue, r);
        }
        // Every box was resolved: the extent is the best witness (or nothing).
        r.upper = r.lower;
        return r;
    }

private:
    double reach(const Aabb& box) const { return sign_ > 0.0 ? box.max[axis_] : -box.min[axis_]; }

    // Finds solid points in the box reaching as far as it can, to raise the
    // lower bound: the centre, and the four corners of the near face (inset
    // by an eighth of the tolerance; the
    // face opposite the far one, where a solid next to the extreme is);
    // from each solid one, a bisection along the face's axis towards the far
    // face finds where the solid ends on that line. Corners matter: a tilted
    // face or an edge reaches furthest at a corner of the box.
    void witness(const Aabb& box, FaceResult& r, double tolerance)
    {
        const double near = sign_ > 0.0 ? box.min[axis_] : box.max[axis_];
        const double far = sign_ > 0.0 ? box.max[axis_] : box.min[axis_];
        if (sign_ * far <= r.lower) return; // cannot raise it
        const int u = (axis_ + 1) % 3, v = (axis_ + 2) % 3;
        // Corners a little inside the box: an extreme often lies exactly on
        // a box face (a cap at the start box's top), where the field is 0
        // give or take rounding and may read as outside.
        const glm::dvec3 inset = glm::min(box.size() * 0.25, glm::dvec3(0.125 * tolerance));
        glm::dvec3 starts[5];
        starts[0] = box.center();
        for (int k = 0; k < 4; ++k) {
            glm::dvec3& p = starts[1 + k];
            p[axis_] = near;
            p[u] = k & 1 ? box.max[u] - inset[u] : box.min[u] + inset[u];
            p[v] = k & 2 ? box.max[v] - inset[v] : box.min[v] + inset[v];
        }
        for (glm::dvec3 p : starts) {
            if (!solid(p)) continue;
            glm::dvec3 q = p;
            q[axis_] = far;
            if (solid(q)) {
                r.lower = std::max(r.lower, sign_ * far);
                return;
            }
            // p solid, q not: bisect until the bracket is well under the tolerance.
            while (std::fabs(q[axis_] - p[axis_]) > 0.25 * tolerance) {
                glm::dvec3 m = p;
                m[axis_] = 0.5 * (p[axis_] + q[axis_]);
                (solid(m) ? p : q) = m;
            }
            r.lower = std::max(r.lower, sign_ * p[axis_]);
        }
    }

    bool solid(const glm::dvec3& p) { return points_.evaluate(tape_, p.x, p.y, p.z) <= 0.0; }

    // Drops a box that holds no solid, takes the far face of one that is all
    // solid as reached, and queues the rest.
    void consider(const Candidate& c, std::priority_queue<Candidate>& queue, FaceResult& r) const
    {
        if (c.f.lo > 0.0) return;
        if (c.f.hi <= 0.0) {
            r.lower = std::max(r.lower, c.reach);
            return;
        }
        queue.push(c);
    }

    // Halves the box across its longest side, the face's own axis counting
    // double (its extent is the one being narrowed). Returns the interval
    // evaluations made.
    std::size_t split(const Candidate& c, std::priority_queue<Candidate>& queue, FaceResult& r)
    {
        glm::dvec3 size = c.box.size();
        size[axis_] *= 2.0;
        const int along = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
        const double mid = 0.5 * (c.box.min[along] + c.box.max[along]);
        Aabb lo = c.box, hi = c.box;
        lo.max[along] = mid;
        hi.min[along] = mid;
        consider({reach(lo), lo, intervals_.evaluate(tape_, lo)}, queue, r);
        consider({reach(hi), hi, intervals_.evaluate(tape_, hi)}, queue, r);
        return 2;
    }

    const Tape& tape_;
    int axis_;
    double sign_;
    IntervalEvaluator intervals_;
    PointEvaluator<double> points_;
};

} // namespace

double TightBounds::uncertainty() const
{
    double gap = 0.0;
    for (int a = 0; a < 3; ++a) {
        gap = std::max(gap, inner.min[a] - outer.min[a]);
        gap = std::max(gap, outer.max[a] - inner.max[a]);
    }
    return gap;
}

std::optional<TightBounds> tightBounds(const Tape& tape, double tolerance, std::size_t maxBoxes)
{
    if (tape.empty() || tape.bounds().isEmpty()) return std::nullopt;
    if (!tape.bounds().isBounded()) throw std::invalid_argument("the solid is unbounded");
    if (!(tolerance > 0.0)) throw std::invalid_argument("tightBounds: the tolerance must be positive");
    const glm::dvec3 origin = tape.origin();
    const Aabb start{tape.bounds().min - origin, tape.bounds().max - origin};
    TightBounds out;
    for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {-1.0, 1.0}) {
            FaceSearch search(tape, axis, sign);
            const FaceResult r = search.run(start, tolerance, maxBoxes);
            // Every box resolved and none held solid: the solid is empty. (A
            // search cut short by maxBoxes before finding a solid point keeps
            // an infinite inner face: uncertainty() is then infinite.)
            if (r.upper == -kInf) return std::nullopt;
            if (sign > 0.0) {
                out.inner.max[axis] = origin[axis] + r.lower;
                out.outer.max[axis] = origin[axis] + r.upper;
            } else {
                out.inner.min[axis] = origin[axis] - r.lower;
                out.outer.min[axis] = origin[axis] - r.upper;
            }
        }
    }
    return out;
}

} // namespace kerf

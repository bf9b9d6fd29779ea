#include "HiddenDetail.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace kerf::mesher {

namespace {

// Sub-cells down to an edge of h / 2^kMaxDepth.
constexpr int kMaxDepth = 4;
// Detail is reported where the hidden region is thinner than this many
// cells along the gradient.
constexpr double kThinCells = 2.0;
// The chord is marched in steps of at least this fraction of the cell edge,
// the last one bisected.
constexpr double kChordStep = 1.0 / 512.0;
constexpr int kChordIterations = 256;
constexpr int kChordBisections = 10;
// The faces on either side of a wall or a slot: their normals at most about
// 35 degrees from opposite.
constexpr double kParallel = 0.82;
// The search for the thinnest place: at most this many steps, the finest a
// sixty-fourth of the cell; a chord under a thousandth of the cell there is
// faces meeting.
constexpr int kDescentSteps = 32;
constexpr double kDescentFinest = 1.0 / 64.0;
constexpr double kContact = 1e-3;

// Distance from p along `direction` to where the field (times `side`) is back
// above zeroBand; beyond `limit`, `limit`. Steps by the field's value (the
// field is 1-Lipschitz: no crossing is passed), at least `minStep`.
double exitDistance(const Tape& full, const glm::dvec3& p, const glm::dvec3& direction, double side, double zeroBand,
                    double minStep, double limit, PointEvaluator<double>& points)
{
    const auto g = [&](double t) {
        const glm::dvec3 q = p + t * direction - full.origin();
        return side * points.evaluate(full, q.x, q.y, q.z);
    };
    double t = 0.0, inside = 0.0; // inside: the last t still on the other side
    for (int i = 0; i < kChordIterations && t < limit; ++i) {
        const double v = g(t);
        if (!std::isfinite(v)) return limit;
        if (v > zeroBand) {
            // Crossed within the last step: bisect it.
            for (int k = 0; k < kChordBisections; ++k) {
                const double mid = 0.5 * (inside + t);
                (g(mid) > zeroBand ? t : inside) = mid;
            }
            return t;
        }
        inside = t;
        t += std::max(-v, minStep);
    }
    return limit;
}

// The field's unit gradient at a world point; 0 where it has none.
glm::dvec3 unitGradient(const Tape& full, const glm::dvec3& world, GradientEvaluator<double>& gradients)
{
    const glm::dvec3 p = world - full.origin();
    const Dual<double> d = gradients.evaluate(full, p.x, p.y, p.z);
    const glm::dvec3 g(d.d[0], d.d[1], d.d[2]);
    const double length = glm::length(g);
    return length > 0.0 && std::isfinite(length) ? g / length : glm::dvec3(0.0);
}

// The chord across the other side's region through p (where g = side * f
// < 0) along the gradient: its length, its midpoint, and whether the faces
// at its ends are nearly opposite. Nothing when the region reaches `limit`
// either way (something thick) or the field has no gradient at p.
struct Chord {
    double length;
    glm::dvec3 mid;
    glm::dvec3 normal; // the way g grows at p
    bool parallelFaces;
};

std::optional<Chord> chordThrough(const Tape& full, const glm::dvec3& p, double side, double h, double zeroBand,
                                  HiddenDetailScratch& s)
{
    const glm::dvec3 n = side * unitGradient(full, p, s.gradients);
    if (n == glm::dvec3(0.0)) return std::nullopt;
    const double limit = kThinCells * h;
    const double minStep = kChordStep * h;
    const double up = exitDistance(full, p, n, side, zeroBand, minStep, limit, s.points);
    if (up >= limit) return std::nullopt;
    const double down = exitDistance(full, p, -n, side, zeroBand, minStep, limit, s.points);
    if (up + down >= limit) return std::nullopt;
    const glm::dvec3 a = unitGradient(full, p + up * n, s.gradients);
    const glm::dvec3 b = unitGradient(full, p - down * n, s.gradients);
    return Chord{up + down, p + 0.5 * (up - down) * n, n, glm::dot(a, b) < -kParallel};
}

// From a witness p, the thinnest place of its region nearby: steps across
// the region's midsurface while the chord shrinks. A wall or a slot keeps a
// thickness, which is reported. Where the faces meet instead (the crevice
// beside two bodies touching, a cylinder lying on a board, the tip of a
// sharp wedge) the chord shrinks towards nothing: that is thin at every cell
// size, not detail a finer cell resolves, and is not reported; nor is a
// region whose faces meet at a wide angle (where two rounded edges cross).
std::optional<HiddenDetailFound> thinnestAround(const Tape& full, const glm::dvec3& p, double side, double h,
                                                double zeroBand, HiddenDetailScratch& s)
{
    std::optional<Chord> best = chordThrough(full, p, side, h, zeroBand, s);
    if (!best) return std::nullopt;
    double step = 0.25 * h;
    for (int i = 0; i < kDescentSteps && step >= kDescentFinest * h; ++i) {
        if (best->length < kContact * h) return std::nullopt;
        // Two directions across the midsurface.
        const glm::dvec3 n = best->normal;
        const glm::dvec3 helper = std::abs(n.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 t1 = glm::normalize(glm::cross(n, helper));
        const glm::dvec3 t2 = glm::cross(n, t1);
        bool moved = false;
        for (const glm::dvec3& t : {t1, -t1, t2, -t2}) {
            const glm::dvec3 q = best->mid + step * t;
            const glm::dvec3 r = q - full.origin();
            if (!(side * s.points.evaluate(full, r.x, r.y, r.z) < -zeroBand)) continue; // beyond its edge
            const std::optional<Chord> c = chordThrough(full, q, side, h, zeroBand, s);
            if (c && c->length < best->length) {
                best = c;
                moved = true;
                break;
            }
        }
        if (!moved) step *= 0.5;
    }
    if (best->length < kContact * h || !best->parallelFaces) return std::nullopt;
    return HiddenDetailFound{best->mid, best->length, side > 0.0};
}

} // namespace

std::optional<HiddenDetailFound> findHiddenDetail(const Tape& local, const Tape& full, const Aabb& cell,
                                                  bool cornersInside, double zeroBand, HiddenDetailScratch& s)
{
    // g = side * f is at least 0 at the corners; the search is for g < 0.
    const double side = cornersInside ? -1.0 : 1.0;
    const double h = cell.max.x - cell.min.x;
    const glm::dvec3 origin = local.origin();

    // Level by level, the live sub-cells' lower corners (tape-relative), all
    // centres of a level evaluated in one batched call.
    std::vector<glm::dvec3>& live = s.live;
    std::vector<glm::dvec3>& next = s.next;
    std::vector<double>&x = s.x, &y = s.y, &z = s.z, &f = s.f;
    live.assign(1, cell.min - origin);
    for (int depth = 0; depth <= kMaxDepth && !live.empty(); ++depth) {
        const double size = h / double(1 << depth);
        const double halfDiagonal = 0.5 * std::sqrt(3.0) * size;
        x.resize(live.size());
        y.resize(live.size());
        z.resize(live.size());
        f.resize(live.size());
        for (std::size_t i = 0; i < live.size(); ++i) {
            x[i] = live[i].x + 0.5 * size;
            y[i] = live[i].y + 0.5 * size;
            z[i] = live[i].z + 0.5 * size;
        }
        s.points.evaluate(local, x.data(), y.data(), z.data(), live.size(), f.data());
        next.clear();
        for (std::size_t i = 0; i < live.size(); ++i) {
            const double g = side * f[i];
            if (!std::isfinite(g)) continue;
            if (g < -zeroBand) {
                const glm::dvec3 p = glm::dvec3(x[i], y[i], z[i]) + origin;
                if (const std::optional<HiddenDetailFound> found = thinnestAround(full, p, side, h, zeroBand, s))
                    return found;
                continue;
            }
            if (g >= halfDiagonal || depth == kMaxDepth) continue; // Lipschitz: no other side in it
            const Aabb box{live[i], live[i] + glm::dvec3(size)};
            const Interval range = s.intervals.evaluate(local, box);
            if (cornersInside ? !(range.hi > zeroBand) : !(range.lo < -zeroBand)) continue;
            const double half = 0.5 * size;
            for (int q = 0; q < 8; ++q)
                next.push_back(live[i] + half * glm::dvec3(q & 1, (q >> 1) & 1, q >> 2));
        }
        live.swap(next);
    }
    return std::nullopt;
}

} // namespace kerf::mesher

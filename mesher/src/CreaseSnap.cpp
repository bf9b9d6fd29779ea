#include "CreaseSnap.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace kerf::mesher {

namespace {

// Whether the field changes sign across p along n: a zero of the field with
// solid on both sides (two bodies touching face to face inside the part) or
// on neither (a difference's tool face on the body's face) is no surface,
// and a vertex put there digs a pit into the part along the contact, round
// after round of the refinement (a drawer's front against its side, where
// both meet the bottom face). 10 times `settled` off p is past what is left
// of the field there and far inside any feature the export resolves; a side
// where the field is 0 (p on a concave or convex crease, the step along the
// face of the other sheet) counts as crossing.
bool crossesHere(const Tape& tape, GradientEvaluator<double>& gradients, const glm::dvec3& p, const glm::dvec3& n,
                 double settled)
{
    const double h = 10.0 * settled;
    const glm::dvec3 q = p - tape.origin();
    const glm::dvec3 out = q + h * n, in = q - h * n;
    const double fOut = gradients.evaluate(tape, out.x, out.y, out.z).v;
    const double fIn = gradients.evaluate(tape, in.x, in.y, in.z).v;
    const bool buried = fOut < -0.5 * h && fIn < -0.5 * h;
    const bool film = fOut > 0.5 * h && fIn > 0.5 * h;
    return !buried && !film;
}

} // namespace

std::optional<SurfacePoint> projectOntoSurface(const Tape& tape, GradientEvaluator<double>& gradients, glm::dvec3 p,
                                               double reach, double settled, const glm::dvec3& expected)
{
    // The normal is the gradient of the step before the last: at the
    // surface itself the gradient can be rounding noise, or 0 where the
    // field is exactly 0 (see TileMesher::solveRoots).
    const glm::dvec3 start = p;
    glm::dvec3 normal(0.0);
    for (int i = 0; i < 16; ++i) {
        const glm::dvec3 q = p - tape.origin();
        const Dual<double> d = gradients.evaluate(tape, q.x, q.y, q.z);
        const glm::dvec3 g(d.d[0], d.d[1], d.d[2]);
        const double g2 = glm::dot(g, g);
        if (!std::isfinite(d.v)) return std::nullopt;
        if (std::abs(d.v) <= settled) {
            if (normal == glm::dvec3(0.0)) {
                // Started on the surface: the gradient a hair off it, on the
                // side the sheet's normal says.
                const glm::dvec3 off = q + settled * expected;
                const Dual<double> e = gradients.evaluate(tape, off.x, off.y, off.z);
                const glm::dvec3 ge(e.d[0], e.d[1], e.d[2]);
                if (!(glm::dot(ge, ge) > 1e-12)) return std::nullopt;
                normal = glm::normalize(ge);
            }
            if (!crossesHere(tape, gradients, p, normal, settled)) return std::nullopt;
            return SurfacePoint{p, normal};
        }
        if (!(g2 > 1e-12)) return std::nullopt;
        normal = g / std::sqrt(g2);
        p -= g * (d.v / g2);
        if (glm::length(p - start) > reach) return std::nullopt;
    }
    return std::nullopt;
}

namespace {

using SheetPoint = SurfacePoint;

// A point of the sheet with normal about `own`, `delta` away from x on the
// sheet's side of the edge (the side away from the other sheet, tried
// both ways: a convex edge and a concave one lie opposite).
std::optional<SheetPoint> sample(const Tape& tape, GradientEvaluator<double>& gradients, const glm::dvec3& x,
                                 const glm::dvec3& own, const glm::dvec3& other, double delta, double tolerance)
{
    glm::dvec3 t = other - glm::dot(other, own) * own; // in the sheet's plane, across the edge
    const double length = glm::length(t);
    if (!(length > 1e-9)) return std::nullopt;
    t /= length;
    for (const double sign : {-1.0, 1.0}) {
        const auto s = projectOntoSurface(tape, gradients, x + sign * delta * t, 4.0 * delta, 1e-3 * tolerance, own);
        if (s && glm::dot(s->n, own) > 0.9) return s;
    }
    return std::nullopt;
}

} // namespace

std::optional<glm::dvec3> snapToCrease(const Tape& tape, GradientEvaluator<double>& gradients, const glm::dvec3& x0,
                                       glm::dvec3 nA, glm::dvec3 nB, double scale, double tolerance,
                                       const std::optional<std::pair<SurfacePoint, SurfacePoint>>& onSheets)
{
    glm::dvec3 e = glm::cross(nA, nB);
    if (!(glm::length(e) > 0.42)) return std::nullopt; // sheets less than 25 degrees apart
    e = glm::normalize(e);
    glm::dvec3 x = x0;
    double delta = 0.25 * scale;
    bool converged = false;
    for (int step = 0; step < 12 && !converged; ++step) {
        // The first step from the sheets' own points where the caller has them.
        const bool given = step == 0 && onSheets;
        const auto a = given ? std::optional(onSheets->first) : sample(tape, gradients, x, nA, nB, delta, tolerance);
        const auto b = given ? std::optional(onSheets->second) : sample(tape, gradients, x, nB, nA, delta, tolerance);
        if (!a || !b) return std::nullopt;
        const glm::dmat3 rows = glm::transpose(glm::dmat3(a->n, b->n, e));
        if (!(std::abs(glm::determinant(rows)) > 1e-6)) return std::nullopt;
        const glm::dvec3 next =
            glm::inverse(rows) * glm::dvec3(glm::dot(a->n, a->p), glm::dot(b->n, b->p), glm::dot(e, x0));
        const double moved = glm::length(next - x);
        x = next;
        if (glm::length(x - x0) > 2.0 * scale) return std::nullopt;
        nA = a->n;
        nB = b->n;
        converged = moved <= 1e-4 * tolerance;
        delta = std::clamp(2.0 * moved, 1e-4 * scale, 0.25 * scale);
    }
    // Not settled: no edge here (the sheets do not meet, or only far off).
    if (!converged) return std::nullopt;
    // Settled where the sheets sampled beside it no longer differ by 25
    // degrees: a rounded edge, whose tangent planes meet on it as the samples
    // close in, not a sharp one (taken for one, its vertex stood off the
    // round and left triangles over 0.01 mm on the bookshelf side's rounds).
    if (!(glm::length(glm::cross(nA, nB)) > 0.42)) return std::nullopt;
    const glm::dvec3 q = x - tape.origin();
    const Dual<double> d = gradients.evaluate(tape, q.x, q.y, q.z);
    if (!(std::abs(d.v) <= tolerance)) return std::nullopt;
    return x;
}

} // namespace kerf::mesher

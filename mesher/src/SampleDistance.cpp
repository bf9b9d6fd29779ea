#include "SampleDistance.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>

namespace kerf::mesher {

namespace {

constexpr double kGradientFloor = 0.1;
constexpr double kStepGradientFloor = 0.5;
constexpr int kWalkSteps = 64; // as the accuracy library walks; most settle in a few
constexpr double kWalkFrom = 0.5;      // of the tolerance: nearer samples do not walk
constexpr double kSettled = 1e-3;      // of the tolerance: |f| this small ends a walk
constexpr double kFar = 1e300;         // no surface: as far as can be

double gradientLength(const Dual<double>& v)
{
    return std::sqrt(v.d[0] * v.d[0] + v.d[1] * v.d[1] + v.d[2] * v.d[2]);
}

} // namespace

double firstOrderDistance(const Dual<double>& field)
{
    const double f = std::abs(field.v);
    if (!std::isfinite(f)) return kFar;
    const double g = gradientLength(field);
    if (!(g < 1.0)) return f; // (also a gradient that is not a number: the field alone)
    return f / std::max(g, kGradientFloor);
}

void SampleDistance::measure(const Tape& tape, const double* x, const double* y, const double* z, std::size_t n,
                             double tolerance, double* out, const glm::dvec3* normals)
{
    if (n == 0) return;
    // |f| first, with the plain evaluator (a fraction of the dual numbers'
    // cost): within half the tolerance a sample is within it (unless the
    // gradient there is shorter than a half); beyond the tolerance it is
    // beyond it whatever a walk finds (|f| is a lower bound of the
    // distance), and |f| is its figure. Only the samples between walk.
    fields_.resize(n);
    plain_.evaluate(tape, x, y, z, n, fields_.data());
    walking_.clear();
    settled_.clear();
    trusted_.clear();
    side_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const double f = std::abs(fields_[i]);
        out[i] = std::isfinite(f) ? f : kFar;
        if (f > kWalkFrom * tolerance && !(f > tolerance)) walking_.push_back(i);
        else if (!(f > kWalkFrom * tolerance)) trusted_.push_back(i);
    }
    if (normals && tolerance > 0.0) walkWhereNoCrossing(tape, x, y, z, normals, tolerance);
    if (walking_.empty() || !(tolerance > 0.0)) return;
    const double reach = this->reach(tolerance), settled = kSettled * tolerance;
    at_.resize(n);
    samples_.resize(n);
    first_.resize(n);
    values_.resize(n);
    wx_.resize(walking_.size());
    wy_.resize(walking_.size());
    wz_.resize(walking_.size());
    for (std::size_t k = 0; k < walking_.size(); ++k) {
        const std::size_t i = walking_[k];
        at_[i] = samples_[i] = glm::dvec3(x[i], y[i], z[i]);
        first_[i] = out[i];
        wx_[k] = x[i];
        wy_[k] = y[i];
        wz_[k] = z[i];
    }
    stepped_.resize(walking_.size());
    evaluator_.evaluate(tape, wx_.data(), wy_.data(), wz_.data(), walking_.size(), stepped_.data());
    for (std::size_t k = 0; k < walking_.size(); ++k) {
        values_[walking_[k]] = stepped_[k];
        out[walking_[k]] = firstOrderDistance(stepped_[k]);
    }
    // The walks step together: each round evaluates the points still going.
    std::vector<Dual<double>>& here = values_; // values_[i] is the field at at_[i] for walking i
    for (int step = 0; step < kWalkSteps && !walking_.empty(); ++step) {
        std::size_t kept = 0;
        for (const std::size_t i : walking_) {
            const Dual<double>& v = here[i];
            const double g = gradientLength(v);
            if (!(g > 0.0) || !std::isfinite(g) || !std::isfinite(v.v)) continue; // no way to go: as judged
            // Newton's step |f| / |g| along the gradient where the gradient
            // is at least a half (a blend's: two or three steps), at most
            // 2 |f| where it is shorter. The ball of radius |f| holds no
            // surface (the field is 1-Lipschitz), so a step overshoots by
            // at most |f| and the next comes back; a plain Newton step
            // overshot by millimetres where the gradient is 0.15 (the
            // middle of the stool's seat, where its blends meet) and the
            // walk came back from far, a figure three times the distance.
            const glm::dvec3 direction(v.d[0] / g, v.d[1] / g, v.d[2] / g);
            at_[i] -= (v.v / std::max(g, kStepGradientFloor)) * direction;
            walking_[kept++] = i;
        }
        walking_.resize(kept);
        wx_.resize(kept);
        wy_.resize(kept);
        wz_.resize(kept);
        for (std::size_t k = 0; k < kept; ++k) {
            wx_[k] = at_[walking_[k]].x;
            wy_[k] = at_[walking_[k]].y;
            wz_[k] = at_[walking_[k]].z;
        }
        stepped_.resize(kept);
        evaluator_.evaluate(tape, wx_.data(), wy_.data(), wz_.data(), kept, stepped_.data());
        kept = 0;
        for (std::size_t k = 0; k < walking_.size(); ++k) {
            const std::size_t i = walking_[k];
            here[i] = stepped_[k];
            const double travelled = glm::length(at_[i] - glm::dvec3(x[i], y[i], z[i]));
            // What is left: |f| here, not the first-order figure, which a
            // short gradient makes up to ten times |f| (a walk that left its
            // reach in the middle of the stool's seat, gradient 0.15, was
            // reported 4.1 mm from the surface where the file is 1.6 mm
            // off). The walk's figure replaces the first-order one; never
            // below |f| at the sample, a lower bound of the distance.
            const double left = std::abs(stepped_[k].v);
            out[i] = std::max(first_[i], std::min(travelled + left, kFar));
            if (travelled > reach) continue; // beyond the tolerance, and the tape's box
            if (std::abs(stepped_[k].v) > settled)
                walking_[kept++] = walking_[k];
            else
                settled_.push_back(i);
        }
        walking_.resize(kept);
    }
    checkCrossings(tape, reach, 2.0 * settled, out);
}

void SampleDistance::fieldEitherSide(const Tape& tape, std::size_t count,
                                     const std::function<std::pair<glm::dvec3, glm::dvec3>(std::size_t)>& pointAndStep)
{
    wx_.resize(2 * count);
    wy_.resize(2 * count);
    wz_.resize(2 * count);
    for (std::size_t k = 0; k < count; ++k) {
        const auto [p, step] = pointAndStep(k);
        for (int side = 0; side < 2; ++side) {
            const glm::dvec3 q = side == 0 ? p - step : p + step;
            wx_[2 * k + std::size_t(side)] = q.x;
            wy_[2 * k + std::size_t(side)] = q.y;
            wz_[2 * k + std::size_t(side)] = q.z;
        }
    }
    crossings_.resize(wx_.size());
    plain_.evaluate(tape, wx_.data(), wy_.data(), wz_.data(), wx_.size(), crossings_.data());
}

void SampleDistance::walkWhereNoCrossing(const Tape& tape, const double* x, const double* y, const double* z,
                                         const glm::dvec3* normals, double tolerance)
{
    // Along the normal of the sample's triangle, a tolerance either way: the
    // part's surface within half a tolerance puts the field above +h/4 on
    // one side and below -h/4 on the other for any triangle within 60
    // degrees of it; 0 on a side (a sharp edge's other face) counts as a
    // crossing. Solid on both sides (a glue line) or on neither (a film)
    // does not. A thin wall or a triangle leaning across an edge may fail
    // too: it walks, which costs time and finds its distance all the same.
    if (trusted_.empty()) return;
    const double h = tolerance;
    fieldEitherSide(tape, trusted_.size(), [&](std::size_t k) {
        const std::size_t i = trusted_[k];
        return std::pair(glm::dvec3(x[i], y[i], z[i]), h * normals[i]);
    });
    for (std::size_t k = 0; k < trusted_.size(); ++k) {
        const double in = crossings_[2 * k], out = crossings_[2 * k + 1];
        const bool buried = out < -0.25 * h && in < -0.25 * h;
        const bool film = out > 0.25 * h && in > 0.25 * h;
        if (!buried && !film) continue;
        walking_.push_back(trusted_[k]);
        side_[trusted_[k]] = film ? 1 : -1;
    }
    std::sort(walking_.begin(), walking_.end());
}

void SampleDistance::checkCrossings(const Tape& tape, double reach, double bracket, double* out)
{
    // A walk can also settle where f comes to 0 without changing sign: the
    // seam where two bodies touch inside the part (a rail's end against a
    // leg), which no reader sees as surface. The part's surface is where the
    // field changes sign: the points either side of the end, along the
    // gradient, show whether it does.
    if (settled_.empty()) return;
    fieldEitherSide(tape, settled_.size(), [&](std::size_t k) {
        const Dual<double>& v = values_[settled_[k]];
        const double g = gradientLength(v);
        const glm::dvec3 along = g > 0.0 && std::isfinite(g) ? glm::dvec3(v.d[0], v.d[1], v.d[2]) / g : glm::dvec3(0.0);
        return std::pair(at_[settled_[k]], bracket * along);
    });
    for (std::size_t k = 0; k < settled_.size(); ++k) {
        const double a = crossings_[2 * k], b = crossings_[2 * k + 1];
        const bool changesSign = (a <= 0.0 && b >= 0.0) || (a >= 0.0 && b <= 0.0);
        if (changesSign) continue;
        const std::size_t i = settled_[k];
        // Not the surface: as if beyond the tolerance, or, when asked,
        // where straight marches from the sample first cross it.
        // On a film or a glue line f is about 0, on either side by rounding:
        // the march leaves the side the probes found.
        const double f0 = side_[i] != 0 ? side_[i] * std::max(std::abs(fields_[i]), 1e-300) : fields_[i];
        out[i] = std::max(first_[i], final_ ? march(tape, samples_[i], f0, reach, reach / 64.0) : reach);
    }
    settled_.clear();
}

double SampleDistance::march(const Tape& tape, const glm::dvec3& p, double f0, double reach, double minStep)
{
    // Sphere-tracing marches along the 26 directions of a cube cell's
    // neighbours, all stepping together, each by max(|f|, minStep) until f
    // changes sign (strictly: the seam itself is 0): the nearest crossing,
    // a point of the surface, bounds the distance. None within `reach`:
    // `reach`.
    constexpr int kDirections = 26;
    glm::dvec3 u[kDirections];
    double t[kDirections], f[kDirections];
    int active = 0;
    for (int k = 0; k < 27; ++k) {
        const glm::dvec3 d(k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1);
        if (d == glm::dvec3(0.0)) continue;
        u[active] = glm::normalize(d);
        t[active] = 0.0;
        f[active] = f0;
        ++active;
    }
    double best = reach;
    double x[kDirections], y[kDirections], z[kDirections], value[kDirections];
    while (active > 0) {
        int kept = 0;
        for (int k = 0; k < active; ++k) {
            const double next = t[k] + std::max(std::abs(f[k]), minStep);
            if (!(next < best) || !std::isfinite(next)) continue;
            u[kept] = u[k];
            t[kept] = next;
            const glm::dvec3 q = p + next * u[k];
            x[kept] = q.x;
            y[kept] = q.y;
            z[kept] = q.z;
            ++kept;
        }
        active = kept;
        if (active == 0) break;
        plain_.evaluate(tape, x, y, z, std::size_t(active), value);
        kept = 0;
        for (int k = 0; k < active; ++k) {
            if (f0 > 0.0 ? value[k] < 0.0 : value[k] > 0.0) {
                best = std::min(best, t[k]);
                continue;
            }
            u[kept] = u[k];
            t[kept] = t[k];
            f[kept] = value[k];
            ++kept;
        }
        active = kept;
    }
    return best;
}

} // namespace kerf::mesher

#include "SurfaceQueries.hpp"

#include "CreaseSnap.hpp"
#include "SampleDistance.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"

namespace kerf::mesher {

SurfaceQueries::SurfaceQueries(const Tape& tape, const glm::dvec3& offset, double creaseTolerance, double regionSize)
    : tape_(&tape), regionSize_(regionSize), regions_(std::make_unique<RegionTapes>(tape, regionSize)), offset_(offset),
      creaseTolerance_(creaseTolerance)
{
}

SurfaceQueries::SurfaceQueries(std::shared_ptr<const Tape> owned, const glm::dvec3& offset, double creaseTolerance,
                               double regionSize)
    : owned_(std::move(owned)), tape_(owned_.get()), regionSize_(regionSize),
      regions_(std::make_unique<RegionTapes>(*tape_, regionSize)), offset_(offset), creaseTolerance_(creaseTolerance)
{
}

SurfaceQueries SurfaceQueries::region(const glm::dvec3& lo, const glm::dvec3& hi) const
{
    auto simplified = std::make_shared<Tape>();
    IntervalEvaluator intervals;
    const glm::dvec3 shift = offset_ - tape_->origin();
    intervals.simplify(*tape_, Aabb{lo + shift, hi + shift}, *simplified);
    return SurfaceQueries(std::move(simplified), offset_, creaseTolerance_, regionSize_);
}

// The tape near the points' box, and the points in its frame in x_, y_, z_.
const Tape& SurfaceQueries::prepare(const glm::dvec3* p, std::size_t n, double reach)
{
    glm::dvec3 lo(p[0]), hi(p[0]);
    for (std::size_t i = 1; i < n; ++i) {
        lo = glm::min(lo, p[i]);
        hi = glm::max(hi, p[i]);
    }
    const Tape& tape = regions_->near(0.5 * (lo + hi) + offset_, 0.5 * glm::length(hi - lo) + reach);
    x_.resize(n);
    y_.resize(n);
    z_.resize(n);
    const glm::dvec3 shift = offset_ - tape.origin();
    for (std::size_t i = 0; i < n; ++i) {
        x_[i] = p[i].x + shift.x;
        y_[i] = p[i].y + shift.y;
        z_[i] = p[i].z + shift.z;
    }
    return tape;
}

void SurfaceQueries::field(const glm::dvec3* p, std::size_t n, double* out)
{
    if (n == 0) return;
    const Tape& tape = prepare(p, n, 0.0);
    points_.evaluate(tape, x_.data(), y_.data(), z_.data(), n, out);
}

void SurfaceQueries::distances(const glm::dvec3* p, std::size_t n, double tolerance, double* out)
{
    if (n == 0) return;
    const Tape& tape = prepare(p, n, distances_.reach(tolerance));
    distances_.measure(tape, x_.data(), y_.data(), z_.data(), n, tolerance, out);
}

glm::dvec3 SurfaceQueries::unitNormal(const glm::dvec3& p)
{
    const Tape& tape = regions_->near(p + offset_, 0.0);
    const glm::dvec3 q = p + offset_ - tape.origin();
    const auto d = gradients_.evaluate(tape, q.x, q.y, q.z);
    const glm::dvec3 g(d.d[0], d.d[1], d.d[2]);
    const double length = glm::length(g);
    return length > 0.0 && std::isfinite(length) ? g / length : glm::dvec3(0.0);
}

std::optional<glm::dvec3> SurfaceQueries::snapToCrease(const glm::dvec3& x, const glm::dvec3& nA, const glm::dvec3& nB,
                                                       double scale)
{
    // The crease search stays within a few `scale` of x.
    const Tape& tape = regions_->near(x + offset_, 4.0 * scale);
    const auto p = mesher::snapToCrease(tape, gradients_, x + offset_, nA, nB, scale, creaseTolerance_);
    if (!p) return std::nullopt;
    return *p - offset_;
}

} // namespace kerf::mesher

#include "SurfaceQueries.hpp"

#include "CreaseSnap.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"

namespace kerf::mesher {

SurfaceQueries::SurfaceQueries(const Tape& tape, const glm::dvec3& offset, double creaseTolerance)
    : tape_(&tape), offset_(offset), creaseTolerance_(creaseTolerance)
{
}

SurfaceQueries::SurfaceQueries(std::shared_ptr<const Tape> owned, const glm::dvec3& offset, double creaseTolerance)
    : owned_(std::move(owned)), tape_(owned_.get()), offset_(offset), creaseTolerance_(creaseTolerance)
{
}

SurfaceQueries SurfaceQueries::region(const glm::dvec3& lo, const glm::dvec3& hi) const
{
    auto simplified = std::make_shared<Tape>();
    IntervalEvaluator intervals;
    const glm::dvec3 shift = offset_ - tape_->origin();
    intervals.simplify(*tape_, Aabb{lo + shift, hi + shift}, *simplified);
    return SurfaceQueries(std::move(simplified), offset_, creaseTolerance_);
}

void SurfaceQueries::field(const glm::dvec3* p, std::size_t n, double* out)
{
    x_.resize(n);
    y_.resize(n);
    z_.resize(n);
    const glm::dvec3 shift = offset_ - tape_->origin();
    for (std::size_t i = 0; i < n; ++i) {
        x_[i] = p[i].x + shift.x;
        y_[i] = p[i].y + shift.y;
        z_[i] = p[i].z + shift.z;
    }
    points_.evaluate(*tape_, x_.data(), y_.data(), z_.data(), n, out);
}

std::optional<glm::dvec3> SurfaceQueries::snapToCrease(const glm::dvec3& x, const glm::dvec3& nA, const glm::dvec3& nB,
                                                       double scale)
{
    const auto p = mesher::snapToCrease(*tape_, gradients_, x + offset_, nA, nB, scale, creaseTolerance_);
    if (!p) return std::nullopt;
    return *p - offset_;
}

} // namespace kerf::mesher

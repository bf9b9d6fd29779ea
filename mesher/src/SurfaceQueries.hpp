#pragma once
// What the simplification asks of the exact surface, in the coordinates of
// the mesh being simplified (world minus an offset): the field at points,
// and points on sharp edges (CreaseSnap.hpp).
//
// Speed: a tape simplified for a region is far shorter than the part's (a
// chair's 42 instructions become one or two near most of its surface), and
// equal to it inside the region. region() makes one for a box, for the work
// done inside it (a cube of the partitioned simplification); within that,
// each query evaluates a tape simplified for a small cube around its
// points (RegionTapes.hpp), when `regionSize` is given.
//
// Not thread-safe: one per thread (each holds its evaluators).

#include "RegionTapes.hpp"
#include "SampleDistance.hpp"

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace kerf::mesher {

class SurfaceQueries {
public:
    /// `tape` must outlive this; `offset` is added to a point to make it a
    /// world point.
    SurfaceQueries(const Tape& tape, const glm::dvec3& offset, double creaseTolerance, double regionSize = 0.0);

    /// The same queries with the tape simplified for the box [lo, hi] (mesh
    /// coordinates): valid for points inside it.
    SurfaceQueries region(const glm::dvec3& lo, const glm::dvec3& hi) const;

    /// out[i] = f(p[i]).
    void field(const glm::dvec3* p, std::size_t n, double* out);
    double field(const glm::dvec3& p)
    {
        double f = 0.0;
        field(&p, 1, &f);
        return f;
    }
    /// out[i] = how far p[i] is from the surface, as a triangle's sample is
    /// judged against `tolerance` (SampleDistance.hpp).
    void distances(const glm::dvec3* p, std::size_t n, double tolerance, double* out);
    /// The unit normal of the surface's sheet at p (the field's gradient),
    /// or 0 where it has none.
    glm::dvec3 unitNormal(const glm::dvec3& p);
    /// The point of the sharp edge between the sheets with normals nA and nB
    /// near x, within `scale` mm; nothing if none (CreaseSnap.hpp).
    std::optional<glm::dvec3> snapToCrease(const glm::dvec3& x, const glm::dvec3& nA, const glm::dvec3& nB,
                                           double scale);

private:
    const Tape& prepare(const glm::dvec3* p, std::size_t n, double reach);

    SurfaceQueries(std::shared_ptr<const Tape> owned, const glm::dvec3& offset, double creaseTolerance,
                   double regionSize);

    std::shared_ptr<const Tape> owned_; // a region's tape
    const Tape* tape_;
    double regionSize_;
    std::unique_ptr<RegionTapes> regions_; // (a pointer: SurfaceQueries moves)
    glm::dvec3 offset_;
    double creaseTolerance_;
    PointEvaluator<double> points_;
    GradientEvaluator<double> gradients_;
    SampleDistance distances_;
    std::vector<double> x_, y_, z_;
};

} // namespace kerf::mesher

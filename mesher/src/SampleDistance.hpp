#pragma once
// How far from the exact surface the exporter judges a sample point of a
// triangle to be. The tolerance of an export is held to this figure, in the
// simplification and in the refinement.
//
// Kerf's fields are the exact distance away from blends and creases and a
// bound of it elsewhere: |f| is never more than the distance, and can be
// much less.
//  - Where a smooth blend joins two faces the gradient is shorter than 1
//    (two boards at a right angle: 0.71 in the middle of the blend), so |f|
//    said 0.1 mm where the surface was 0.14 mm away. |f| / |grad f| is the
//    distance to first order: exact for a field that changes linearly
//    towards a flat face, whatever its slope, and off by the square of the
//    distance over the surface's radius elsewhere.
//  - Inside a union near where two bodies meet (a rail's end buried in a
//    leg), |f| is the distance to a face of one body that lies inside the
//    other, not to the part's surface: the chair at 0.1 mm, judged by
//    |f| / |grad f|, had samples 0.096 mm by the field and 0.13 mm from the
//    surface.
// So a sample whose |f| lies between half the tolerance and the tolerance
// walks to the surface, as the accuracy library measures an export
// (SurfaceDistance.hpp): steps along the gradient (Newton's, at most
// 2 |f|), re-aimed at every step, until |f| is a thousandth of the
// tolerance; its distance is then how far it ended from where it started,
// plus what is left. That turns the corner where one body's face goes into
// the other, and lands on the part's surface; where it lands on a zero of
// the field that is no surface (the field does not change sign there: two
// bodies touching inside the part), the sample counts as beyond the
// tolerance. A sample within half the tolerance by |f| is within it unless
// the field's gradient there is shorter than a half, which only a blend
// between faces turned more than 120 degrees apart has; one beyond the
// tolerance by |f| is beyond it (|f| is its figure, a lower bound). Only
// the walks need the gradient (dual numbers, several times the cost of |f|).
//
// The figure is never less than |f| (where the gradient is longer than 1,
// from rounding, the tolerance stays what |f| says), and the gradient is
// taken as at least 0.1: a field whose gradient vanishes at the surface
// (the saddle of a blend between faces turned towards each other) would
// otherwise make every sample near that point look infinitely far.

#include "kerf/evaluator/Dual.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace kerf::mesher {

/// The distance to first order, |f| / |grad f|, from the field's value and
/// gradient at a point.
double firstOrderDistance(const Dual<double>& field);

/// Judges samples. Scratch memory only: one per thread.
class SampleDistance {
public:
    /// `finalJudgement`: the judgement whose figures are reported and whose
    /// triangles over the tolerance are split (the refinement's), not the
    /// simplification's, which judges far more samples. There a walk may go
    /// 4 tolerances from its sample instead of 1.5 (where the stool's
    /// blends meet, with a gradient of 0.15, the file is 1.3 mm from the
    /// surface at 0.5 mm: a walk cut off at 0.75 mm said 1.1), and a sample
    /// whose walk settles on a seam gets the distance of the nearest
    /// crossing of straight marches from it (26 directions, up to the
    /// reach) instead of counting as beyond the tolerance.
    explicit SampleDistance(bool finalJudgement = false) : final_(finalJudgement) {}

    /// How far the walks may go from their samples: the box a tape given to
    /// measure() must be valid in, grown on every side.
    double reach(double tolerance) const { return (final_ ? 4.0 : 1.5) * tolerance; }

    /// How far each of the points (x, y, z: the tape's frame) lies from the
    /// surface, as the tolerance `tolerance` is judged. The walks stay within
    /// reach(tolerance) of their points: `tape` must be valid that far.
    ///
    /// `normals` (unit, one per point: the normal of the triangle it lies
    /// on), for the final judgement: a point that |f| puts within half the
    /// tolerance is trusted only where the field changes sign across it,
    /// a tolerance along the normal either way; else it walks. |f| is 0 on
    /// a film (a hole's end flush with the board's face: 0 across the mouth)
    /// and on a glue line inside the part, and a triangle cutting the rim of
    /// such a hole by 0.08 mm was judged 0.049 mm off (random joinery,
    /// ExportedJoinery).
    void measure(const Tape& tape, const double* x, const double* y, const double* z, std::size_t n,
                 double tolerance, double* out, const glm::dvec3* normals = nullptr);

private:
    void checkCrossings(const Tape& tape, double reach, double bracket, double* out);
    // The field at p - step and p + step for `count` points (p, step):
    // crossings_[2k] and crossings_[2k + 1].
    void fieldEitherSide(const Tape& tape, std::size_t count,
                         const std::function<std::pair<glm::dvec3, glm::dvec3>(std::size_t)>& pointAndStep);
    // The samples of `trusted` (indices) whose field does not change sign
    // across them along their normals: appended to walking_.
    void walkWhereNoCrossing(const Tape& tape, const double* x, const double* y, const double* z,
                             const glm::dvec3* normals, double tolerance);
    double march(const Tape& tape, const glm::dvec3& p, double f0, double reach, double minStep);

    bool final_;
    PointEvaluator<Dual<double>> evaluator_;
    PointEvaluator<double> plain_;
    std::vector<Dual<double>> values_, stepped_;
    std::vector<std::size_t> walking_, settled_, trusted_;
    std::vector<double> wx_, wy_, wz_;
    std::vector<glm::dvec3> at_, samples_;
    std::vector<double> first_, crossings_, fields_;
    // Per sample, the side of the zero it lies on where that is known and
    // |f| cannot tell (walkWhereNoCrossing: +1 a film, outside the part; -1
    // a glue line, inside), else 0: the sign a march looks to leave.
    std::vector<signed char> side_;
};


} // namespace kerf::mesher

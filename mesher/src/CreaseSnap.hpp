#pragma once
// Puts a point exactly onto a sharp edge of the part, straight or curved
// (the rim of a hole, where a leg meets the floor cut): the curve where two
// smooth sheets of the surface meet, f_A = 0 and f_B = 0.
//
// Newton's method on (f_A, f_B, e . (x - x0)) = 0, e the edge's direction:
// each sheet is sampled a little way onto its own side of the edge (where
// the field is that sheet's alone: the tape's min or max picks it there),
// its tangent plane taken there, and the two planes and the plane across
// the edge through x0 meet at the next point. Quadratic near the edge, so
// a few steps reach rounding; the sampling distance shrinks with the step.
// Used by extended marching cubes (TileMesher) and by the refinement
// (ToleranceRefiner) for the vertices they put on sharp edges.

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <glm/vec3.hpp>

#include <optional>
#include <utility>

namespace kerf::mesher {

struct SurfacePoint {
    glm::dvec3 p;
    glm::dvec3 n; // unit
};

/// Newton steps along the gradient from `p` onto the surface, until
/// |f| <= `settled`; nothing when they wander further than `reach` from p
/// or meet a zero gradient, and nothing when they settle on a zero the
/// field does not cross (two bodies touching inside the part). The normal is the gradient of the step before
/// the last (at the surface itself the gradient can be rounding noise, or 0
/// where the field is exactly 0); a start already on the surface takes it a
/// hair off, on the side of `expected`.
std::optional<SurfacePoint> projectOntoSurface(const Tape& tape, GradientEvaluator<double>& gradients, glm::dvec3 p,
                                               double reach, double settled, const glm::dvec3& expected);

/// The point of the sharp edge near `x` in the plane across it through `x`,
/// where the sheets have (about) unit normals `nA` and `nB` near x (at least
/// 25 degrees apart); `scale` is the size of the neighbourhood (mm: a cell, an
/// edge's length) and `tolerance` how close to the surface the result must
/// be. Nothing when the sheets cannot be found or do not meet there.
///
/// `onSheets`: a point of each sheet the caller knows (a cell polygon's
/// vertices, root-found, with their normals), for the first step. Sampled
/// from x instead, a sheet can be missed: a cell's polygon centre 0.87 mm
/// from one face of a board and 0.88 mm from the other, at 2 mm cells,
/// projects onto the nearer face from both sides, and a plain box's edges
/// were cut off by a third of a cell.
std::optional<glm::dvec3> snapToCrease(const Tape& tape, GradientEvaluator<double>& gradients, const glm::dvec3& x,
                                       glm::dvec3 nA, glm::dvec3 nB, double scale, double tolerance,
                                       const std::optional<std::pair<SurfacePoint, SurfacePoint>>& onSheets = {});

} // namespace kerf::mesher

#pragma once
// Places marching-cubes vertices on their lattice edges by root finding on
// the exact field (Illinois false position with a bisection safeguard), many
// edges in lockstep so that every iteration is one batched evaluation.
//
// Accuracy: the bracket is narrowed to kRootTolerance of the edge (1e-6 of
// the feature size); the field is 1-Lipschitz, so |f| at the vertex is below
// that times the feature size, plus the clamp below. The result is clamped
// to [margin, 1 - margin] so that no vertex sits on (or next to) a lattice
// point: two vertices on edges meeting at a corner where the surface passes
// would otherwise coincide, in memory or once written as float32. The
// mesher sets the margin from the coordinates the file will hold
// (ExportPrecision.hpp); kEdgeMargin is the least.

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace kerf {

inline constexpr double kRootTolerance = 1e-6;
inline constexpr double kEdgeMargin = 1e-6;

/// One segment with a sign change: p(t) = start + t * delta, t in [0, 1]
/// (a lattice edge: delta = h along one axis, so the other coordinates stay
/// exactly those of start). Exactly one of f0 = f(p(0)) and f1 = f(p(1)) is
/// < 0 (inside).
struct EdgeRootJob {
    glm::dvec3 start{0.0}; // world mm
    glm::dvec3 delta{0.0}; // mm
    double f0 = 0.0, f1 = 0.0;

    glm::dvec3 at(double t) const { return start + t * delta; }
};

/// Scratch memory for root finding; one per thread. Not thread-safe.
class EdgeRootFinder {
public:
    /// Writes to roots[i] the parameter t of a point where the field changes
    /// side on jobs[i] (an end whose value is exactly 0 is that point), with
    /// `tape` valid along every edge (points relative to its origin).
    /// Returns the number of field evaluations.
    std::uint64_t solve(const Tape& tape, std::span<const EdgeRootJob> jobs, double* roots);

    /// Roots closer than `margin` (a fraction of the edge, in
    /// [kEdgeMargin, 0.25]) to an end are moved to that distance.
    void setMargin(double margin) { margin_ = margin; }
    double margin() const { return margin_; }

private:
    struct State {
        double a, b;   // bracket
        double fa, fb; // field at a and b
        double wa, wb; // Illinois weights (fa, fb, halved when one side stalls)
        double widthAtCheck;
        int last; // which end moved last: 0 a, 1 b, -1 none
        int sinceCheck;
        bool bisect;
    };
    double clampToEdge(double t) const;

    double margin_ = kEdgeMargin;
    PointEvaluator<double> points_;
    std::vector<State> state_;
    std::vector<std::uint32_t> active_;
    std::vector<double> t_, x_, y_, z_, f_;
};

} // namespace kerf

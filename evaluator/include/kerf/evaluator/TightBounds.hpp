#pragma once
// The tightest axis-aligned box around a solid, to a stated tolerance: what
// a person measures with a ruler (a cut list's L x W x T, the status bar's
// bounding box), as opposed to the conservative node bounds that the
// voxelizer uses (which carry margins and blend reach).
//
// Method, per face (6 of them): branch and bound over boxes with sound
// interval evaluation. Boxes are taken from a priority queue by how far
// they reach in the face's direction; a box whose interval is positive holds
// no solid and is dropped; sample points with f <= 0 give a lower bound on
// the extent; a box found entirely inside reaches its own face. The search
// stops when the farthest unresolved box reaches no further than the lower
// bound plus the tolerance, so the true extent lies in [lower, upper] with
// upper - lower <= tolerance. Boxes split across their longest side, with
// the face's own axis preferred, since that is the extent being narrowed.
//
// Threading: pure function; evaluator scratch is local to the call.

#include "kerf/document/Aabb.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <optional>

namespace kerf {

struct TightBounds {
    Aabb inner; // every face proven to reach at least this far (solid points found there)
    Aabb outer; // no solid reaches beyond this
    /// Largest gap between inner and outer over the six faces, mm.
    double uncertainty() const;
};

/// Tight bounds of {f <= 0} for `tape`, each face within `tolerance` (mm)
/// unless `maxBoxes` interval evaluations per face run out first (then the
/// gap is wider; uncertainty() says how wide). Nothing when the solid is
/// empty; throws std::invalid_argument when the tape is unbounded.
std::optional<TightBounds> tightBounds(const Tape& tape, double tolerance = 1e-4, std::size_t maxBoxes = 200000);

} // namespace kerf

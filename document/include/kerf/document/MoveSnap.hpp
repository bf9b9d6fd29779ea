#pragma once
// Where a dragged feature comes to rest along one world axis: lined up with
// another feature (its faces or its centre on the other's faces or centre)
// when that is within reach, else on a round step of the grid. Exact
// millimetres come out: a hole dragged near 32 mm moves 32, not 31.7.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/LengthFormat.hpp"

#include <string>
#include <vector>

namespace kerf {

/// Another feature's placed bounds, and what to call it ("the shelf").
struct SnapTarget {
    std::string name;
    Aabb bounds;
};

struct AxisSnap {
    double delta = 0.0;  // the move to make (mm)
    std::string reason;  // "on the 1 mm grid", "centre on the centre of the panel", ...
};

/// The step of round values a drag snaps to when one screen pixel is
/// `mmPerPixel` long: the smallest of 0.01, 0.05, 0.1, 0.5, 1, 5, 10, 50, ...
/// mm that spans at least 6 pixels on screen; in inches, of 1/64, 1/32, ...,
/// 1/2, 1, 6, 12, 24, 48, ... inches (returned in mm).
double gridStepFor(double mmPerPixel, LengthUnit unit = LengthUnit::Millimetres);

/// The snapped move of the box `moving` by `rawDelta` along `axis` (0, 1, 2):
/// the alignment of its min face, centre or max face with a target's min
/// face, centre or max face that is nearest and within `reach` mm, else the
/// multiple of `gridStep` nearest to rawDelta. `gridStep` 0: no grid. The
/// reason names the grid in `unit` ("on the 1/16\" grid").
AxisSnap snapAxisMove(const Aabb& moving, int axis, double rawDelta, const std::vector<SnapTarget>& targets,
                      double reach, double gridStep, LengthUnit unit = LengthUnit::Millimetres);

} // namespace kerf

#include "kerf/document/MoveSnap.hpp"


#include <array>
#include <cmath>
#include <cstdio>

namespace kerf {

namespace {

const char* const kPlaceName[3] = {"low face", "centre", "high face"};

std::string stepText(double step)
{
    char text[32];
    std::snprintf(text, sizeof text, "%g", step);
    return text;
}

} // namespace

double gridStepFor(double mmPerPixel, LengthUnit unit)
{
    constexpr double kMinPixels = 6.0;
    if (!(mmPerPixel > 0.0) || !std::isfinite(mmPerPixel)) return unit == LengthUnit::Inches ? 25.4 / 16 : 1.0;
    if (unit == LengthUnit::Inches) {
        // A tape measure's steps: halvings of the inch, then inches, a foot, feet.
        for (double inches : {1.0 / 64, 1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0 / 2, 1.0, 6.0})
            if (inches * 25.4 / mmPerPixel >= kMinPixels) return inches * 25.4;
        for (double feet = 1.0;; feet *= 2.0)
            if (feet * 304.8 / mmPerPixel >= kMinPixels || feet >= 1e5) return feet * 304.8;
    }
    for (double decade = 0.01;; decade *= 10.0)
        for (double m : {1.0, 5.0}) {
            const double step = m * decade;
            if (step / mmPerPixel >= kMinPixels || step >= 1e6) return step;
        }
}

AxisSnap snapAxisMove(const Aabb& moving, int axis, double rawDelta, const std::vector<SnapTarget>& targets,
                      double reach, double gridStep, LengthUnit unit)
{
    AxisSnap best;
    double bestGap = reach;
    bool aligned = false;
    if (!moving.isEmpty()) {
        // Centres first: among equal gaps, centre on centre is what a person means.
        constexpr std::array<int, 3> kOrder{1, 0, 2};
        const std::array<double, 3> mine{moving.min[axis], 0.5 * (moving.min[axis] + moving.max[axis]),
                                         moving.max[axis]};
        for (const SnapTarget& t : targets) {
            if (t.bounds.isEmpty() || !t.bounds.isBounded()) continue;
            const std::array<double, 3> theirs{t.bounds.min[axis], 0.5 * (t.bounds.min[axis] + t.bounds.max[axis]),
                                               t.bounds.max[axis]};
            for (int i : kOrder)
                for (int j : kOrder) {
                    // The move that puts my place i on their place j, exact to their coordinates.
                    const double delta = theirs[j] - mine[i];
                    const double gap = std::abs(delta - rawDelta);
                    if (gap > bestGap || (aligned && gap == bestGap)) continue;
                    bestGap = gap;
                    aligned = true;
                    best.delta = delta;
                    best.reason = std::string(kPlaceName[i]) + " on the " + kPlaceName[j] + " of " + t.name;
                }
        }
    }
    if (aligned) return best;
    if (gridStep > 0.0) {
        best.delta = std::round(rawDelta / gridStep) * gridStep;
        if (best.delta == 0.0) best.delta = 0.0; // no "-0"
        best.reason = "on the " + (unit == LengthUnit::Inches ? lengthReadout(gridStep, unit) : stepText(gridStep) + " mm") +
                      " grid";
    } else {
        best.delta = rawDelta;
    }
    return best;
}

} // namespace kerf

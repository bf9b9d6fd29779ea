#pragma once
// The volume of a part from its exact field, with a stated uncertainty: the
// reference that `kerf bench` measures the exported mesh's volume against
// (furniture parts have no closed form in general).
//
// Method: the part's bounds are covered by blocks of 32^3 cells of edge
// `cellSize`, subdivided as an octree. Sound interval arithmetic (the
// evaluator's, with the tape simplified per box) proves a box inside
// (f < 0 everywhere) or outside (f >= 0 everywhere): such boxes count whole
// or not at all, exactly. A cell of edge `cellSize` that intervals cannot
// decide is split into 2 x 2 x 2 strata, and each stratum is sampled at two
// uniformly random points (a deterministic generator seeded by the cell's
// position); the cell's inside fraction is the mean of the strata's means.
// That estimate is unbiased, and so is the variance estimate built from the
// two samples of each stratum ((x1 - x2)^2 / 4 for a stratum's mean); the
// stated uncertainty is two standard errors of the sum (about a 95% interval).
//
// The uncertainty shrinks as cellSize^2 (the sampled shell is one cell thick
// and each cell's variance falls with its volume squared), the cost grows as
// cellSize^-2 (the surface's area in cells).

#include "kerf/document/Progress.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <cstdint>

namespace kerf {

struct VolumeEstimate {
    double volume = 0.0;       // mm^3
    double uncertainty = 0.0;  // mm^3: two standard errors (the true volume lies within +- this, about 95%)
    double provenInside = 0.0; // mm^3 that interval arithmetic proves inside
    double undecided = 0.0;    // mm^3 of the cells that were sampled
    double cellSize = 0.0;     // mm
    std::uint64_t sampledCells = 0;
    std::uint64_t samples = 0;
    bool bounded = true; // false: the part is unbounded, no volume
    bool complete = true; // false: cancelled part way, the figures are not the part's
};

/// Integrates the inside of `tape`'s solid (world coordinates) with cells of
/// edge `cellSize` mm (> 0), on `threads` threads (0: every core). The result
/// does not depend on the thread count. Throws std::invalid_argument for a
/// non-positive cell size. `work` hears the fraction of blocks integrated;
/// cancelled, it stops between blocks and the estimate is not complete.
VolumeEstimate integrateVolume(const Tape& tape, double cellSize, int threads = 0, const Progress& work = {});

} // namespace kerf

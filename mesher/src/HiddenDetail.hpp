#pragma once
// Detail that a cell hides: material (a wall, a pin, a fin) or a gap (a slot,
// a saw kerf) thinner than the cell, lying between its corners so that
// marching cubes never sees a sign change there. Left alone it comes out as
// fragments (a 0.05 mm shell at 0.1 mm cells: thousands of pieces with most
// of its volume gone) or not at all (a 0.5 mm gap closed at 0.5 mm cells).
//
// Where it is looked for: the voxelizer's seeds whose corners all lie on one
// side. Their interval contained 0, so the surface may pass through them;
// most are cells next to the surface of something thick.
//
// How: the cell is split into eight, recursively, down to a sixteenth of its
// edge. A sub-cell is dropped when its field cannot reach the other side:
// the field is 1-Lipschitz (IntervalEvaluator.hpp), so a centre value at
// least the half-diagonal away from 0 settles it, and otherwise the interval
// over the sub-cell may. A centre on the other side is a witness. Something
// thick poking into the cell (a sphere's cap, the corner of a board) gives
// witnesses too, so each witness is measured: the chord of the other side's
// region along the field's gradient there (across a wall, that is its
// thickness). Detail is reported only where that chord is under two cells;
// a board's edge poking into a cell has the whole board behind it.
//
// What it does not find: detail thinner than about a sixteenth of the cell
// (the search stops there) and detail inside cells that do have a sign
// change. Cost: one point evaluation per seed cell far from any surface,
// a few dozen near one (docs/benchmarks.md).

#include "kerf/document/Aabb.hpp"
#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <glm/vec3.hpp>

#include <optional>
#include <vector>

namespace kerf::mesher {

struct HiddenDetailFound {
    glm::dvec3 at{0.0};    // world position of the witness
    double thickness = 0.; // mm: the chord across the hidden region along the gradient
    bool material = true;  // material between outside corners (else a gap between inside corners)
};

/// Evaluators reused across cells (one per thread).
struct HiddenDetailScratch {
    PointEvaluator<double> points;
    GradientEvaluator<double> gradients;
    IntervalEvaluator intervals;
    std::vector<glm::dvec3> live, next; // sub-cells of the current and the next level
    std::vector<double> x, y, z, f;
};

/// Searches the cell `cell` (world box, a cube of edge h), whose corners all
/// lie outside (`cornersInside` false) or all inside, for a region of the
/// other side thinner than two cells. `local` must equal the part's field
/// inside the cell (a tape simplified for a box containing it); `full` is
/// the whole part's tape, used to measure the region beyond the cell.
/// `zeroBand`: values within it of 0 count as neither side.
std::optional<HiddenDetailFound> findHiddenDetail(const Tape& local, const Tape& full, const Aabb& cell,
                                                  bool cornersInside, double zeroBand, HiddenDetailScratch& scratch);

} // namespace kerf::mesher

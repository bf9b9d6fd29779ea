#pragma once
// Sound interval evaluation of a tape over an axis-aligned box, and tape
// simplification for a box.
//
// Soundness: for every point p in the box, the exact (real-number) field at
// p lies inside the returned interval. Each primitive's interval is the
// intersection of two sound enclosures: the natural interval extension of its
// distance formula (box, sphere, cylinder, torus, halfspace) and the
// Lipschitz bound f(centre) +- half-diagonal, which holds because every
// primitive's field is an exact distance (1-Lipschitz) and placements are
// isometries. Combining operations are monotone (min, max, smooth min/max,
// offset) or convex (shell), so their interval images are exact.
// The GLSL tape library computes the same intervals on the device, in float
// (shaders/tape.glsl, evaluateTileTapeInterval); TapeLanguagesTest holds the
// two together.
//
// Simplification drops every branch that cannot change the result inside the
// box: a min whose operands' intervals do not overlap keeps the lower one, a
// smooth min keeps one side when the operands stay k apart, a max the upper
// one. The simplified tape equals the full tape exactly at every point inside
// the box.

#include "kerf/document/Aabb.hpp"
#include "kerf/evaluator/Interval.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <vector>

namespace kerf {

/// Sound interval of one primitive over a box given relative to the tape origin.
Interval shapeInterval(const ShapeInstance& shape, const Aabb& box);

class IntervalEvaluator {
public:
    /// Interval of the field over `box` (tape-relative coordinates). Empty
    /// tape: [+inf, +inf].
    Interval evaluate(const Tape& tape, const Aabb& box);

    /// As evaluate(), and writes to `out` the tape simplified for `box`
    /// (origin unchanged). `out` may not alias `tape`.
    Interval simplify(const Tape& tape, const Aabb& box, Tape& out);

private:
    enum class Keep : std::uint8_t { Both, Left, Right };
    void run(const Tape& tape, const Aabb& box);

    std::vector<Interval> values_;
    std::vector<Keep> keep_;
    std::vector<std::uint32_t> stack_;
    std::vector<std::uint8_t> live_;
};

} // namespace kerf

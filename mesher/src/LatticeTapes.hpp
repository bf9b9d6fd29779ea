#pragma once
// Which tape evaluates which lattice point: the rule that makes every lattice
// value a function of the point alone.
//
// Interval simplification shortens the tape enormously near the surface (the
// chair's 42 instructions become one or two), and a simplified tape equals
// the full tape at points inside its box. Rather than lean on that equality
// being bit-exact at points shared by two boxes, every lattice point is
// evaluated with the tape of the one block that owns it: block
// floor(p / B), whose tape is the full tape simplified for the block's tile
// (the lattice's tile box), then for the block's box. Both boxes are derived
// from integer coordinates by Lattice::box, so whichever thread asks, the
// same point gets the same tape, the same coordinates and the same double.
// That is what lets two cells (or two tiles) sharing a face agree on its
// corner values, signs and asymptotic decision.
//
// Edge roots use the tape of the block owning the edge's lower end: the
// whole edge lies in that block's closed box.
//
// One per thread; the cache is cleared per tile task, so it holds the tapes
// of one tile's blocks and of their upper neighbours. Not thread-safe.

#include "Lattice.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <unordered_map>

namespace kerf::mesher {

class LatticeTapes {
public:
    LatticeTapes(const Tape& full, const Lattice& lattice) : full_(&full), lattice_(lattice) {}

    /// Forgets every cached tape.
    void clear()
    {
        blocks_.clear();
        tiles_.clear();
    }

    /// The tape owning the lattice points of block `block` (global block
    /// coordinates). The reference stays valid until clear().
    const Tape& blockTape(const I3& block);

private:
    struct Hash {
        std::size_t operator()(const I3& v) const
        {
            return std::size_t(v.x * 0x9E3779B97F4A7C15ull ^ v.y * 0xC2B2AE3D27D4EB4Full ^ v.z * 0x165667B19E3779F9ull);
        }
    };
    const Tape& tileTape(const I3& tile);

    const Tape* full_;
    Lattice lattice_;
    IntervalEvaluator intervals_;
    std::unordered_map<I3, Tape, Hash> blocks_; // node-based: references stay valid
    std::unordered_map<I3, Tape, Hash> tiles_;
};

} // namespace kerf::mesher

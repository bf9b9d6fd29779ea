#include "LatticeTapes.hpp"

namespace kerf::mesher {

namespace {
// Boxes are given to the interval evaluator relative to the tape's origin.
Aabb relative(const Aabb& box, const glm::dvec3& origin) { return {box.min - origin, box.max - origin}; }
} // namespace

const Tape& LatticeTapes::tileTape(const I3& tile)
{
    auto [it, inserted] = tiles_.try_emplace(tile);
    if (inserted)
        intervals_.simplify(*full_, relative(lattice_.box(tile * lattice_.n, lattice_.n), full_->origin()), it->second);
    return it->second;
}

const Tape& LatticeTapes::blockTape(const I3& block)
{
    auto found = blocks_.find(block);
    if (found != blocks_.end()) return found->second;
    const I3 lo = block * lattice_.b;
    const Tape& parent = tileTape(lattice_.tileOf(lo));
    Tape tape;
    intervals_.simplify(parent, relative(lattice_.box(lo, lattice_.b), full_->origin()), tape);
    return blocks_.emplace(block, std::move(tape)).first->second;
}

} // namespace kerf::mesher

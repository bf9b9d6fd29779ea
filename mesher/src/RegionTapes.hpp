#pragma once
// Tapes simplified for the neighbourhood of a point, cached by cube: what
// a sequential pass of many small local queries (the refiner's splits:
// projections, crease snaps, sampled errors) evaluates instead of the
// whole part's tape. Near most of a bookshelf side its hundred shelf-pin
// holes are decided, and the simplified tape is a few instructions long;
// inside the box it was simplified for it equals the full tape (interval
// pruning is exact there).
//
// A cube's tape holds for the cube grown by one cube on every side, so a
// query of radius up to a cube about any point inside the cube is covered.
// A larger query (a large triangle's samples: the last pass of the
// simplification makes triangles of centimetres on flat boards) gets the
// tape of a cube twice, four times, ... as large, the smallest that covers
// it: the full tape would evaluate every shape of the part for each sample
// (on the side chair, its two curved rails' 32-edge profiles were 30 % of
// that pass's time, for samples nowhere near them).
//
// Not thread-safe: one per thread.

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <unordered_map>

namespace kerf::mesher {

class RegionTapes {
public:
    /// `tape` must outlive this; `cube` (mm) the size of the cached regions
    /// (0 or less: always the full tape).
    RegionTapes(const Tape& tape, double cube) : tape_(tape), cube_(cube) {}

    /// A tape equal to the full one at every world point within `radius` of
    /// `centre`.
    const Tape& near(const glm::dvec3& centre, double radius)
    {
        if (!(cube_ > 0.0) || !(radius <= cube_ * double(1u << (kLevels - 1)))) return tape_;
        std::size_t level = 0;
        double size = cube_;
        while (radius > size) {
            ++level;
            size *= 2.0;
        }
        const glm::dvec3 local = centre - tape_.origin();
        const glm::dvec3 cell = glm::floor(local / size);
        if (!(glm::all(glm::lessThan(glm::abs(cell), glm::dvec3(1e6))))) return tape_; // far outside (or NaN)
        const auto key = (std::uint64_t(std::int64_t(cell.x) + (1 << 20)) << 42) ^
                         (std::uint64_t(std::int64_t(cell.y) + (1 << 20)) << 21) ^ std::uint64_t(std::int64_t(cell.z) + (1 << 20));
        std::unique_ptr<Tape>& slot = cache_[level][key];
        if (!slot) {
            slot = std::make_unique<Tape>();
            const glm::dvec3 lo = (cell - 1.0) * size, hi = (cell + 2.0) * size;
            intervals_.simplify(tape_, Aabb{lo, hi}, *slot);
        }
        return *slot;
    }

private:
    const Tape& tape_;
    double cube_;
    IntervalEvaluator intervals_;
    static constexpr std::size_t kLevels = 12; // cubes up to 2048 times `cube`
    std::array<std::unordered_map<std::uint64_t, std::unique_ptr<Tape>>, kLevels> cache_;
};

} // namespace kerf::mesher

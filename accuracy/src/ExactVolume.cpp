#include "kerf/accuracy/ExactVolume.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/voxelizer/WorkerArena.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <tbb/task_arena.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace kerf {

namespace {

constexpr int kBlockLevels = 5;       // a block is 2^5 = 32 cells across
constexpr int kStrata = 2;            // per axis, in an undecided cell
constexpr int kSamplesPerStratum = 2; // two, so that each stratum's variance can be estimated
constexpr int kCellSamples = kStrata * kStrata * kStrata * kSamplesPerStratum;

std::uint64_t splitmix64(std::uint64_t& state)
{
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Uniform in [0, 1).
double uniform(std::uint64_t& state) { return double(splitmix64(state) >> 11) * 0x1.0p-53; }

struct BlockSum {
    double inside = 0.0;    // proven, mm^3
    double sampled = 0.0;   // estimated inside volume of undecided cells, mm^3
    double variance = 0.0;  // of `sampled`, mm^6
    double undecided = 0.0; // mm^3
    std::uint64_t cells = 0;
};

class BlockIntegrator {
public:
    BlockIntegrator(const Tape& tape, const glm::dvec3& gridOrigin, double cellSize)
        : tape_(tape), gridOrigin_(gridOrigin), cellSize_(cellSize)
    {
        tapes_.resize(kBlockLevels + 1);
    }

    // Integrates the block whose minimum cell is `cell` (integer cell
    // coordinates from the grid origin).
    BlockSum integrate(const glm::i64vec3& cell)
    {
        sum_ = {};
        visit(tape_, cell, kBlockLevels);
        return sum_;
    }

private:
    // A box of 2^level cells across.
    void visit(const Tape& parent, const glm::i64vec3& cell, int level)
    {
        const double edge = cellSize_ * double(std::int64_t(1) << level);
        const glm::dvec3 lo = gridOrigin_ + glm::dvec3(cell) * cellSize_;
        const glm::dvec3 o = tape_.origin();
        Tape& simplified = tapes_[std::size_t(level)];
        const Interval range = intervals_.simplify(parent, {lo - o, lo + glm::dvec3(edge) - o}, simplified);
        if (range.lo >= 0.0) return; // outside: f >= 0 everywhere in the box
        if (range.hi < 0.0) {
            sum_.inside += edge * edge * edge;
            return;
        }
        if (level == 0) return sample(simplified, cell, lo);
        const std::int64_t half = std::int64_t(1) << (level - 1);
        for (int k = 0; k < 8; ++k)
            visit(simplified, cell + glm::i64vec3(k & 1 ? half : 0, k & 2 ? half : 0, k & 4 ? half : 0), level - 1);
    }

    void sample(const Tape& tape, const glm::i64vec3& cell, const glm::dvec3& lo)
    {
        // Seeded by the cell's position: the same samples whatever the thread.
        std::uint64_t state = std::uint64_t(cell.x) * 0x8CB92BA72F3D8DD7ull ^
                              std::uint64_t(cell.y) * 0x9E3779B97F4A7C15ull ^
                              std::uint64_t(cell.z) * 0xC2B2AE3D27D4EB4Full;
        const double stratum = cellSize_ / kStrata;
        const glm::dvec3 o = tape.origin();
        int n = 0;
        for (int s = 0; s < kStrata * kStrata * kStrata; ++s) {
            const glm::dvec3 corner =
                lo + stratum * glm::dvec3(s % kStrata, (s / kStrata) % kStrata, s / (kStrata * kStrata));
            for (int j = 0; j < kSamplesPerStratum; ++j, ++n) {
                // One draw per statement: the order in which a constructor's
                // arguments are evaluated is unspecified (GCC goes right to
                // left, clang left to right), and with it which draw lands on
                // which axis. This is GCC's order, so results stay as they were.
                const double dz = uniform(state), dy = uniform(state), dx = uniform(state);
                const glm::dvec3 p = corner + stratum * glm::dvec3(dx, dy, dz) - o;
                x_[std::size_t(n)] = p.x;
                y_[std::size_t(n)] = p.y;
                z_[std::size_t(n)] = p.z;
            }
        }
        points_.evaluate(tape, x_.data(), y_.data(), z_.data(), std::size_t(n), f_.data());
        double fraction = 0.0, variance = 0.0;
        constexpr int strata = kStrata * kStrata * kStrata;
        for (int s = 0; s < strata; ++s) {
            const double a = f_[std::size_t(2 * s)] < 0.0 ? 1.0 : 0.0, b = f_[std::size_t(2 * s + 1)] < 0.0 ? 1.0 : 0.0;
            fraction += 0.5 * (a + b) / strata;
            variance += (a - b) * (a - b) / 4.0 / (double(strata) * strata);
        }
        const double volume = cellSize_ * cellSize_ * cellSize_;
        sum_.sampled += fraction * volume;
        sum_.variance += variance * volume * volume;
        sum_.undecided += volume;
        ++sum_.cells;
    }

    const Tape& tape_;
    glm::dvec3 gridOrigin_;
    double cellSize_;
    IntervalEvaluator intervals_;
    PointEvaluator<double> points_;
    std::vector<Tape> tapes_; // one simplified tape per level
    std::array<double, kCellSamples> x_{}, y_{}, z_{}, f_{};
    BlockSum sum_;
};

} // namespace

VolumeEstimate integrateVolume(const Tape& tape, double cellSize, int threads, const Progress& work)
{
    if (!(cellSize > 0.0) || !std::isfinite(cellSize))
        throw std::invalid_argument("integrateVolume: the cell size must be positive");
    VolumeEstimate result;
    result.cellSize = cellSize;
    const Aabb bounds = tape.bounds();
    if (tape.empty() || bounds.isEmpty()) return result;
    if (!bounds.isBounded()) {
        result.bounded = false;
        return result;
    }
    // A cell's width of margin: no solid point on the bounds is left out.
    const Aabb box = bounds.grown(cellSize);
    const double blockEdge = cellSize * double(1 << kBlockLevels);
    const glm::i64vec3 blocks(glm::ceil(box.size() / blockEdge));
    const std::size_t count = std::size_t(blocks.x * blocks.y * blocks.z);
    std::vector<BlockSum> sums(count);
    tbb::enumerable_thread_specific<BlockIntegrator> integrators(tape, box.min, cellSize);
    tbb::task_arena arena = workerArena(threads);
    std::atomic<std::size_t> done{0};
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
            if (work.cancelled()) return;
            const std::int64_t b = std::int64_t(i);
            const glm::i64vec3 block(b % blocks.x, (b / blocks.x) % blocks.y, b / (blocks.x * blocks.y));
            sums[i] = integrators.local().integrate(block * std::int64_t(1 << kBlockLevels));
            if (work.reporting()) work.report(double(++done) / double(count));
        });
    });
    result.complete = !work.cancelled();
    // Summed in block order: the same figures whatever the thread count.
    double variance = 0.0, sampled = 0.0;
    for (const BlockSum& s : sums) {
        result.provenInside += s.inside;
        sampled += s.sampled;
        variance += s.variance;
        result.undecided += s.undecided;
        result.sampledCells += s.cells;
    }
    result.samples = result.sampledCells * kCellSamples;
    result.volume = result.provenInside + sampled;
    result.uncertainty = 2.0 * std::sqrt(variance);
    return result;
}

} // namespace kerf

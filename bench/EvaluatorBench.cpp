// Evaluator throughput on the default chair: point evaluations per second
// (float, double, with gradients), interval evaluations and simplifications
// per second, all on one core; and how much tape simplification shortens the
// tape at each level of a 4x4x4 subdivision.
//
//   build/bench/kerf_bench_evaluator [--benchmark_filter=...]

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include <benchmark/benchmark.h>

#include <random>

namespace kerf {
namespace {

const Tape& chair()
{
    static const Tape tape = compileTape(Document::load(KERF_EXAMPLES_DIR "/side-chair.kerf"));
    return tape;
}

template <class S> struct Points {
    std::vector<S> x, y, z;
};

template <class S> Points<S> randomPoints(const Aabb& b, std::size_t n)
{
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Points<S> p;
    for (std::size_t i = 0; i < n; ++i) {
        p.x.push_back(S(b.min.x + u(rng) * b.size().x));
        p.y.push_back(S(b.min.y + u(rng) * b.size().y));
        p.z.push_back(S(b.min.z + u(rng) * b.size().z));
    }
    return p;
}

template <class S> void BM_PointEvaluation(benchmark::State& state)
{
    const Tape& tape = chair();
    const auto p = randomPoints<S>(tape.bounds(), 4096);
    std::vector<S> out(4096);
    PointEvaluator<S> eval;
    for (auto _ : state) {
        eval.evaluate(tape, p.x.data(), p.y.data(), p.z.data(), out.size(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(out.size()));
    state.counters["tape_instructions"] = double(tape.size());
}
BENCHMARK_TEMPLATE(BM_PointEvaluation, float);
BENCHMARK_TEMPLATE(BM_PointEvaluation, double);

void BM_GradientEvaluation(benchmark::State& state)
{
    const Tape& tape = chair();
    const auto p = randomPoints<float>(tape.bounds(), 4096);
    std::vector<float> d(4096), gx(4096), gy(4096), gz(4096);
    GradientEvaluator<float> eval;
    for (auto _ : state) {
        eval.evaluate(tape, p.x.data(), p.y.data(), p.z.data(), d.size(), d.data(), gx.data(), gy.data(), gz.data());
        benchmark::DoNotOptimize(d.data());
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(d.size()));
}
BENCHMARK(BM_GradientEvaluation);

std::vector<Aabb> randomBoxes(const Aabb& b, double fraction, std::size_t n)
{
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Aabb> boxes;
    const glm::dvec3 size = b.size() * fraction;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 lo = b.min + (b.size() - size) * glm::dvec3(u(rng), u(rng), u(rng));
        boxes.push_back({lo, lo + size});
    }
    return boxes;
}

void BM_IntervalEvaluation(benchmark::State& state)
{
    const Tape& tape = chair();
    const auto boxes = randomBoxes(tape.bounds(), 1.0 / 16.0, 1024);
    IntervalEvaluator eval;
    for (auto _ : state)
        for (const auto& b : boxes) benchmark::DoNotOptimize(eval.evaluate(tape, b));
    state.SetItemsProcessed(state.iterations() * std::int64_t(boxes.size()));
}
BENCHMARK(BM_IntervalEvaluation);

void BM_Simplify(benchmark::State& state)
{
    const Tape& tape = chair();
    const auto boxes = randomBoxes(tape.bounds(), 1.0 / 16.0, 1024);
    IntervalEvaluator eval;
    Tape out;
    for (auto _ : state)
        for (const auto& b : boxes) benchmark::DoNotOptimize(eval.simplify(tape, b, out));
    state.SetItemsProcessed(state.iterations() * std::int64_t(boxes.size()));
}
BENCHMARK(BM_Simplify);

// Subdivides the chair's cubic bounding region 4x4x4 per level, keeping only
// ambiguous cells (interval contains 0) and simplifying the parent's tape for
// each child, as the voxelizer does. Reports the mean tape length per level.
void BM_TapeLengthAtDepth(benchmark::State& state)
{
    const Tape& root = chair();
    const int levels = 4;
    std::vector<double> meanLength(levels + 1), cells(levels + 1);
    for (auto _ : state) {
        IntervalEvaluator eval;
        const glm::dvec3 c = root.bounds().center();
        const double side = std::max({root.bounds().size().x, root.bounds().size().y, root.bounds().size().z});
        struct Cell {
            Aabb box;
            Tape tape;
        };
        std::vector<Cell> current{{Aabb{c - glm::dvec3(side / 2), c + glm::dvec3(side / 2)}, root}};
        for (int level = 0; level <= levels; ++level) {
            double sum = 0;
            for (const auto& cell : current) sum += double(cell.tape.size());
            meanLength[std::size_t(level)] = sum / double(std::max<std::size_t>(current.size(), 1));
            cells[std::size_t(level)] = double(current.size());
            if (level == levels) break;
            std::vector<Cell> next;
            for (const auto& cell : current) {
                const glm::dvec3 step = cell.box.size() / 4.0;
                for (int i = 0; i < 64; ++i) {
                    const glm::dvec3 lo = cell.box.min + step * glm::dvec3(i & 3, (i >> 2) & 3, i >> 4);
                    Cell child{{lo, lo + step}, {}};
                    const Interval iv = eval.simplify(cell.tape, child.box, child.tape);
                    if (iv.lo <= 0.0 && iv.hi >= 0.0) next.push_back(std::move(child));
                }
            }
            current = std::move(next);
        }
    }
    for (int level = 0; level <= levels; ++level) {
        state.counters["len_L" + std::to_string(level)] = meanLength[std::size_t(level)];
        state.counters["cells_L" + std::to_string(level)] = cells[std::size_t(level)];
    }
}
BENCHMARK(BM_TapeLengthAtDepth)->Unit(benchmark::kMillisecond)->Iterations(1);

} // namespace
} // namespace kerf

BENCHMARK_MAIN();

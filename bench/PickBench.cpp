// What a click and a hover cost in the viewport, on the GUI thread: the
// exact ray under the cursor (a plain click: the baseline) against a snap
// for measuring (the same ray plus the primitives' corners, edges and rims
// near the cursor, each checked on the exact field). Every bundled example,
// iso view at 1280 x 800, the cursor swept over a grid of 9 x 9 points.

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/tracer/SnapPoint.hpp"

#include <benchmark/benchmark.h>

#include <glm/geometric.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace {

const char* const kExamples[] = {"bookshelf-side", "door-frame", "side-chair", "stool", "table-top"};

struct Scene {
    kerf::Tape tape;
    kerf::Camera camera;
    std::vector<glm::dvec2> cursors;
};

Scene scene(int example)
{
    Scene s;
    s.tape = kerf::compileTape(kerf::Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) /
                                                    (std::string(kExamples[example]) + ".kerf")));
    s.camera = kerf::Camera::standardView(s.tape.bounds(), "iso", 1280, 800);
    // Over the part's image (its bounds' projection), where a person points.
    glm::dvec2 lo(1e300), hi(-1e300);
    const kerf::Aabb& b = s.tape.bounds();
    for (int c = 0; c < 8; ++c) {
        const auto p = s.camera.project(glm::dvec3((c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y,
                                                   (c & 4) ? b.max.z : b.min.z));
        lo = glm::min(lo, *p);
        hi = glm::max(hi, *p);
    }
    for (int i = 1; i <= 9; ++i)
        for (int j = 1; j <= 9; ++j) s.cursors.push_back(lo + (hi - lo) * glm::dvec2(i / 10.0, j / 10.0));
    return s;
}

void BM_PickRay(benchmark::State& state)
{
    const Scene s = scene(int(state.range(0)));
    const double epsilon = std::max(1e-6, 1e-6 * glm::length(s.tape.bounds().size()));
    std::size_t i = 0;
    for (auto _ : state) {
        const glm::dvec2 c = s.cursors[i++ % s.cursors.size()];
        benchmark::DoNotOptimize(kerf::castExactRay(s.tape, s.camera.ray(c.x, c.y), epsilon));
    }
    state.SetLabel(kExamples[state.range(0)]);
}
BENCHMARK(BM_PickRay)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);

void BM_SnapAt(benchmark::State& state)
{
    const Scene s = scene(int(state.range(0)));
    std::size_t i = 0;
    for (auto _ : state) {
        const glm::dvec2 c = s.cursors[i++ % s.cursors.size()];
        benchmark::DoNotOptimize(kerf::snapAt(s.tape, s.camera, c));
    }
    state.SetLabel(kExamples[state.range(0)]);
}
BENCHMARK(BM_SnapAt)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);

} // namespace

BENCHMARK_MAIN();

// Voxelizer benchmarks (issue 3): cold voxelization of the default chair at
// several feature sizes and thread counts, re-voxelization after moving one
// dowel hole, tiles against depth, and a seed-comparable case; and the
// tiles' exact tapes evaluated as the hybrid refinement does (values, and
// values with gradients) at points spread over each tile.
//
//   build/bench/kerf_bench_voxelizer [--benchmark_filter=...]

#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/tracer/ViewController.hpp"
#include "kerf/voxelizer/TileTape.hpp"
#include "kerf/voxelizer/Voxelizer.hpp"

#include <benchmark/benchmark.h>

namespace kerf {
namespace {

const Document& chairDocument()
{
    static const Document doc = Document::load(KERF_EXAMPLES_DIR "/side-chair.kerf");
    return doc;
}

void report(benchmark::State& state, const VoxelSnapshot& s)
{
    long surfaceTiles = 0;
    for (const auto& t : s.tiles)
        if (t && t->state == TileState::Surface) ++surfaceTiles;
    state.counters["bytes"] = double(s.bytes());
    state.counters["voxels"] = double(s.populatedVoxels());
    state.counters["bytes_per_voxel"] = double(s.bytes()) / double(std::max<std::size_t>(1, s.populatedVoxels()));
    state.counters["tiles"] = double(s.layout.tileCount());
    state.counters["surface_tiles"] = double(surfaceTiles);
    state.counters["levels"] = s.layout.levels;
}

// Args: feature size in micrometres, threads.
void BM_ChairCold(benchmark::State& state)
{
    const double fs = double(state.range(0)) / 1000.0;
    const Tape tape = compileTape(chairDocument());
    const GridLayout g = GridLayout::choose(tape.bounds(), fs);
    VoxelSnapshot s;
    for (auto _ : state) {
        s = voxelize(tape, g, {.levels = -1, .threads = int(state.range(1))});
        benchmark::DoNotOptimize(s.tiles.data());
    }
    report(state, s);
}
BENCHMARK(BM_ChairCold)
    ->ArgNames({"fs_um", "threads"})
    ->Args({2000, 1})->Args({2000, 2})
    ->Args({1000, 1})->Args({1000, 2})
    ->Args({500, 1})->Args({500, 2})
    ->Args({250, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ChairCold)->ArgNames({"fs_um", "threads"})->Args({100, 2})->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// Modelling only what the view needs (issue 7): the chair seen close up, a
// 1920x1080 view zoomed to a sixth of the standard iso distance towards the
// front corner of the seat, voxelized by the background Voxelizer (2
// threads) until complete, with the view-dependent plan against uniform
// full depth. Args: feature size in micrometres; view: 0 uniform, 1 the
// view-dependent plan, 2 the same with the viewport's picture of the view
// (tiles the part hides stay coarse). The picture, made before the timing,
// is the CPU tracer's 1920x1080 trace of the chair voxelized at 1 mm, as a
// viewport would show it before the new build.
void BM_ChairCloseUp(benchmark::State& state)
{
    const double fs = double(state.range(0)) / 1000.0;
    Document doc = chairDocument();
    doc.settings.featureSize = fs;
    const Tape tape = compileTape(doc);
    ViewController view;
    view.setStandardView("iso", tape.bounds(), 16.0 / 9.0);
    const Aabb seat = Aabb{{-225.0, -240.0, 428.0}, {225.0, 220.0, 450.0}}; // the seat (its box in the document)
    view.zoom(1.0 / 6.0, glm::dvec3(seat.max.x, seat.min.y, seat.max.z));
    const Camera camera = view.camera(1920, 1080, tape.bounds());
    const ViewRequirement need = viewRequirement(camera);
    std::shared_ptr<const OcclusionMap> picture;
    if (state.range(1) == 2) {
        const TraceImage image =
            traceVoxels(FlatVoxelBuffers::flatten(voxelize(tape, GridLayout::choose(tape.bounds(), 1.0))), camera);
        picture = std::make_shared<const OcclusionMap>(
            OcclusionMap::fromDepths(need, image.width, image.height, image.depth));
    }
    std::shared_ptr<const VoxelSnapshot> s;
    VoxelizerStats stats;
    for (auto _ : state) {
        Voxelizer vox({.limits = {}, .coarseLevelDrop = 2, .threads = 2, .featureSize = 0.0, .onPublish = {}});
        if (state.range(1)) vox.setView(need);
        if (picture) vox.setOcclusion(picture);
        const auto rev = vox.setDocument(doc);
        if (!vox.waitFor(rev, true, std::chrono::minutes(10))) state.SkipWithError("timed out");
        s = vox.snapshot();
        stats = vox.lastStats();
    }
    report(state, *s);
    state.counters["outside_view_tiles"] = double(s->outsideView);
    state.counters["hidden_tiles"] = double(s->hiddenTiles);
    state.counters["coarse_ms"] = stats.coarseMs;
}
BENCHMARK(BM_ChairCloseUp)
    ->ArgNames({"fs_um", "view"})
    ->Args({500, 0})->Args({500, 1})->Args({500, 2})
    ->Args({250, 0})->Args({250, 1})->Args({250, 2})
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// Tiles against depth at the same voxel size: the grid limit decides how
// many levels each tile's contree has. Args: max tiles, threads.
void BM_ChairTilesVersusDepth(benchmark::State& state)
{
    const Tape tape = compileTape(chairDocument());
    const GridLayout g = GridLayout::choose(tape.bounds(), 0.5, {.maxTiles = state.range(0), .maxLevels = 10, .minLevels = 1});
    VoxelSnapshot s;
    for (auto _ : state) s = voxelize(tape, g, {.levels = -1, .threads = int(state.range(1))});
    report(state, s);
}
BENCHMARK(BM_ChairTilesVersusDepth)
    ->ArgNames({"max_tiles", "threads"})
    ->Args({200000, 2})->Args({32768, 2})->Args({1000, 2})->Args({100, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// Moves one dowel hole by 5 mm and waits for the complete re-voxelization;
// counts the tiles rebuilt. Arg: feature size in micrometres.
void BM_ChairMoveDowelHole(benchmark::State& state)
{
    Document doc = chairDocument();
    Node* hole = doc.root.find("dowel-hole-r");
    if (!hole) {
        state.SkipWithError("the chair has no node 'dowel-hole-r'");
        return;
    }
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 2, .threads = 2, .featureSize = double(state.range(0)) / 1000.0,
                   .onPublish = {}});
    vox.waitFor(vox.setDocument(doc), true, std::chrono::minutes(5));
    double coarse = 0, fine = 0;
    std::size_t dirty = 0, tiles = 0;
    int n = 0;
    for (auto _ : state) {
        hole->transform.translate.x += (n % 2 ? -5.0 : 5.0);
        const auto rev = vox.setDocument(doc);
        vox.waitFor(rev, true, std::chrono::minutes(5));
        const VoxelizerStats st = vox.lastStats();
        coarse += st.coarseMs;
        fine += st.fineMs;
        dirty = st.dirtyTiles;
        tiles = st.tilesInGrid;
        ++n;
    }
    state.counters["coarse_ms"] = coarse / n;
    state.counters["final_ms"] = fine / n;
    state.counters["tiles_rebuilt"] = double(dirty);
    state.counters["tiles"] = double(tiles);
}
BENCHMARK(BM_ChairMoveDowelHole)->ArgNames({"fs_um"})->Arg(1000)->Arg(500)->Unit(benchmark::kMillisecond)->UseRealTime();

// The seed's case, approximated with Kerf's primitives (the document format
// has no sine): a sphere of radius 4 with 26 blended bumps, about 11 units
// across, in a 10-unit region, voxelized as one tile 5 levels deep and as
// 16^3 tiles 3 levels deep: both 1024 voxels across (the seed's "depth 4"
// and "depth 2" count levels from zero). Args: tiles per axis, threads.
void BM_SeedBumpySphere(benchmark::State& state)
{
    std::string bumps;
    int id = 0;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z) {
                if (!x && !y && !z) continue;
                const glm::dvec3 d = glm::normalize(glm::dvec3(x, y, z)) * 4.2;
                bumps += R"(,{"id":"b)" + std::to_string(id++) + R"(","type":"sphere","radius":1.1,"transform":{"translate":[)" +
                         std::to_string(d.x) + "," + std::to_string(d.y) + "," + std::to_string(d.z) + "]}}";
            }
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","blend":0.8,
        "children":[{"id":"s","type":"sphere","radius":4})" + bumps + "]}}",
                                         "seed");
    const Tape tape = compileTape(doc);
    const int tilesPerAxis = int(state.range(0));
    const int levels = tilesPerAxis == 1 ? 5 : 3;
    GridLayout g;
    g.dims = glm::ivec3(tilesPerAxis);
    g.tileSize = 10.0 / tilesPerAxis;
    g.levels = levels;
    g.voxelSize = g.tileSize / std::pow(4.0, levels);
    g.origin = glm::dvec3(-5.0);
    VoxelSnapshot s;
    for (auto _ : state) s = voxelize(tape, g, {.levels = -1, .threads = int(state.range(1))});
    report(state, s);
}
BENCHMARK(BM_SeedBumpySphere)
    ->ArgNames({"tiles_per_axis", "threads"})
    ->Args({1, 1})->Args({16, 1})->Args({16, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// The chair's surface tiles' exact tapes (2 mm), each at 64 points of its
// tile: the CPU reference tracer's hybrid refinement runs exactly this.
// Arg 0: values (evaluateTileTape), 1: with gradients (evaluateTileTapeGradient).
void BM_TileTapeEvaluation(benchmark::State& state)
{
    static const VoxelSnapshot chair = [] {
        const Tape tape = compileTape(chairDocument());
        return voxelize(tape, GridLayout::choose(tape.bounds(), 2.0));
    }();
    std::vector<const std::vector<std::uint32_t>*> tapes;
    for (const auto& t : chair.tiles)
        if (t && !t->tape.empty()) tapes.push_back(&t->tape);
    const float edge = float(chair.layout.tileSize);
    std::size_t evaluations = 0;
    for (auto _ : state) {
        float sum = 0.0f;
        for (const auto* tape : tapes)
            for (int i = 0; i < 64; ++i) {
                const glm::vec3 p = edge * glm::vec3((i & 3) + 0.5f, ((i >> 2) & 3) + 0.5f, (i >> 4) + 0.5f) / 4.0f;
                if (state.range(0) == 0) {
                    sum += voxel::evaluateTileTape(tape->data(), p);
                } else {
                    std::uint32_t feature = 0;
                    sum += voxel::evaluateTileTapeGradient(tape->data(), p, feature).y;
                }
            }
        benchmark::DoNotOptimize(sum);
        evaluations += tapes.size() * 64;
    }
    state.counters["tapes"] = double(tapes.size());
    state.counters["evaluations_per_s"] = benchmark::Counter(double(evaluations), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TileTapeEvaluation)->ArgNames({"gradient"})->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

} // namespace
} // namespace kerf

BENCHMARK_MAIN();

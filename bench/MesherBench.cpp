// Export benchmarks (issue 5): the default chair meshed, checked and written
// as binary STL, at several feature sizes and thread counts (and
// BM_ChairFileChecks: the checks of the file as a reader gets it).
// Counters: triangles, the time of each phase, triangles per second, and
// the peak resident memory of the export.
//
//   build/bench/kerf_bench_mesher [--benchmark_filter=...]
//
// Peak memory is the kernel's high-water mark of resident memory (VmHWM in
// /proc/self/status), reset before every export by writing 5 to
// /proc/self/clear_refs (Linux 4.0+): it counts everything the process
// touches (malloc'd, mmap'd, oneTBB's), not only operator new. `base_MB` is
// the resident memory just before the export (the program, the document,
// after handing malloc's free pages back with malloc_trim); `peak_MB -
// base_MB` is what the export itself needed. The STL goes to a
// temporary folder ($TMPDIR or /tmp) and is deleted after each iteration.

#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/mesher/SelfIntersections.hpp"
#include "kerf/mesher/StlWriter.hpp"
#include "kerf/mesher/WrittenCoordinates.hpp"

#include <tbb/task_arena.h>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <unistd.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace kerf {
namespace {

const Document& chairDocument()
{
    static const Document doc = Document::load(KERF_EXAMPLES_DIR "/side-chair.kerf");
    return doc;
}

// Resident memory in MB from /proc/self/status ("VmRSS" now, "VmHWM" peak).
double statusMegabytes(const char* field)
{
    std::ifstream in("/proc/self/status");
    std::string line;
    const std::string prefix = std::string(field) + ":";
    while (std::getline(in, line))
        if (line.rfind(prefix, 0) == 0) return std::stod(line.substr(prefix.size())) / 1024.0; // kB
    return 0.0;
}

// malloc keeps freed memory resident for reuse; without this, what earlier
// runs freed would count in the next run's base and hide part of its need.
void releaseFreedMemory()
{
#ifdef __GLIBC__
    ::malloc_trim(0);
#endif
}

bool resetPeakMemory()
{
    std::ofstream out("/proc/self/clear_refs");
    out << "5";
    return bool(out);
}

double since(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Args: feature size in micrometres, threads.
void BM_ChairExport(benchmark::State& state)
{
    const double fs = double(state.range(0)) / 1000.0;
    MeshOptions options;
    options.featureSize = fs;
    options.threads = int(state.range(1));
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("kerf-bench-chair-" + std::to_string(::getpid()) + ".stl");
    double meshSeconds = 0, checkSeconds = 0, writeSeconds = 0, peak = 0, base = 0;
    std::size_t triangles = 0, vertices = 0;
    bool watertight = true;
    MeshStats stats;
    int n = 0;
    for (auto _ : state) {
        releaseFreedMemory();
        base = statusMegabytes("VmRSS");
        if (!resetPeakMemory()) state.SkipWithError("cannot reset the peak-memory mark (/proc/self/clear_refs)");
        auto t = std::chrono::steady_clock::now();
        std::optional<Mesh> mesh = meshPart(chairDocument(), options, {}, &stats);
        meshSeconds += since(t);
        t = std::chrono::steady_clock::now();
        const MeshReport report = checkMesh(*mesh);
        checkSeconds += since(t);
        t = std::chrono::steady_clock::now();
        writeStl(*mesh, file);
        writeSeconds += since(t);
        peak = std::max(peak, statusMegabytes("VmHWM"));
        watertight = watertight && report.watertight();
        triangles = mesh->triangles.size();
        vertices = mesh->vertices.size();
        std::filesystem::remove(file);
        ++n;
    }
    if (!watertight) state.SkipWithError("the mesh is not watertight");
    state.counters["triangles"] = double(triangles);
    state.counters["vertices"] = double(vertices);
    state.counters["mesh_s"] = meshSeconds / n;
    state.counters["check_s"] = checkSeconds / n;
    state.counters["write_s"] = writeSeconds / n;
    state.counters["tri_per_s_mesh"] = double(triangles) * n / meshSeconds;
    state.counters["tri_per_s_export"] = double(triangles) * n / (meshSeconds + checkSeconds + writeSeconds);
    state.counters["peak_MB"] = peak;
    state.counters["base_MB"] = base;
    state.counters["seed_cpu_s"] = stats.seedSeconds;
    state.counters["cell_cpu_s"] = stats.cellSeconds;
    state.counters["merge_s"] = stats.mergeSeconds;
    state.counters["flood_cells"] = double(stats.cellsFromFloodFill);
    state.counters["rounds"] = stats.rounds;
}
// The chair at 1 and 0.5 mm cells on 1 and 2 threads, twice each.
benchmark::internal::Benchmark* chairSizesAndThreads(benchmark::internal::Benchmark* b)
{
    return b->ArgNames({"fs_um", "threads"})
        ->ArgsProduct({{1000, 500}, {1, 2}})
        ->Iterations(2)
        ->Unit(benchmark::kMillisecond);
}
void chairExportRuns(benchmark::internal::Benchmark* b) { chairSizesAndThreads(b)->UseRealTime(); }
BENCHMARK(BM_ChairExport)->Apply(chairExportRuns);
BENCHMARK(BM_ChairExport)
    ->ArgNames({"fs_um", "threads"})
    ->Args({250, 1})
    ->Args({250, 2})
    ->Args({100, 2})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Meshes the chair once per iteration (no check, no file); returns the peak
// resident memory in MB, the last mesh's figures in `stats`.
double meshChairRepeatedly(benchmark::State& state, const MeshOptions& options, MeshStats& stats)
{
    double peak = 0;
    for (auto _ : state) {
        releaseFreedMemory();
        if (!resetPeakMemory()) state.SkipWithError("cannot reset the peak-memory mark (/proc/self/clear_refs)");
        std::optional<Mesh> mesh = meshPart(chairDocument(), options, {}, &stats);
        benchmark::DoNotOptimize(mesh->triangles.data());
        peak = std::max(peak, statusMegabytes("VmHWM"));
    }
    return peak;
}

// Meshing alone (no check, no file), for the scaling of the mesher itself.
void BM_ChairMeshOnly(benchmark::State& state)
{
    MeshOptions options;
    options.featureSize = double(state.range(0)) / 1000.0;
    options.threads = int(state.range(1));
    options.findHiddenDetail = state.range(2) != 0;
    MeshStats stats;
    const double peak = meshChairRepeatedly(state, options, stats);
    state.counters["triangles"] = double(stats.triangles);
    state.counters["tri_per_s"] =
        benchmark::Counter(double(stats.triangles), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["peak_MB"] = peak;
    state.counters["seed_cpu_s"] = stats.seedSeconds;
    state.counters["cell_cpu_s"] = stats.cellSeconds;
    state.counters["merge_s"] = stats.mergeSeconds;
    state.counters["hidden_searches"] = double(stats.hiddenDetailSearches);
}
BENCHMARK(BM_ChairMeshOnly)
    ->ArgNames({"fs_um", "threads", "hidden"})
    ->Args({1000, 1, 1})
    ->Args({1000, 2, 1})
    ->Args({500, 1, 1})
    ->Args({500, 2, 1})
    ->Args({1000, 2, 0})
    ->Args({500, 2, 0})
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The part's side of the tolerance (SurfaceCoverage.hpp) on every bundled
// example at the default tolerance: the export with the refinement's last
// step, the splits for the part's points beyond the tolerance, and without
// it (the baseline, same run): triangles, the part's points beyond the
// tolerance and the furthest, triangles left over the tolerance, time.
void BM_ExamplePartSide(benchmark::State& state)
{
    static const char* const examples[] = {"side-chair", "stool", "door-frame", "bookshelf-side", "table-top",
                                           "turned-leg"};
    const Document doc = Document::load(std::string(KERF_EXAMPLES_DIR) + "/" + examples[state.range(0)] + ".kerf");
    MeshOptions options;
    options.tolerance = double(state.range(1)) / 1000.0;
    options.coverPartPoints = state.range(2) != 0;
    MeshStats stats;
    for (auto _ : state) {
        std::optional<Mesh> mesh = meshPart(doc, options, {}, &stats);
        benchmark::DoNotOptimize(mesh->triangles.data());
    }
    state.SetLabel(examples[state.range(0)]);
    state.counters["triangles"] = double(stats.triangles);
    state.counters["part_beyond"] = double(stats.partSamplesBeyond);
    state.counters["part_worst_um"] = 1000.0 * stats.worstPartSample;
    state.counters["tri_over"] = double(stats.trianglesOverTolerance);
    state.counters["tri_worst_um"] = 1000.0 * stats.worstSample;
}
BENCHMARK(BM_ExamplePartSide)
    ->ArgNames({"example", "tol_um", "cover"})
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {50, 10}, {0, 1}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The export a woodworker gets: meshed and simplified to a tolerance (the
// default 0.05 mm, and 0.01), no check or file, for the thread scaling of
// the whole simplified path (lattice, simplification, refinement).
void BM_ChairSimplified(benchmark::State& state)
{
    MeshOptions options;
    options.featureSize = double(state.range(0)) / 1000.0;
    options.tolerance = double(state.range(1)) / 1000.0;
    options.threads = int(state.range(2));
    MeshStats stats;
    const double peak = meshChairRepeatedly(state, options, stats);
    state.counters["triangles"] = double(stats.triangles);
    state.counters["lattice_triangles"] = double(stats.latticeTriangles);
    state.counters["lattice_s"] = stats.seconds - stats.simplifySeconds - stats.refineSeconds;
    state.counters["simplify_s"] = stats.simplifySeconds;
    state.counters["refine_s"] = stats.refineSeconds;
    state.counters["over"] = double(stats.trianglesOverTolerance);
    state.counters["peak_MB"] = peak;
}
BENCHMARK(BM_ChairSimplified)
    ->ArgNames({"fs_um", "tol_um", "threads"})
    ->Args({500, 50, 1})
    ->Args({500, 50, 2})
    ->Args({500, 50, 4})
    ->Args({500, 50, 8})
    ->Args({500, 50, 16})
    ->Args({500, 10, 2})
    ->Args({500, 10, 16})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The checks `kerf export` makes of the file as a reader gets it, on the
// chair's marching-cubes mesh (no simplification: the largest meshes an
// export checks): the fit to the written coordinates, the read-back weld,
// the connectivity check and the search for crossing triangles, on 1 and 2
// threads. Manual time: the four steps, not the copy of the mesh that the
// fit changes.
void BM_ChairFileChecks(benchmark::State& state)
{
    static std::map<long, Mesh> meshes;
    const long fsUm = long(state.range(0));
    if (!meshes.contains(fsUm)) {
        MeshOptions options;
        options.featureSize = double(fsUm) / 1000.0;
        meshes[fsUm] = *meshPart(chairDocument(), options);
    }
    tbb::task_arena arena(int(state.range(1)));
    double fit = 0, read = 0, check = 0, crossing = 0;
    std::size_t pairs = 0;
    int n = 0;
    for (auto _ : state) {
        Mesh mesh = meshes[fsUm];
        double total = 0;
        arena.execute([&] {
            auto t = std::chrono::steady_clock::now();
            auto lap = [&] {
                const double s = since(t);
                t = std::chrono::steady_clock::now();
                total += s;
                return s;
            };
            fitToWritten(mesh, WrittenFormat::Float32);
            fit += lap();
            const Mesh asRead = readBack(mesh, WrittenFormat::Float32, true);
            read += lap();
            benchmark::DoNotOptimize(checkMesh(asRead));
            check += lap();
            pairs = findSelfIntersections(asRead, 0).pairs;
            crossing += lap();
        });
        state.SetIterationTime(total);
        ++n;
    }
    if (pairs != 0) state.SkipWithError("the chair's mesh crosses itself");
    state.counters["triangles"] = double(meshes[fsUm].triangles.size());
    state.counters["fit_s"] = fit / n;
    state.counters["read_back_s"] = read / n;
    state.counters["check_s"] = check / n;
    state.counters["crossings_s"] = crossing / n;
}
void chairFileCheckRuns(benchmark::internal::Benchmark* b) { chairSizesAndThreads(b)->UseManualTime(); }
BENCHMARK(BM_ChairFileChecks)->Apply(chairFileCheckRuns);

} // namespace
} // namespace kerf

BENCHMARK_MAIN();

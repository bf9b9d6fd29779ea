// Trace time per frame of the Vulkan compute tracer on whatever device Kerf
// finds (the H100 of the `device` tool, lavapipe here): the default chair at
// several feature sizes and a stand-in for the seed's showcase, at 1920x1080
// and 2560x1440, each with and without the hybrid refinement (quality
// voxels and exact). Headless; needs only the Vulkan loader and what the core
// links, so it can be carried to a machine without Qt or a package registry.
//
//   kerf_gpu_bench [--quick] [--frames N] [--quality voxels|exact|exact-everywhere|all]
//                  [--scene chair|showcase] [--feature-size MM]
//                  [--json OUT.json] [--examples DIR] [--pipeline-statistics]
//
// --scene and --feature-size keep only that scene and that feature size (for
// slow devices, where the whole run would take hours). --pipeline-statistics
// prints the compiler's figures for each trace pipeline after its scene
// (registers, spills, as the driver names them; VK_KHR_pipeline_executable_properties,
// which NVIDIA's driver has and this machine's lavapipe has not).
//
//   kerf_gpu_bench bench FILE.kerf [kerf bench's options but --plot]
//
//   kerf_gpu_bench voxelize [--scene chair|showcase] [--feature-size MM]
//                           [--repeats N] [--json OUT.json] [--examples DIR]
//                           [--one-thread-up-to VOXELS] [--cpu-threads 1,2,4,8,16]
//
// The voxelize form times the GPU voxelizer (vk::GpuVoxelizer) against the
// CPU voxelizer on every core and on one (one core only up to a populated
// voxel count, by default 30 million: the chair at 0.1 mm would take minutes),
// cold (a fresh voxelizer: its pools guessed) and warm (a rebuild of the same
// part, as after an edit that dirties every tile), all in the same run.
//
//   kerf_gpu_bench bricks [--scene chair|showcase] [--feature-size MM] [--frames N]
//                         [--accuracy-width PIXELS] [--json OUT.json] [--examples DIR]
// measures brick leaves and the brick renderer against contree leaves and
// the compute tracer's voxel trace (issue 19).
//
//   kerf_gpu_bench edit [--scene chair|showcase] [--feature-size MM] [--edits N] [--json OUT.json]
//                       [--examples DIR]
//
// The edit form times what the viewport does after an edit of the chair
// (and of the showcase) when it voxelizes on the GPU (View > Voxelize on the GPU): the typical
// edit (kerf bench's: a feature moved 5 mm, back and forth), the document
// compiled, the tiles it reaches found, the GPU voxelizer's worker building
// them into the build on screen, and one 2560x1440 trace of the result: the
// edit to its final picture. The same run times each edit as an update of
// the dirty tiles and as a whole rebuild, alternated.
//
// The bench form runs `kerf bench` itself (the same code, app/TradeBench),
// so that the speed/accuracy table can be measured on the GPU machine, which
// has no Qt; --trace-only leaves out the export measurements.

#include "kerf/app/Commands.hpp"
#include "kerf/app/TypicalEdit.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/ExactRefinement.h"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/viewport/BrickRenderer.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/GpuVoxelWorker.hpp"
#include "kerf/viewport/GpuVoxelizer.hpp"
#include "kerf/voxelizer/DirtyRegion.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

using namespace kerf;

namespace {

// The seed's showcase stand-in: four spheres about 11 units across with 26
// blended bumps each (the document format has no sine to distort them).
Document showcase()
{
    std::string kids;
    int id = 0;
    for (int s = 0; s < 4; ++s) {
        const glm::dvec3 c((s & 1) ? 7.0 : -7.0, (s & 2) ? 7.0 : -7.0, 0.0);
        std::string bumps;
        for (int x = -1; x <= 1; ++x)
            for (int y = -1; y <= 1; ++y)
                for (int z = -1; z <= 1; ++z) {
                    if (!x && !y && !z) continue;
                    const glm::dvec3 d = c + glm::normalize(glm::dvec3(x, y, z)) * 4.2;
                    bumps += R"(,{"id":"b)" + std::to_string(id++) +
                             R"(","type":"sphere","radius":1.1,"transform":{"translate":[)" + std::to_string(d.x) +
                             "," + std::to_string(d.y) + "," + std::to_string(d.z) + "]}}";
                }
        kids += std::string(s ? "," : "") + R"({"id":"u)" + std::to_string(s) +
                R"(","type":"union","blend":0.8,"children":[)" + R"({"id":"s)" + std::to_string(s) +
                R"(","type":"sphere","radius":4,"transform":{"translate":[)" + std::to_string(c.x) + "," +
                std::to_string(c.y) + "," + std::to_string(c.z) + "]}}" + bumps + "]}";
    }
    return Document::parse(
        R"({"format":"kerf","version":1,"root":{"id":"all","type":"union","children":[)" + kids + "]}}", "showcase");
}

// The options the voxelize and edit forms share; true when args[i] was one
// (i then at its value).
bool takeSceneOption(const std::vector<std::string>& args, std::size_t& i, std::string& examples, std::string& jsonPath,
                     std::string& onlyScene, double& onlyFeatureSize)
{
    const std::string& a = args[i];
    if (i + 1 >= args.size()) return false;
    if (a == "--json")
        jsonPath = args[++i];
    else if (a == "--examples")
        examples = args[++i];
    else if (a == "--scene")
        onlyScene = args[++i];
    else if (a == "--feature-size")
        onlyFeatureSize = std::atof(args[++i].c_str());
    else
        return false;
    return true;
}

// The voxelizer benchmarks' scenes: the chair and the showcase, each at the
// feature sizes issue 18 asks for.
struct Scene {
    std::string name;
    Document doc;
    std::vector<double> featureSizes;
};

std::vector<Scene> benchScenes(const std::string& examples)
{
    return {{"chair", Document::load(examples + "/side-chair.kerf"), {1.0, 0.5, 0.25, 0.1}},
            {"showcase", showcase(), {0.1, 0.01}}};
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

int voxelizeBench(const std::vector<std::string>& args)
{
    std::string examples = KERF_EXAMPLES_DIR, jsonPath, onlyScene;
    double onlyFeatureSize = 0.0, oneThreadUpTo = 3e7;
    int repeats = 5;
    bool cpu = true;
    bool prune = true; // --no-prune: every node on its tile's tape (the cold build's before)
    std::vector<int> threadSweep;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const bool more = i + 1 < args.size();
        if (takeSceneOption(args, i, examples, jsonPath, onlyScene, onlyFeatureSize)) continue;
        if (a == "--no-cpu")
            cpu = false;
        else if (a == "--no-prune")
            prune = false;
        else if (a == "--repeats" && more)
            repeats = std::max(1, std::atoi(args[++i].c_str()));
        else if (a == "--one-thread-up-to" && more)
            oneThreadUpTo = std::atof(args[++i].c_str());
        else if (a == "--cpu-threads" && more) {
            std::stringstream list(args[++i]);
            for (std::string t; std::getline(list, t, ',');)
                threadSweep.push_back(std::max(1, std::atoi(t.c_str())));
        } else {
            std::cerr << "usage: kerf_gpu_bench voxelize [--scene chair|showcase] [--feature-size MM] [--repeats N] "
                         "[--json OUT.json] [--examples DIR] [--one-thread-up-to VOXELS] [--cpu-threads 1,2,4,...] [--no-cpu] [--no-prune]\n";
            return 2;
        }
    }
    vk::Context ctx;
    std::cout << "device: " << ctx.deviceDescription() << "\n";
    std::vector<Scene> scenes = benchScenes(examples);
    nlohmann::ordered_json results = nlohmann::ordered_json::array();
    std::printf("%-9s %6s %11s %5s %9s %9s %8s %8s %8s %9s %8s %7s %10s %10s %8s\n", "scene", "fs", "voxels", "host",
                "gpu cold", "gpu warm", "prepare", "alloc", "upload", "device", "pool MB", "reruns", "cpu all", "cpu 1",
                "Gvox/s");
    for (auto& scene : scenes) {
        if (!onlyScene.empty() && scene.name != onlyScene) continue;
        const Tape tape = compileTape(scene.doc);
        if (onlyFeatureSize > 0.0) scene.featureSizes = {onlyFeatureSize};
        for (const double fs : scene.featureSizes) {
            const GridLayout layout = GridLayout::choose(tape.bounds(), fs);
            // GPU, cold: a fresh voxelizer guesses its pools from the surface tiles.
            vk::GpuVoxelizer fresh(ctx);
            vk::GpuVoxelizeReport cold;
            const vk::GpuVoxelizeOptions usual{.pruneNodeTapes = prune};
            auto t0 = std::chrono::steady_clock::now();
            std::optional<vk::GpuVoxels> gpu = fresh.build(tape, layout, usual, &cold);
            const double coldMs = millisecondsSince(t0);
            if (!gpu) {
                std::printf("%-9s %6g  GPU build refused: %s\n", scene.name.c_str(), fs, cold.whyNot.c_str());
                continue;
            }
            const std::size_t voxels = gpu->populatedVoxels;
            std::printf(
                "    gpu cold: prepare %.1f, allocate %.1f (pools %.1f), submissions %.1f ms, %d levels run again; "
                "%.1f voxels per leaf, %.2f vertices per voxel; %zu leaf nodes on a pruned tape%s\n",
                cold.prepareMilliseconds, cold.allocateMilliseconds, cold.poolAllocateMilliseconds,
                cold.deviceMilliseconds, cold.levelReruns,
                double(gpu->populatedVoxels) / double(std::max<std::size_t>(gpu->leafCount, 1)),
                double(gpu->vertexCount) / double(std::max<std::size_t>(gpu->populatedVoxels, 1)),
                cold.prunedLeafJobs, prune ? "" : " (--no-prune)");
            // Warm: rebuilds of the same part, as an edit that dirties every
            // tile asks for, while the last build is still on screen; the one
            // before it is recycled. The GPU's clocks first come up (300 ms of
            // the same work): a discrete GPU idles down between calls.
            std::optional<vk::GpuVoxels> previous;
            vk::GpuVoxelizeReport warm;
            const auto rebuild = [&](const vk::GpuVoxelizeOptions& options) {
                if (previous) fresh.recycle(std::move(*previous));
                previous = std::move(gpu);
                gpu = fresh.build(tape, layout, options, &warm);
            };
            const auto warmUp = std::chrono::steady_clock::now();
            while (millisecondsSince(warmUp) < 300.0)
                rebuild(usual);
            std::vector<double> warmMs, prepareMs, allocateMs, uploadMs, deviceMs;
            for (int r = 0; r < repeats; ++r) {
                t0 = std::chrono::steady_clock::now();
                rebuild(usual);
                warmMs.push_back(millisecondsSince(t0));
                prepareMs.push_back(warm.prepareMilliseconds);
                allocateMs.push_back(warm.allocateMilliseconds);
                uploadMs.push_back(warm.uploadMilliseconds);
                deviceMs.push_back(warm.deviceMilliseconds);
            }
            const auto list = [](const auto& values, int digits = 1) {
                std::string s;
                for (const auto v : values) {
                    char one[32];
                    std::snprintf(one, sizeof one, "%s%.*f", s.empty() ? "" : ", ", digits, double(v));
                    s += one;
                }
                return s;
            };
            std::printf("    levels' nodes: %s\n    submissions (ms), cold: %s; warm: %s\n", list(cold.levelJobs, 0).c_str(),
                        list(cold.submissionMilliseconds).c_str(), list(warm.submissionMilliseconds).c_str());
            // What the per-tile tape simplification buys: the same rebuilds
            // with the whole tape in every tile (the same voxels).
            std::vector<double> wholeTapeMs, wholeTapeDeviceMs;
            std::size_t wholeTapeHostTiles = 0;
            for (int r = 0; r < repeats; ++r) {
                t0 = std::chrono::steady_clock::now();
                rebuild({.simplifyTileTapes = false, .pruneNodeTapes = prune});
                wholeTapeMs.push_back(millisecondsSince(t0));
                wholeTapeDeviceMs.push_back(warm.deviceMilliseconds);
                wholeTapeHostTiles = warm.hostBuiltTiles;
            }
            std::printf("    whole tape in every tile: warm %.1f ms (device %.1f ms, %zu tiles built by the host); "
                        "simplified per tile: warm %.1f ms (device %.1f ms)\n",
                        median(wholeTapeMs), median(wholeTapeDeviceMs), wholeTapeHostTiles, median(warmMs),
                        median(deviceMs));
            // What pruning each node's tape on the device buys: the same
            // rebuilds with every node on its tile's tape (the same voxels).
            std::vector<double> unprunedMs, unprunedDeviceMs, unprunedLeafMs, leafMs;
            for (int r = 0; prune && r < repeats; ++r) {
                rebuild(usual);
                leafMs.push_back(warm.submissionMilliseconds.empty() ? 0.0 : warm.submissionMilliseconds.back());
                t0 = std::chrono::steady_clock::now();
                rebuild({.pruneNodeTapes = false});
                unprunedMs.push_back(millisecondsSince(t0));
                unprunedDeviceMs.push_back(warm.deviceMilliseconds);
                unprunedLeafMs.push_back(warm.submissionMilliseconds.empty() ? 0.0 : warm.submissionMilliseconds.back());
            }
            if (prune)
                std::printf("    node tapes unpruned: warm %.1f ms (device %.1f ms, leaf level %.1f ms); pruned: warm "
                            "%.1f ms (device %.1f ms, leaf level %.1f ms)\n",
                            median(unprunedMs), median(unprunedDeviceMs), median(unprunedLeafMs), median(warmMs),
                            median(deviceMs), median(leafMs));
            rebuild(usual); // the last figures below are the usual build's
            gpu.reset();
            previous.reset();
            // CPU: every core, then one (the same code, an arena of one thread).
            std::vector<double> cpuAll, cpuOne;
            std::size_t cpuVoxels = 0;
            for (int r = 0; cpu && r < std::max(1, repeats / 2); ++r) {
                t0 = std::chrono::steady_clock::now();
                const VoxelSnapshot snap = voxelize(tape, layout, {.threads = 0});
                cpuAll.push_back(millisecondsSince(t0));
                cpuVoxels = snap.populatedVoxels();
            }
            if (cpu && double(cpuVoxels) <= oneThreadUpTo) {
                t0 = std::chrono::steady_clock::now();
                (void)voxelize(tape, layout, {.threads = 1});
                cpuOne.push_back(millisecondsSince(t0));
            }
            // The CPU path's scaling: the same build on each thread count asked for.
            nlohmann::ordered_json sweep = nlohmann::ordered_json::object();
            for (const int threads : threadSweep) {
                if (threads == 1 && double(cpuVoxels) > oneThreadUpTo) continue;
                t0 = std::chrono::steady_clock::now();
                (void)voxelize(tape, layout, {.threads = threads});
                const double ms = millisecondsSince(t0);
                sweep[std::to_string(threads)] = ms;
                std::printf("    cpu %2d threads: %.1f ms\n", threads, ms);
            }
            const double gpuWarm = median(warmMs);
            std::printf("%-9s %6g %11zu %5zu %9.1f %9.1f %8.1f %8.1f %8.1f %9.1f %8.0f %7d %10.1f %10s %8.2f\n",
                        scene.name.c_str(), fs, voxels, warm.hostBuiltTiles, coldMs, gpuWarm, median(prepareMs),
                        median(allocateMs), median(uploadMs), median(deviceMs), double(warm.poolBytes) / 1e6,
                        cold.levelReruns, median(cpuAll), cpuOne.empty() ? "-" : std::to_string(int(cpuOne[0])).c_str(),
                        double(voxels) / (gpuWarm * 1e-3) / 1e9);
            std::fflush(stdout);
            results.push_back({{"scene", scene.name},
                               {"feature_size", fs},
                               {"populated_voxels", voxels},
                               {"cpu_populated_voxels", cpuVoxels},
                               {"host_built_tiles", warm.hostBuiltTiles},
                               {"gpu_cold_ms", coldMs},
                               {"gpu_cold_level_reruns", cold.levelReruns},
                               {"gpu_warm_level_reruns", warm.levelReruns},
                               {"gpu_allocate_ms", allocateMs},
                               {"gpu_warm_ms", warmMs},
                               {"gpu_prepare_ms", prepareMs},
                               {"gpu_upload_ms", uploadMs},
                               {"gpu_device_ms", deviceMs},
                               {"gpu_whole_tape_warm_ms", wholeTapeMs},
                               {"gpu_whole_tape_device_ms", wholeTapeDeviceMs},
                               {"gpu_whole_tape_host_built_tiles", wholeTapeHostTiles},
                               {"gpu_pool_bytes", warm.poolBytes},
                               {"gpu_pruned_node_tapes", prune},
                               {"gpu_pruned_leaf_jobs", cold.prunedLeafJobs},
                               {"gpu_unpruned_warm_ms", unprunedMs},
                               {"gpu_unpruned_device_ms", unprunedDeviceMs},
                               {"gpu_unpruned_leaf_level_ms", unprunedLeafMs},
                               {"gpu_leaf_level_ms", leafMs},
                               {"cpu_all_threads_ms", cpuAll},
                               {"cpu_one_thread_ms", cpuOne},
                               {"cpu_threads_ms", sweep}});
        }
    }
    if (!jsonPath.empty()) {
        nlohmann::ordered_json j;
        j["device"] = ctx.deviceDescription();
        j["results"] = results;
        std::ofstream(jsonPath) << j.dump(2) << "\n";
    }
    return 0;
}

// The edit to its final picture on the GPU path (see the usage above).
int editBench(const std::vector<std::string>& args)
{
    std::string examples = KERF_EXAMPLES_DIR, jsonPath, onlyScene;
    double onlyFeatureSize = 0.0;
    int edits = 9;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const bool more = i + 1 < args.size();
        if (takeSceneOption(args, i, examples, jsonPath, onlyScene, onlyFeatureSize)) continue;
        if (a == "--edits" && more)
            edits = std::max(1, std::atoi(args[++i].c_str()));
        else {
            std::cerr << "usage: kerf_gpu_bench edit [--scene chair|showcase] [--feature-size MM] [--edits N] "
                         "[--json OUT.json] [--examples DIR]\n";
            return 2;
        }
    }
    vk::Context ctx;
    std::cout << "device: " << ctx.deviceDescription() << "\n";
    std::vector<Scene> scenes = benchScenes(examples);
    std::mutex m;
    std::condition_variable changed;
    vk::GpuVoxelWorker worker(ctx, [&] {
        std::lock_guard lock(m);
        changed.notify_all();
    });
    vk::ComputeTracer tracer(ctx);
    std::unique_ptr<vk::GpuVoxelResult> shown;
    // Waits for the worker's complete build of `revision`; the one shown before goes back.
    const auto waitFor = [&](std::uint64_t revision) {
        for (;;) {
            if (auto r = worker.take()) {
                worker.recycle(std::move(shown));
                shown = std::move(r);
                if (shown->complete && shown->revision == revision) return;
            }
            if (!worker.busy() && !worker.refusal().empty()) throw std::runtime_error(worker.refusal());
            std::unique_lock lock(m);
            changed.wait_for(lock, std::chrono::milliseconds(1));
        }
    };
    nlohmann::ordered_json results = nlohmann::ordered_json::array();
    std::printf("%-9s %6s %9s %12s %12s %12s %12s %10s\n", "scene", "fs", "tiles", "dirty tiles", "update ms",
                "whole ms", "update dev", "trace ms");
    std::uint64_t revision = 0;
    nlohmann::ordered_json edited = nlohmann::ordered_json::object();
    for (auto& scene : scenes) {
        if (!onlyScene.empty() && scene.name != onlyScene) continue;
        const std::optional<TypicalEdit> typical = chooseTypicalEdit(scene.doc);
        if (!typical) throw std::runtime_error("the " + scene.name + " has no feature to move");
        edited[scene.name] = typical->nodeId;
        if (onlyFeatureSize > 0.0) scene.featureSizes = {onlyFeatureSize};
        for (const double fs : scene.featureSizes) {
            Document doc = scene.doc;
            const Tape first = compileTape(doc);
            const GridLayout layout = GridLayout::choose(first.bounds(), fs);
            worker.request(vk::GpuVoxelRequest::of(++revision, std::make_shared<const Tape>(first), layout, 0));
            waitFor(revision);
            std::vector<double> updateMs, wholeMs, updateDevice, traceMs;
            std::size_t dirtyCount = 0;
            const Camera camera = Camera::standardView(first.bounds(), "iso", 2560, 1440);
            // One edit to its picture: compile, dirty tiles, build, trace.
            const auto editOnce = [&](double offset, bool update) {
                const auto t0 = std::chrono::steady_clock::now();
                const Document next = applyTypicalEdit(doc, *typical, offset);
                auto tape = std::make_shared<const Tape>(compileTape(next));
                vk::GpuVoxelRequest request =
                    vk::GpuVoxelRequest::of(++revision, tape, GridLayout::choose(tape->bounds(), fs), 0);
                if (update && request.layout == layout) {
                    request.dirtyTiles = tilesAnEditReaches(doc, next, layout);
                    request.dirtySince = revision - 1;
                }
                if (update)
                    dirtyCount = request.dirtyTiles ? request.dirtyTiles->size() : std::size_t(layout.tileCount());
                worker.request(std::move(request));
                waitFor(revision);
                const auto t1 = std::chrono::steady_clock::now();
                const vk::VoxelAddresses voxels = shown->voxels->addresses(revision);
                ctx.submitAndWait([&](VkCommandBuffer cb) { tracer.record(cb, camera, voxels); });
                const double total = millisecondsSince(t0);
                (update ? updateMs : wholeMs).push_back(total);
                if (update) {
                    updateDevice.push_back(shown->report.deviceMilliseconds);
                    traceMs.push_back(millisecondsSince(t1));
                }
                doc = next;
            };
            // Warm-up (the GPU clocks up), then edits alternating +5/-5 mm, each way timed.
            for (int i = 0; i < 4; ++i)
                editOnce(i % 2 ? -kTypicalEditMm : kTypicalEditMm, true);
            for (int i = 0; i < edits; ++i) {
                editOnce(kTypicalEditMm, true);
                editOnce(-kTypicalEditMm, false);
                editOnce(kTypicalEditMm, false);
                editOnce(-kTypicalEditMm, true);
            }
            std::printf("%-9s %6g %9ld %12zu %12.1f %12.1f %12.1f %10.2f\n", scene.name.c_str(), fs, layout.tileCount(),
                        dirtyCount, median(updateMs), median(wholeMs), median(updateDevice), median(traceMs));
            std::fflush(stdout);
            results.push_back({{"scene", scene.name},
                               {"feature_size", fs},
                               {"tiles", layout.tileCount()},
                               {"dirty_tiles", dirtyCount},
                               {"edit_to_picture_update_ms", updateMs},
                               {"edit_to_picture_whole_ms", wholeMs},
                               {"update_device_ms", updateDevice},
                               {"trace_ms", traceMs}});
        }
    }
    worker.recycle(std::move(shown));
    if (!jsonPath.empty()) {
        nlohmann::ordered_json j;
        j["device"] = ctx.deviceDescription();
        j["edited"] = edited;
        j["results"] = results;
        std::ofstream(jsonPath) << j.dump(2) << "\n";
    }
    return 0;
}

} // namespace

// Brick leaves against contree leaves (issue 19): for each scene and
// feature size, the memory and build time of each, the frame time of the
// brick renderer against the compute tracer's voxel trace (same voxels,
// same run), and each picture's error against the exact picture.
int bricksBench(const std::vector<std::string>& args)
{
    std::string examples = KERF_EXAMPLES_DIR, jsonPath, onlyScene;
    double onlyFeatureSize = 0.0;
    int frames = 20;
    int accuracyWidth = 960;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const bool more = i + 1 < args.size();
        if (takeSceneOption(args, i, examples, jsonPath, onlyScene, onlyFeatureSize)) continue;
        if (a == "--frames" && more)
            frames = std::max(1, std::atoi(args[++i].c_str()));
        else if (a == "--accuracy-width" && more)
            accuracyWidth = std::atoi(args[++i].c_str());
        else {
            std::cerr << "usage: kerf_gpu_bench bricks [--scene chair|showcase] [--feature-size MM] [--frames N] "
                         "[--accuracy-width PIXELS (0: none)] [--json OUT.json] [--examples DIR]\n";
            return 2;
        }
    }
    vk::Context ctx;
    std::cout << "device: " << ctx.deviceDescription() << "\n";
    nlohmann::ordered_json results = nlohmann::ordered_json::array();
    std::printf("%-9s %6s %9s %9s %10s %10s %10s %10s %10s %12s %12s %12s\n", "scene", "fs", "bricks", "voxels",
                "contree MB", "bricks MB", "voxelize ms", "bricks ms", "size", "contree ms", "bricks ms", "sort ms");
    // The sizes issue 19 asks for.
    const std::vector<Scene> scenes = {{"chair", Document::load(examples + "/side-chair.kerf"), {2.0, 1.0, 0.5, 0.25}},
                                       {"showcase", showcase(), {0.1, 0.01}}};
    for (const Scene& scene : scenes) {
        if (!onlyScene.empty() && scene.name != onlyScene) continue;
        const Tape tape = compileTape(scene.doc);
        for (double fs : onlyFeatureSize > 0.0 ? std::vector<double>{onlyFeatureSize} : scene.featureSizes) {
            auto since = [](auto t0) { return millisecondsSince(t0); };
            const auto t0 = std::chrono::steady_clock::now();
            const GridLayout layout = GridLayout::choose(tape.bounds(), fs);
            const VoxelSnapshot snap = voxelize(tape, layout);
            const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(snap);
            const double voxelizeMs = since(t0);
            const auto b0 = std::chrono::steady_clock::now();
            const BrickLeaves bricks = BrickLeaves::fromVoxels(buffers);
            const double bricksMs = since(b0);
            vk::ComputeTracer tracer(ctx);
            tracer.setVoxels(buffers);
            vk::BrickRenderer renderer(ctx);
            renderer.setBricks(bricks);
            for (auto [w, h] : std::vector<std::pair<int, int>>{{1920, 1080}, {2560, 1440}}) {
                const Camera camera = Camera::standardView(tape.bounds(), "iso", w, h);
                // Alternated, twice: the faster of each.
                double contreeMs = 1e30, brickMs = 1e30;
                for (int round = 0; round < 2; ++round) {
                    contreeMs = std::min(contreeMs, tracer.sustainedMilliseconds(camera, frames, TraceQuality::Voxels));
                    brickMs = std::min(brickMs, renderer.sustainedMilliseconds(camera, frames));
                }
                // A section across X through the middle (the bricks draw it
                // themselves since 2026-12-02; before, the tracer did).
                const Aabb box = tape.bounds();
                const Section section = Section::alongAxis(0, 0.5 * (box.min.x + box.max.x));
                double contreeCutMs = 1e30, brickCutMs = 1e30;
                for (int round = 0; round < 2; ++round) {
                    contreeCutMs = std::min(contreeCutMs,
                                            tracer.sustainedMilliseconds(camera, frames, TraceQuality::Voxels, section));
                    brickCutMs = std::min(brickCutMs, renderer.sustainedMilliseconds(camera, frames, section));
                }
                renderer.render(camera); // a moved eye: the sort's cost
                const Camera moved = Camera::standardView(tape.bounds(), "front", w, h);
                renderer.render(moved);
                const double sortMs = renderer.lastSortMilliseconds();
                std::printf("%-9s %6g %9zu %9zu %10.1f %10.1f %10.1f %10.1f %5dx%-5d %11.3f %12.3f %12.1f\n",
                            scene.name.c_str(), fs, bricks.bricks.size(), snap.populatedVoxels(),
                            double(snap.bytes()) / 1e6, double(renderer.residentBytes()) / 1e6, voxelizeMs, bricksMs, w,
                            h, contreeMs, brickMs, sortMs);
                std::printf("    with a section across X through the middle: contree %.3f ms, bricks %.3f ms\n",
                            contreeCutMs, brickCutMs);
                std::fflush(stdout);
                results.push_back({{"scene", scene.name}, {"feature_size", fs}, {"bricks", bricks.bricks.size()},
                                   {"populated_voxels", snap.populatedVoxels()}, {"contree_bytes", snap.bytes()},
                                   {"brick_device_bytes", renderer.residentBytes()}, {"voxelize_ms", voxelizeMs},
                                   {"bricks_from_contree_ms", bricksMs}, {"width", w}, {"height", h},
                                   {"contree_sustained_ms", contreeMs}, {"bricks_sustained_ms", brickMs},
                                   {"sort_ms", sortMs}, {"contree_section_sustained_ms", contreeCutMs},
                                   {"bricks_section_sustained_ms", brickCutMs}});
            }
            if (accuracyWidth > 0) {
                // Against the exact picture (the exact tracer, 1e-4 voxel), on
                // the pixels all three hit.
                const int w = accuracyWidth, h = accuracyWidth * 9 / 16;
                const Camera camera = Camera::standardView(tape.bounds(), "iso", w, h);
                const TraceImage exact = traceExact(tape, camera, 1e-4 * layout.voxelSize);
                const TraceImage contree = tracer.trace(camera);
                const TraceImage brick = renderer.render(camera);
                struct Error {
                    std::vector<double> depth, angle;
                    std::size_t masked = 0;
                };
                Error ec, eb;
                for (std::size_t i = 0; i < exact.depth.size(); ++i) {
                    ec.masked += exact.hit(i) != contree.hit(i);
                    eb.masked += exact.hit(i) != brick.hit(i);
                    if (!exact.hit(i) || !contree.hit(i) || !brick.hit(i)) continue;
                    for (auto [e, image] : {std::pair{&ec, &contree}, std::pair{&eb, &brick}}) {
                        e->depth.push_back(std::fabs(double(image->depth[i]) - double(exact.depth[i])));
                        e->angle.push_back(glm::degrees(std::acos(std::clamp(
                            double(glm::dot(image->normal[i], exact.normal[i])), -1.0, 1.0))));
                    }
                }
                auto quantile = [](std::vector<double> v, double q) {
                    if (v.empty()) return 0.0;
                    std::sort(v.begin(), v.end());
                    return v[std::size_t(q * double(v.size() - 1))];
                };
                for (auto [name, e] : {std::pair{"contree", &ec}, std::pair{"bricks", &eb}}) {
                    const double meanDepth = e->depth.empty() ? 0.0 :
                        std::accumulate(e->depth.begin(), e->depth.end(), 0.0) / double(e->depth.size());
                    const double meanAngle = e->angle.empty() ? 0.0 :
                        std::accumulate(e->angle.begin(), e->angle.end(), 0.0) / double(e->angle.size());
                    std::printf("    %-8s against the exact picture at %dx%d: depth mean %.4f p99 %.4f mm, normal mean "
                                "%.2f p99 %.2f deg, mask differs %zu px\n",
                                name, w, h, meanDepth, quantile(e->depth, 0.99), meanAngle, quantile(e->angle, 0.99),
                                e->masked);
                    results.push_back({{"scene", scene.name}, {"feature_size", fs}, {"leaves", name},
                                       {"width", w}, {"height", h}, {"depth_mean_mm", meanDepth},
                                       {"depth_p99_mm", quantile(e->depth, 0.99)}, {"normal_mean_deg", meanAngle},
                                       {"normal_p99_deg", quantile(e->angle, 0.99)}, {"mask_differs", e->masked}});
                }
                std::fflush(stdout);
            }
        }
    }
    if (!jsonPath.empty()) {
        nlohmann::ordered_json j;
        j["device"] = ctx.deviceDescription();
        j["frames"] = frames;
        j["results"] = results;
        std::ofstream(jsonPath) << j.dump(2) << "\n";
    }
    return 0;
}

int main(int argc, char** argv)
{
    if (argc > 1 && std::string(argv[1]) == "voxelize") {
        try {
            return voxelizeBench(std::vector<std::string>(argv + 2, argv + argc));
        } catch (const std::exception& e) {
            std::cerr << "kerf_gpu_bench: " << e.what() << "\n";
            return 1;
        }
    }
    if (argc > 1 && std::string(argv[1]) == "bricks") {
        try {
            return bricksBench(std::vector<std::string>(argv + 2, argv + argc));
        } catch (const std::exception& e) {
            std::cerr << "kerf_gpu_bench: " << e.what() << "\n";
            return 1;
        }
    }
    if (argc > 1 && std::string(argv[1]) == "edit") {
        try {
            return editBench(std::vector<std::string>(argv + 2, argv + argc));
        } catch (const std::exception& e) {
            std::cerr << "kerf_gpu_bench: " << e.what() << "\n";
            return 1;
        }
    }
    if (argc > 1 && std::string(argv[1]) == "bench")
        return kerf::runBench(std::vector<std::string>(argv + 2, argv + argc), std::cout, std::cerr);
    bool quick = false;
    int frames = 20;
    std::string jsonPath, examples = KERF_EXAMPLES_DIR;
    std::vector<TraceQuality> qualities{TraceQuality::Voxels, TraceQuality::ExactEverywhere, TraceQuality::Exact};
    std::string onlyScene;
    double onlyFeatureSize = 0.0;
    bool pipelineStatistics = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--quick")
            quick = true;
        else if (a == "--pipeline-statistics")
            pipelineStatistics = true;
        else if (a == "--frames" && i + 1 < argc)
            frames = std::max(1, std::atoi(argv[++i]));
        else if (a == "--json" && i + 1 < argc)
            jsonPath = argv[++i];
        else if (a == "--examples" && i + 1 < argc)
            examples = argv[++i];
        else if (a == "--scene" && i + 1 < argc)
            onlyScene = argv[++i];
        else if (a == "--feature-size" && i + 1 < argc)
            onlyFeatureSize = std::atof(argv[++i]);
        else if (a == "--quality" && i + 1 < argc && std::string(argv[i + 1]) == "all")
            ++i; // the default
        else if (a == "--quality" && i + 1 < argc && parseTraceQuality(argv[i + 1]))
            qualities = {*parseTraceQuality(argv[++i])};
        else {
            std::cerr << "usage: kerf_gpu_bench [--quick] [--frames N] [--quality voxels|exact|exact-everywhere|all] "
                         "[--scene chair|showcase] [--feature-size MM] [--json OUT.json] [--examples DIR] "
                         "[--pipeline-statistics]\n"
                         "       kerf_gpu_bench bench FILE.kerf [kerf bench options]\n";
            return 2;
        }
    }
    try {
        vk::ContextOptions options;
        options.pipelineStatistics = pipelineStatistics;
        vk::Context ctx(options);
        std::cout << "device: " << ctx.deviceDescription() << "\n";
        if (pipelineStatistics && !ctx.capturesPipelineStatistics())
            std::cout << "pipeline statistics: this device has no VK_KHR_pipeline_executable_properties\n";
        struct Scene {
            std::string name;
            Document doc;
            std::vector<double> featureSizes;
        };
        std::vector<Scene> scenes;
        const Document chair = Document::load(examples + "/side-chair.kerf");
        scenes.push_back(
            {"chair", chair, quick ? std::vector<double>{2.0, 1.0} : std::vector<double>{2.0, 1.0, 0.5, 0.25}});
        scenes.push_back({"showcase", showcase(), quick ? std::vector<double>{0.1} : std::vector<double>{0.1, 0.01}});
        const std::vector<std::pair<int, int>> sizes =
            quick ? std::vector<std::pair<int, int>>{{640, 360}}
                  : std::vector<std::pair<int, int>>{{1920, 1080}, {2560, 1440}};

        nlohmann::ordered_json results = nlohmann::ordered_json::array();
        std::printf("%-9s %8s %11s %10s %9s %11s %10s %16s %12s %12s %14s\n", "scene", "fs", "voxels", "MB", "tape MB",
                    "upload ms", "size", "quality", "trace ms", "Mrays/s", "sustained ms");
        for (auto& scene : scenes) {
            if (!onlyScene.empty() && scene.name != onlyScene) continue;
            const Tape tape = compileTape(scene.doc);
            if (onlyFeatureSize > 0.0) scene.featureSizes = {onlyFeatureSize};
            for (double fs : scene.featureSizes) {
                const auto t0 = std::chrono::steady_clock::now();
                const GridLayout layout = GridLayout::choose(tape.bounds(), fs);
                const VoxelSnapshot snap = voxelize(tape, layout);
                const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(snap);
                const double voxelizeMs =
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                vk::ComputeTracer tracer(ctx);
                const auto u0 = std::chrono::steady_clock::now();
                tracer.setVoxels(buffers);
                const double uploadMs =
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - u0).count();
                const std::size_t tapeBytes = buffers.tapes.size() * sizeof(std::uint32_t);
                for (auto [w, h] : sizes)
                    for (TraceQuality quality : qualities) {
                        const Camera camera = Camera::standardView(tape.bounds(), "iso", w, h);
                        std::vector<double> ms;
                        std::size_t hits = 0;
                        for (int f = 0; f < frames + 2; ++f) {
                            vk::TraceTiming timing;
                            const TraceImage image = tracer.trace(camera, &timing, {}, quality);
                            if (f >= 2) ms.push_back(timing.gpuMilliseconds); // two warm-up frames
                            if (f == 0)
                                for (std::size_t i = 0; i < image.depth.size(); ++i)
                                    hits += image.hit(i);
                        }
                        const double m = median(ms);
                        const double mrays = double(w) * h / (m * 1e-3) / 1e6;
                        // Each frame above waits for its read-back, so the
                        // GPU idles between frames; see sustainedMilliseconds.
                        const double sustained = tracer.sustainedMilliseconds(camera, frames, quality);
                        // The last sustained frame's timestamps: Exact's passes, warm.
                        const vk::TraceTiming passes = tracer.lastTiming();
                        const std::string q(traceQualityName(quality));
                        std::printf("%-9s %8g %11zu %10.1f %9.2f %11.1f %5dx%-5d %16s %11.3f %12.1f %14.3f",
                                    scene.name.c_str(), fs, snap.populatedVoxels(), double(snap.bytes()) / 1e6,
                                    double(tapeBytes) / 1e6, uploadMs, w, h, q.c_str(), m, mrays, sustained);
                        if (quality == TraceQuality::Exact)
                            std::printf("   passes %.3f + %.3f + %.3f ms, %u pixels refined (%.1f%% of hits), %d lanes a ray",
                                        passes.voxelPassMilliseconds, passes.checkMilliseconds,
                                        passes.refineMilliseconds, passes.refinedPixels,
                                        100.0 * double(passes.refinedPixels) / double(std::max<std::size_t>(hits, 1)),
                                        tracer.refineLanes());
                        std::printf("\n");
                        std::fflush(stdout);
                        results.push_back({{"scene", scene.name},
                                           {"feature_size", fs},
                                           {"populated_voxels", snap.populatedVoxels()},
                                           {"bytes", snap.bytes()},
                                           {"tape_bytes", tapeBytes},
                                           {"voxelize_ms", voxelizeMs},
                                           {"upload_ms", uploadMs},
                                           {"width", w},
                                           {"height", h},
                                           {"quality", q},
                                           {"pixels_hit", hits},
                                           {"trace_ms_median", m},
                                           {"trace_ms_min", *std::min_element(ms.begin(), ms.end())},
                                           {"mrays_per_s", mrays},
                                           {"trace_ms_sustained", sustained},
                                           {"voxel_pass_ms", passes.voxelPassMilliseconds},
                                           {"check_ms", passes.checkMilliseconds},
                                           {"refine_ms", passes.refineMilliseconds},
                                           {"pixels_refined", passes.refinedPixels},
                                           {"refine_lanes", tracer.refineLanes()}});
                    }
                if (ctx.capturesPipelineStatistics())
                    for (const auto& [name, lines] : tracer.pipelineStatistics()) {
                        std::printf("pipeline %s:", name.c_str());
                        for (const std::string& line : lines) std::printf(" [%s]", line.c_str());
                        std::printf("\n");
                    }
            }
        }
        if (!jsonPath.empty()) {
            nlohmann::ordered_json j;
            j["device"] = ctx.deviceDescription();
            j["frames"] = frames;
            j["exact_refinement"] = {{"margin_voxels", KERF_EXACT_MARGIN},
                                     {"sphere_steps", KERF_EXACT_STEPS},
                                     {"bracketed_steps", KERF_EXACT_BRACKETED_STEPS},
                                     {"refinements", KERF_EXACT_REFINEMENTS},
                                     {"epsilon_voxels", KERF_EXACT_EPSILON},
                                     {"check_shift_voxels", KERF_EDGE_CHECK_SHIFT},
                                     {"check_residual_voxels", KERF_EDGE_CHECK_RESIDUAL},
                                     {"check_clearance_voxels", KERF_EDGE_CHECK_CLEARANCE},
                                     {"check_smooth_clearance_voxels", KERF_EDGE_CHECK_SMOOTH_CLEARANCE},
                                     {"check_clearance_per_radian", KERF_EDGE_CHECK_CLEARANCE_PER_RADIAN},
                                     {"refine_lanes_at_most", KERF_EDGE_REFINE_MAX_LANES},
                                     {"refine_rounds", KERF_EDGE_REFINE_ROUNDS},
                                     {"refine_window_rounds", KERF_EDGE_REFINE_WINDOW_ROUNDS},
                                     {"check_smooth_angle_degrees", KERF_EDGE_CHECK_SMOOTH_ANGLE}};
            j["results"] = results;
            std::ofstream(jsonPath) << j.dump(2) << "\n";
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "kerf_gpu_bench: " << e.what() << "\n";
        return 1;
    }
}

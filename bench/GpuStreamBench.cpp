// The upload path on a real GPU (issue 4): how the voxel streamer moves a
// published snapshot to the device under a per-frame byte budget. For the
// default chair at 0.5 and 0.25 mm and several budgets: frames until the
// whole snapshot is resident, the GPU time of each frame's copies (from
// timestamps around them), the CPU time of each frame's recording (the
// copy into the staging ring dominates it), and the throughput; then the
// same after an edit (a dowel hole moved 6 mm), where only the changed
// tiles travel. Headless, like kerf_gpu_bench: carried to the GPU machine.
//
//   kerf_gpu_stream_bench [--json OUT.json] [--examples DIR] [--quick]

#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/viewport/VoxelStreamer.hpp"
#include "kerf/viewport/VulkanError.hpp"
#include "kerf/voxelizer/Voxelizer.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using namespace kerf;

namespace {

struct StreamResult {
    int frames = 0;
    std::size_t bytes = 0;
    double gpuMsMedian = 0.0, gpuMsMax = 0.0, cpuMsMedian = 0.0, cpuMsMax = 0.0, wallMs = 0.0;
};

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// Streams `target` to the device frame by frame until it is resident.
StreamResult streamUntilResident(const vk::Context& ctx, vk::VoxelStreamer& streamer, VkQueryPool timestamps,
                                 std::shared_ptr<const VoxelSnapshot> target)
{
    StreamResult r;
    std::vector<double> gpu, cpu;
    const double period = double(ctx.properties().limits.timestampPeriod) * 1e-6; // ms per tick
    const auto start = std::chrono::steady_clock::now();
    streamer.setTarget(std::move(target));
    for (;;) {
        vk::FrameUpload up;
        double recordMs = 0.0;
        ctx.submitAndWait([&](VkCommandBuffer cb) {
            vkCmdResetQueryPool(cb, timestamps, 0, 2);
            vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps, 0);
            const auto t0 = std::chrono::steady_clock::now();
            up = streamer.recordFrame(cb);
            recordMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps, 1);
        });
        std::uint64_t stamps[2] = {0, 0};
        vk::check(vkGetQueryPoolResults(ctx.device(), timestamps, 0, 2, sizeof stamps, stamps, sizeof(std::uint64_t),
                                        VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
                  "vkGetQueryPoolResults");
        gpu.push_back(double(stamps[1] - stamps[0]) * period);
        cpu.push_back(recordMs);
        r.bytes += up.bytes;
        ++r.frames;
        if (up.switched || r.frames > 100000) break;
    }
    r.wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    r.gpuMsMedian = median(gpu);
    r.gpuMsMax = *std::max_element(gpu.begin(), gpu.end());
    r.cpuMsMedian = median(cpu);
    r.cpuMsMax = *std::max_element(cpu.begin(), cpu.end());
    return r;
}

} // namespace

int main(int argc, char** argv)
{
    std::string jsonPath, examples = KERF_EXAMPLES_DIR;
    bool quick = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--json" && i + 1 < argc) jsonPath = argv[++i];
        else if (a == "--examples" && i + 1 < argc) examples = argv[++i];
        else if (a == "--quick") quick = true;
        else {
            std::cerr << "usage: kerf_gpu_stream_bench [--json OUT.json] [--examples DIR] [--quick]\n";
            return 2;
        }
    }
    try {
        vk::Context ctx;
        std::cout << "device: " << ctx.deviceDescription() << "\n";
        VkQueryPoolCreateInfo qpci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qpci.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qpci.queryCount = 2;
        VkQueryPool pool;
        vk::check(vkCreateQueryPool(ctx.device(), &qpci, nullptr, &pool), "vkCreateQueryPool");
        const vk::QueryPool timestamps(ctx.device(), pool);

        nlohmann::ordered_json results = nlohmann::ordered_json::array();
        std::printf("%-6s %9s %8s %9s %7s %10s %15s %15s %10s\n", "fs", "MB", "budget", "what", "frames", "MB moved",
                    "GPU ms/frame", "CPU ms/frame", "GB/s");
        for (double fs : quick ? std::vector<double>{2.0} : std::vector<double>{0.5, 0.25}) {
            Document doc = Document::load(examples + "/side-chair.kerf");
            Voxelizer vox({.limits = {}, .coarseLevelDrop = 0, .threads = 0, .featureSize = fs, .onPublish = {}});
            if (!vox.waitFor(vox.setDocument(doc), true, std::chrono::minutes(10))) throw std::runtime_error("voxelize");
            const auto before = vox.snapshot();
            doc.root.find("dowel-hole-r")->transform.translate.x += 6.0;
            if (!vox.waitFor(vox.setDocument(doc), true, std::chrono::minutes(10))) throw std::runtime_error("voxelize");
            const auto after = vox.snapshot();
            for (std::size_t budgetMb : quick ? std::vector<std::size_t>{8} : std::vector<std::size_t>{8, 32, 128}) {
                vk::VoxelStreamer streamer(ctx, {.budgetBytesPerFrame = budgetMb << 20, .framesInFlight = 3,
                                                 .initialHeapBytes = 64u << 20});
                for (const auto& [what, snap] : {std::pair{"cold", before}, std::pair{"edit", after}}) {
                    const StreamResult r = streamUntilResident(ctx, streamer, timestamps, snap);
                    const double seconds = r.wallMs * 1e-3;
                    const double gbps = double(r.bytes) / 1e9 / std::max(seconds, 1e-9);
                    std::printf("%-6g %9.1f %5zu MB %9s %7d %10.1f %7.3f (max %6.3f) %6.3f (max %6.3f) %10.2f\n", fs,
                                double(snap->bytes()) / 1e6, budgetMb, what, r.frames, double(r.bytes) / 1e6,
                                r.gpuMsMedian, r.gpuMsMax, r.cpuMsMedian, r.cpuMsMax, gbps);
                    std::fflush(stdout);
                    results.push_back({{"feature_size", fs},         {"snapshot_bytes", snap->bytes()},
                                       {"budget_bytes", budgetMb << 20}, {"what", what},
                                       {"frames", r.frames},         {"bytes_moved", r.bytes},
                                       {"gpu_ms_median", r.gpuMsMedian}, {"gpu_ms_max", r.gpuMsMax},
                                       {"cpu_ms_median", r.cpuMsMedian}, {"cpu_ms_max", r.cpuMsMax},
                                       {"wall_ms", r.wallMs},        {"gb_per_s", gbps}});
                }
            }
        }
        if (!jsonPath.empty()) {
            nlohmann::ordered_json j;
            j["device"] = ctx.deviceDescription();
            j["results"] = results;
            std::ofstream(jsonPath) << j.dump(2) << "\n";
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "kerf_gpu_stream_bench: " << e.what() << "\n";
        return 1;
    }
}

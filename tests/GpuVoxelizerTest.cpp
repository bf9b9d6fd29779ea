// The GPU voxelizer (shaders/voxelize.comp, vk::GpuVoxelizer) held to the
// CPU voxelizer, its reference: the same populated voxels with the same
// corner distances and normals, on every bundled example and on generated
// parts at several feature sizes; the same picture when the compute tracer
// reads the GPU's buffers where they were built; pools that overflow grow
// and the build is retried; a budget too small is refused in words; and the
// validation layers stay quiet (lavapipe here).

#include "kerf/viewport/GpuVoxelizer.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/GpuVoxelWorker.hpp"
#include "kerf/viewport/VulkanError.hpp"
#include "kerf/voxelizer/DirtyRegion.hpp"
#include "kerf/voxelizer/TileTape.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>

namespace kerf {
namespace {

// A populated voxel as a reader of the flat buffers sees it, whatever the
// order its records were written in.
struct VoxelRead {
    std::array<float, 8> distance{};
    std::array<glm::vec3, 8> normal{};
    std::array<std::uint32_t, 8> feature{};
    std::array<glm::vec3, 8> at{};       // the corners, tile-relative mm, as the voxelizers compute them
    const std::uint32_t* tape = nullptr; // the tile's exact tape, when it has one
};
using VoxelKey = std::pair<long, glm::u64>; // tile, then x | y << 21 | z << 42 in voxels

std::map<VoxelKey, VoxelRead> readVoxels(const FlatVoxelBuffers& b, int& tilesWithEntries)
{
    std::map<VoxelKey, VoxelRead> out;
    tilesWithEntries = 0;
    for (long t = 0; t < long(b.tiles.size()); ++t) {
        const std::uint32_t w = b.tiles[std::size_t(t)];
        if (w == voxel::kEmptyTile || w == voxel::kFullTile) continue;
        ++tilesWithEntries;
        const TileEntry& e = b.entries.at(w);
        const double voxelEdge = b.layout.tileSize / std::pow(4.0, int(e.levels));
        const float voxelMm = float(voxelEdge);
        // (node, depth, minimum corner in voxels)
        std::vector<std::tuple<std::uint32_t, int, glm::u64vec3>> stack{{e.node, 0, glm::u64vec3(0)}};
        while (!stack.empty()) {
            const auto [index, depth, lo] = stack.back();
            stack.pop_back();
            const voxel::Node& n = b.nodes.at(index);
            const std::uint64_t mask = n.mask();
            const glm::u64 childEdge = glm::u64(1) << (2 * (int(e.levels) - depth - 1));
            for (int c = 0; c < 64; ++c) {
                if (!(mask >> c & 1)) continue;
                const std::uint32_t rank = std::uint32_t(std::popcount(mask & ((std::uint64_t(1) << c) - 1)));
                const glm::u64vec3 clo = lo + childEdge * glm::u64vec3(c & 3, (c >> 2) & 3, c >> 4);
                if (!n.isLeaf()) {
                    stack.emplace_back(e.node + n.pointer() + rank, depth + 1, clo);
                    continue;
                }
                const voxel::LeafIndirection& li = b.leafIndirections.at(e.leafIndirection + n.pointer());
                const voxel::LeafData& ld = b.leafData.at(e.leafData + li.leafData + rank);
                VoxelRead v;
                for (int q = 0; q < 8; ++q) {
                    const voxel::Vertex& x = b.vertices.at(e.vertex + li.vertex + ld.corner[std::size_t(q)]);
                    v.distance[std::size_t(q)] = voxel::decodeDistance(x.distanceFeature, voxelMm);
                    v.normal[std::size_t(q)] = voxel::decodeNormal(x.normal);
                    v.feature[std::size_t(q)] = voxel::decodeFeature(x.distanceFeature);
                    // Tile-relative mm as both voxelizers compute them: in double, rounded once.
                    v.at[std::size_t(q)] =
                        glm::vec3(glm::dvec3(clo + glm::u64vec3(q & 1, (q >> 1) & 1, q >> 2)) * voxelEdge);
                }
                if (e.tape != voxel::kNoTape) v.tape = b.tapes.data() + e.tape;
                out.emplace(VoxelKey{t, clo.x | clo.y << 21 | clo.z << 42}, v);
            }
        }
    }
    return out;
}

struct VoxelComparison {
    std::size_t cpu = 0, gpu = 0, both = 0;
    std::size_t onlyOneSideNearZero = 0; // in one only, with a corner within a hair of the surface
    std::size_t onlyOneSideElsewhere = 0;
    std::size_t distanceOff = 0, normalOff = 0;
    std::size_t normalTies = 0; // the GPU's normal is its tape's exact gradient; the CPU broke a tie the other way
    std::size_t gpuCorners = 0, gpuCornersNotItsTape = 0; // GPU corners against its own tape, evaluated in C++
    float worstDistance = 0.0f;
    std::set<long> tilesWithHairDifferences; // tiles holding voxels populated on one side only
};

bool hasCornerNearZero(const VoxelRead& v, float hair)
{
    for (float d : v.distance)
        if (std::fabs(d) <= hair) return true;
    return false;
}

VoxelComparison compareVoxels(const FlatVoxelBuffers& cpu, const FlatVoxelBuffers& gpu, double voxelMm)
{
    int cpuTiles = 0, gpuTiles = 0;
    const auto a = readVoxels(cpu, cpuTiles), b = readVoxels(gpu, gpuTiles);
    VoxelComparison c;
    c.cpu = a.size();
    c.gpu = b.size();
    // Three quanta of the stored distance: the two sides may round a corner's
    // value differently in its last bits (fused multiply-adds).
    const float quantum = float(2.0 * voxelMm / 32767.0);
    const float hair = 4.0f * quantum;
    const float cosTolerance = std::cos(glm::radians(0.5f));
    for (const auto& [key, v] : a) {
        const auto it = b.find(key);
        if (it == b.end()) {
            ++(hasCornerNearZero(v, hair) ? c.onlyOneSideNearZero : c.onlyOneSideElsewhere);
            c.tilesWithHairDifferences.insert(key.first);
            continue;
        }
        ++c.both;
        bool distanceOff = false, normalOff = false;
        for (std::size_t q = 0; q < 8; ++q) {
            const float dd = std::fabs(v.distance[q] - it->second.distance[q]);
            c.worstDistance = std::max(c.worstDistance, dd);
            distanceOff |= dd > 3.0f * quantum;
            // A corner on the surface may take either face's gradient; so may
            // one on a tie between two faces (inside a box, on its diagonal
            // planes), where the CPU's gradient evaluator and the tile tape's
            // break ties their own way: a GPU normal that differs from the
            // CPU's must then be its tape's exact gradient there.
            if (std::fabs(v.distance[q]) <= hair || glm::dot(v.normal[q], it->second.normal[q]) >= cosTolerance)
                continue;
            bool tie = false;
            if (it->second.tape) {
                std::uint32_t feature = 0;
                const glm::vec4 g = voxel::evaluateTileTapeGradient(it->second.tape, it->second.at[q], feature);
                tie = glm::dot(glm::normalize(glm::vec3(g.y, g.z, g.w)), it->second.normal[q]) >= cosTolerance;
            }
            if (tie)
                ++c.normalTies;
            else
                normalOff = true;
        }
        c.distanceOff += distanceOff;
        c.normalOff += normalOff;
    }
    // Every corner the GPU stored is its tile tape's value there, as the C++
    // port of the shaders' evaluator computes it: the GPU samples the right
    // points with the right tape, wherever the two voxelizers' evaluators
    // differ in the last bits. To within one step of the stored code: the
    // port and lavapipe agree bit for bit (TapeLanguagesTest), but NVIDIA's
    // compiler fuses multiplies and adds where C++ rounds each (on an H200:
    // 41 of 120,048 corners of the chair one step off, 573 of the stool). A
    // wrong point or a wrong tape moves a code by far more than one step.
    auto code = [&](float distance) {
        return int(std::int16_t(voxel::encodeDistanceFeature(distance, float(voxelMm), 0) & 0xFFFF));
    };
    for (const auto& [key, v] : b) {
        if (!v.tape) continue;
        for (std::size_t q = 0; q < 8; ++q) {
            ++c.gpuCorners;
            const float d = voxel::evaluateTileTape(v.tape, v.at[q]);
            c.gpuCornersNotItsTape += std::abs(code(d) - code(v.distance[q])) > 1;
        }
    }
    for (const auto& [key, v] : b)
        if (!a.contains(key)) {
            ++(hasCornerNearZero(v, hair) ? c.onlyOneSideNearZero : c.onlyOneSideElsewhere);
            c.tilesWithHairDifferences.insert(key.first);
        }
    return c;
}

void expectSameVoxels(const VoxelComparison& c)
{
    EXPECT_GT(c.cpu, 0u);
    EXPECT_EQ(c.onlyOneSideElsewhere, 0u) << "voxels populated on one side only, with no corner near the surface";
    // A corner on the surface to float precision may fall either way: the
    // CPU voxelizer evaluates its own simplified tapes, the GPU the tile's,
    // and they may differ in the last bit. Where a face lies on a lattice
    // plane that is a whole layer of voxels (the turned leg at 1.8 mm: 27 of
    // 45,295, each with a corner within a hair of 0).
    EXPECT_LE(c.onlyOneSideNearZero, c.cpu / 20 + 2);
    EXPECT_EQ(c.gpuCornersNotItsTape, 0u) << "of " << c.gpuCorners << " corners";
    EXPECT_LE(c.distanceOff, c.both / 1000 + 2) << "worst distance difference " << c.worstDistance << " mm";
    // Normals: a corner on a crease may take either face's gradient. On an
    // H200 a generated part at 0.75 mm had 6 of 392 voxels with a normal off
    // and no tie recognized (lavapipe: within the old bound of a 200th);
    // most likely faces whose values tie to the last bits, which NVIDIA's
    // fused multiply-adds decide otherwise than the C++ port of the tape.
    EXPECT_LE(c.normalOff, c.both / 50 + 2);
}

Tape sphereTape(double radius)
{
    return compileTape(Document::parse(R"({"format":"kerf","version":1,"root":{"id":"s","type":"sphere","radius":)" +
                                           std::to_string(radius) + "}}",
                                       "sphere.kerf"));
}

class GpuVoxelizerTest : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        try {
            context = std::make_unique<vk::Context>(vk::ContextOptions{.validation = true, .preferCpu = false});
            voxelizer = std::make_unique<vk::GpuVoxelizer>(*context);
        } catch (const vk::VulkanError& e) {
            skipReason = e.what();
        }
    }
    static void TearDownTestSuite()
    {
        voxelizer.reset();
        context.reset();
    }
    void SetUp() override
    {
        if (!context) GTEST_SKIP() << "no Vulkan device: " << skipReason;
    }
    void TearDown() override
    {
        if (!context) return;
        EXPECT_EQ(context->validationErrors(), 0)
            << (context->validationMessages().empty() ? std::string() : context->validationMessages().front());
    }

    // Builds `tape` on both sides and compares; returns the GPU's build.
    vk::GpuVoxels buildBoth(const Tape& tape, const GridLayout& layout, FlatVoxelBuffers& cpu,
                            const vk::GpuVoxelizeOptions& options = {}, vk::GpuVoxelizeReport* report = nullptr)
    {
        vk::GpuVoxelizeReport local;
        vk::GpuVoxelizeReport& r = report ? *report : local;
        std::optional<vk::GpuVoxels> gpu = voxelizer->build(tape, layout, options, &r);
        EXPECT_TRUE(gpu.has_value()) << r.whyNot;
        if (!gpu) return {};
        cpu = FlatVoxelBuffers::flatten(voxelize(tape, layout, {.levels = options.levels}));
        const FlatVoxelBuffers back = gpu->readBack(*context);
        const double voxelMm = layout.tileSize / std::pow(4.0, gpu->levels);
        const VoxelComparison c = compareVoxels(cpu, back, voxelMm);
        const std::string figures =
            "voxels: cpu " + std::to_string(c.cpu) + ", gpu " + std::to_string(c.gpu) + ", both " +
            std::to_string(c.both) + ", one side near zero " + std::to_string(c.onlyOneSideNearZero) +
            ", distances off " + std::to_string(c.distanceOff) + " (worst " + std::to_string(c.worstDistance) +
            " mm), normals off " + std::to_string(c.normalOff) + " (ties " + std::to_string(c.normalTies) +
            "); levels run again " + std::to_string(r.levelReruns);
        std::printf("%s; GPU corners not its tape's value %zu of %zu\n", figures.c_str(), c.gpuCornersNotItsTape,
                    c.gpuCorners);
        SCOPED_TRACE(figures);
        expectSameVoxels(c);
        EXPECT_EQ(gpu->populatedVoxels, c.gpu) << "every voxel written is reachable from its tile";
        // Tiles: the same ones empty, full and with surface, but where the
        // only voxels of a tile are ones populated on one side by a hair.
        std::size_t differentTiles = 0;
        for (std::size_t t = 0; t < cpu.tiles.size(); ++t) {
            const auto kind = [](std::uint32_t w) {
                return w == voxel::kEmptyTile ? 0 : w == voxel::kFullTile ? 1 : 2;
            };
            differentTiles +=
                kind(cpu.tiles[t]) != kind(back.tiles[t]) && !c.tilesWithHairDifferences.contains(long(t));
        }
        EXPECT_EQ(differentTiles, 0u);
        return std::move(*gpu);
    }

    static inline std::unique_ptr<vk::Context> context;
    static inline std::unique_ptr<vk::GpuVoxelizer> voxelizer;
    static inline std::string skipReason;
};

class EveryExampleOnTheGpu : public GpuVoxelizerTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(EveryExampleOnTheGpu, BuildsTheCpuVoxelsAndTracesTheSamePicture)
{
    const Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / (GetParam() + ".kerf"));
    const Tape tape = compileTape(doc);
    const double extent = std::max({tape.bounds().size().x, tape.bounds().size().y, tape.bounds().size().z});
    // Two depths: coarse, and four times finer (lavapipe runs the shaders on two cores).
    for (const double divisions : {100.0, 400.0}) {
        SCOPED_TRACE("feature size " + std::to_string(extent / divisions));
        const GridLayout layout = GridLayout::choose(tape.bounds(), extent / divisions);
        FlatVoxelBuffers cpu;
        const vk::GpuVoxels gpu = buildBoth(tape, layout, cpu);
        if (HasFailure()) return;
        vk::ComputeTracer tracer(*context);
        tracer.setVoxels(cpu);
        for (const TraceQuality quality : {TraceQuality::Voxels, TraceQuality::Exact})
            for (const char* view : {"iso", "right"}) {
                SCOPED_TRACE(std::string(view) + " view, " + std::string(traceQualityName(quality)));
                const Camera camera = Camera::standardView(tape.bounds(), view, 240, 180);
                const TraceImage fromCpu = tracer.trace(camera, nullptr, {}, quality);
                const TraceImage fromGpu = tracer.trace(camera, gpu.addresses(1), nullptr, {}, quality);
                std::size_t hitsDiffer = 0, depthOff = 0, hits = 0;
                for (std::size_t i = 0; i < fromCpu.depth.size(); ++i) {
                    hits += fromCpu.hit(i);
                    if (fromCpu.hit(i) != fromGpu.hit(i)) {
                        ++hitsDiffer;
                        continue;
                    }
                    if (fromCpu.hit(i) && std::fabs(fromCpu.depth[i] - fromGpu.depth[i]) > 0.01 * layout.voxelSize)
                        ++depthOff;
                }
                EXPECT_GT(hits, 400u);
                EXPECT_LE(hitsDiffer, fromCpu.depth.size() / 2000);
                EXPECT_LE(depthOff, hits / 500);
            }
    }
}

INSTANTIATE_TEST_SUITE_P(Examples, EveryExampleOnTheGpu,
                         ::testing::Values("side-chair", "bookshelf-side", "table-top", "stool", "door-frame",
                                           "turned-leg"));

TEST_F(GpuVoxelizerTest, GeneratedPartsAtSeveralFeatureSizes)
{
    test::RandomShapes r(20261125);
    for (int part = 0; part < 6; ++part) {
        const Tape tape = compileTape(test::RandomShapes::document(r.tree(3)));
        if (tape.bounds().isEmpty()) continue;
        for (const double feature : {2.0, 0.75, 0.3}) {
            SCOPED_TRACE("part " + std::to_string(part) + " at " + std::to_string(feature) + " mm");
            const GridLayout layout = GridLayout::choose(tape.bounds(), feature);
            FlatVoxelBuffers cpu;
            buildBoth(tape, layout, cpu);
            if (HasFailure()) return;
        }
    }
}

TEST_F(GpuVoxelizerTest, ALevelThatOutgrowsItsPoolsRunsAgainInLargerOnes)
{
    // Pools guessed a tenth of what a fresh voxelizer guesses (16 children
    // per node, room for all 64 where that is cheap, 18 voxels per leaf):
    // levels outgrow them and run again in pools of what they asked for.
    vk::GpuVoxelizer fresh(*context);
    const Tape tape = sphereTape(30);
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.25, {.maxTiles = 8});
    vk::GpuVoxelizeReport report;
    std::optional<vk::GpuVoxels> gpu = fresh.build(tape, layout, {.poolGuessScale = 0.1}, &report);
    ASSERT_TRUE(gpu) << report.whyNot;
    EXPECT_GT(report.levelReruns, 0) << "the first guess was meant to be too small here";
    const FlatVoxelBuffers cpu = FlatVoxelBuffers::flatten(voxelize(tape, layout));
    expectSameVoxels(compareVoxels(cpu, gpu->readBack(*context), layout.voxelSize));
    // The next build of the same part (an edit) sizes its pools from this one.
    std::optional<vk::GpuVoxels> second = fresh.build(tape, layout, {}, &report);
    ASSERT_TRUE(second);
    EXPECT_EQ(report.levelReruns, 0);
    // A build made in the pools of a recycled one is the same build.
    fresh.recycle(std::move(*gpu));
    std::optional<vk::GpuVoxels> third = fresh.build(tape, layout, {}, &report);
    ASSERT_TRUE(third);
    expectSameVoxels(compareVoxels(cpu, third->readBack(*context), layout.voxelSize));
    EXPECT_EQ(compareVoxels(second->readBack(*context), third->readBack(*context), layout.voxelSize).distanceOff, 0u);
}

TEST_F(GpuVoxelizerTest, ABudgetTooSmallIsRefusedInWords)
{
    const Tape tape = sphereTape(30);
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.5);
    vk::GpuVoxelizeReport report;
    EXPECT_FALSE(voxelizer->build(tape, layout, {.memoryBudget = 1 << 20}, &report));
    EXPECT_NE(report.whyNot.find("device memory"), std::string::npos) << report.whyNot;
    EXPECT_NE(report.whyNot.find("budget is 1 MB"), std::string::npos) << report.whyNot;
}

TEST_F(GpuVoxelizerTest, CoarserDepthsAndPartsFarFromTheOrigin)
{
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","children":[
        {"id":"b","type":"box","size":[18,120,300],"transform":{"translate":[100000,-50000,2000]}},
        {"id":"c","type":"cylinder","radius":6,"height":40,"transform":{"translate":[100009,-50000,2000]}}]}})",
                                         "far.kerf");
    const Tape tape = compileTape(doc);
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.5);
    for (const int levels : {1, 2, layout.levels}) {
        SCOPED_TRACE("levels " + std::to_string(levels));
        FlatVoxelBuffers cpu;
        buildBoth(tape, layout, cpu, {.levels = levels});
    }
}

TEST_F(GpuVoxelizerTest, PoolsLargerThanLavapipesStorageBufferRangeWork)
{
    // lavapipe caps a storage-buffer binding at 128 MiB; the voxelizer and
    // the tracer reach their pools by device address, where no such cap
    // applies. A sphere whose vertex pool alone is larger than that.
    const Tape tape = sphereTape(58);
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.1);
    vk::GpuVoxelizeReport report;
    std::optional<vk::GpuVoxels> gpu = voxelizer->build(tape, layout, {}, &report);
    ASSERT_TRUE(gpu) << report.whyNot;
    constexpr std::size_t kLavapipeRange = std::size_t(128) << 20;
    EXPECT_GT(gpu->vertices->size(), kLavapipeRange);
    EXPECT_GT(gpu->vertexCount * sizeof(voxel::Vertex), kLavapipeRange) << "the records in use, not only the pool";
    std::printf("%zu voxels, %zu vertices; device %.0f ms\n", gpu->populatedVoxels, gpu->vertexCount,
                report.deviceMilliseconds);
    // The same voxels as the CPU's (counted: the voxel-by-voxel comparison is
    // the other tests' business, and costs a minute at this size here). To
    // within a millionth: a voxel with a corner on the surface to the last
    // bit goes either way where the GPU's compiler fuses multiply-adds (an
    // H200: 6 of 6,340,652; lavapipe: none).
    const std::size_t cpuVoxels = voxelize(tape, layout).populatedVoxels();
    EXPECT_LE(std::max(gpu->populatedVoxels, cpuVoxels) - std::min(gpu->populatedVoxels, cpuVoxels), cpuVoxels / 1000000 + 2)
        << "GPU " << gpu->populatedVoxels << ", CPU " << cpuVoxels;
    // And the tracer reads them where they are: the sphere's silhouette and depth.
    vk::ComputeTracer tracer(*context);
    const Camera camera = Camera::standardView(tape.bounds(), "front", 160, 120);
    const TraceImage image = tracer.trace(camera, gpu->addresses(1));
    const TraceImage exact = traceExact(tape, camera, 1e-3);
    std::size_t hits = 0, agree = 0;
    for (std::size_t i = 0; i < image.depth.size(); ++i) {
        if (!exact.hit(i)) continue;
        ++hits;
        agree += image.hit(i) && std::fabs(image.depth[i] - exact.depth[i]) < 2.0 * layout.voxelSize;
    }
    EXPECT_GT(hits, 1000u);
    EXPECT_GE(double(agree), 0.995 * double(hits));
}

TEST_F(GpuVoxelizerTest, AnEditSequenceOnOneVoxelizerEqualsFreshBuilds)
{
    // One voxelizer through a sequence of edits, each build made in the pools
    // of the one before last (as the viewport will hand them back) and sized
    // from what it learned: every build holds exactly the voxels a fresh
    // voxelizer builds for that document (atomics order the records
    // differently from run to run; the voxels they describe do not change).
    const auto part = [](double holeX, double depth) {
        return compileTape(Document::parse(
            R"({"format":"kerf","version":1,"root":{"id":"d","type":"difference","children":[
                {"id":"b","type":"box","size":[120,80,)" +
                std::to_string(depth) + R"(]},
                {"id":"h","type":"cylinder","radius":4,"height":60,"transform":{"translate":[)" +
                std::to_string(holeX) + R"(,0,0]}}]}})",
            "edit.kerf"));
    };
    vk::GpuVoxelizer editing(*context);
    std::optional<vk::GpuVoxels> shown, before;
    const std::vector<std::pair<double, double>> edits{{0, 18}, {20, 18}, {20, 30}, {-35.5, 30}, {-35.5, 12}};
    for (const auto& [x, depth] : edits) {
        SCOPED_TRACE("hole at " + std::to_string(x) + ", depth " + std::to_string(depth));
        const Tape tape = part(x, depth);
        const GridLayout layout = GridLayout::choose(tape.bounds(), 1.0);
        if (before) editing.recycle(std::move(*before));
        before = std::move(shown);
        vk::GpuVoxelizeReport report;
        shown = editing.build(tape, layout, {}, &report);
        ASSERT_TRUE(shown) << report.whyNot;
        vk::GpuVoxelizer fresh(*context);
        const std::optional<vk::GpuVoxels> reference = fresh.build(tape, layout);
        ASSERT_TRUE(reference);
        const VoxelComparison c =
            compareVoxels(reference->readBack(*context), shown->readBack(*context), layout.voxelSize);
        EXPECT_GT(c.both, 1000u);
        EXPECT_EQ(c.onlyOneSideNearZero + c.onlyOneSideElsewhere, 0u);
        EXPECT_EQ(c.distanceOff, 0u);
        EXPECT_EQ(c.worstDistance, 0.0f);
        EXPECT_EQ(c.normalOff, 0u);
    }
}

// The benchmarks' switch: every tile on the whole tape instead of the tape
// simplified for its box. The same voxels (simplification only drops
// branches that cannot win there), longer tapes.
TEST_F(GpuVoxelizerTest, TheWholeTapeEverywhereBuildsTheSameVoxels)
{
    const Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf");
    const Tape tape = compileTape(doc);
    const GridLayout layout = GridLayout::choose(tape.bounds(), 2.0);
    vk::GpuVoxelizeReport simplified, whole;
    const std::optional<vk::GpuVoxels> a = voxelizer->build(tape, layout, {}, &simplified);
    const std::optional<vk::GpuVoxels> b = voxelizer->build(tape, layout, {.simplifyTileTapes = false}, &whole);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(whole.hostBuiltTiles, 0u) << "the chair's whole tape fits the shaders";
    EXPECT_GT(b->tapes.size(), 2 * a->tapes.size()) << "the whole tape is longer than the tiles' own";
    const VoxelComparison c = compareVoxels(a->readBack(*context), b->readBack(*context), layout.voxelSize);
    EXPECT_GT(c.both, 10000u);
    EXPECT_EQ(c.onlyOneSideNearZero + c.onlyOneSideElsewhere, 0u);
    EXPECT_EQ(c.distanceOff, 0u) << "worst " << c.worstDistance << " mm";
}

// The node tapes pruned on the device (voxelize.comp, "Tapes pruned per
// node"): most leaf nodes of the chair evaluate a pruned tape, and the
// voxels are the unpruned build's bit for bit (corner distances, normals
// and deciding features), on the chair and on generated parts with blends,
// differences and shells.
TEST_F(GpuVoxelizerTest, NodeTapesPrunedOnTheDeviceBuildTheSameVoxels)
{
    auto check = [&](const Tape& tape, double feature, const std::string& what) -> std::pair<std::size_t, std::size_t> {
        const GridLayout layout = GridLayout::choose(tape.bounds(), feature);
        vk::GpuVoxelizeReport pruned, whole;
        const std::optional<vk::GpuVoxels> a = voxelizer->build(tape, layout, {}, &pruned);
        const std::optional<vk::GpuVoxels> b = voxelizer->build(tape, layout, {.pruneNodeTapes = false}, &whole);
        if (!a || !b) {
            ADD_FAILURE() << what << ": " << pruned.whyNot << whole.whyNot;
            return {0, 0};
        }
        EXPECT_EQ(whole.prunedLeafJobs, 0u) << what;
        const FlatVoxelBuffers fa = a->readBack(*context), fb = b->readBack(*context);
        const VoxelComparison c = compareVoxels(fa, fb, layout.voxelSize);
        EXPECT_EQ(c.onlyOneSideNearZero + c.onlyOneSideElsewhere, 0u) << what;
        EXPECT_EQ(c.distanceOff, 0u) << what << ": worst " << c.worstDistance << " mm";
        EXPECT_EQ(c.normalOff, 0u) << what;
        // Bit for bit: the same vertex words (normal, distance and feature;
        // their order follows the atomics' claims, so compared sorted).
        EXPECT_EQ(a->populatedVoxels, b->populatedVoxels) << what;
        auto words = [](const FlatVoxelBuffers& f) {
            std::vector<std::uint64_t> w;
            for (const voxel::Vertex& v : f.vertices) w.push_back(std::uint64_t(v.normal) << 32 | v.distanceFeature);
            std::sort(w.begin(), w.end());
            return w;
        };
        EXPECT_TRUE(words(fa) == words(fb)) << what;
        return {pruned.prunedLeafJobs, pruned.levelJobs.empty() ? 0u : pruned.levelJobs.back()};
    };
    const Tape chair = compileTape(Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf"));
    const auto [prunedChair, leafJobs] = check(chair, 2.0, "side chair at 2 mm");
    EXPECT_GT(prunedChair * 4, leafJobs) << "a quarter of the chair's leaf nodes at least prune their tape";
    test::RandomShapes shapes(20261127);
    for (int i = 0; i < 6; ++i) {
        const Tape tape = compileTape(test::RandomShapes::document(shapes.tree(3)));
        if (tape.empty() || tape.bounds().isEmpty()) continue;
        const glm::dvec3 extent = tape.bounds().max - tape.bounds().min;
        check(tape, std::max({extent.x, extent.y, extent.z}) / 90.0, "generated part " + std::to_string(i));
    }
}

// An edit rebuilds only the tiles it reaches, appended to the pools of the
// build on screen: every update holds exactly the voxels of its document
// (as the CPU voxelizer builds them), and the build it started from still
// reads as it did (the frames on screen read it meanwhile).
TEST_F(GpuVoxelizerTest, AnEditRebuildsOnlyTheTilesItReachesIntoTheBuildOnScreen)
{
    const auto part = [](double holeX, double depth) {
        return Document::parse(R"({"format":"kerf","version":1,"root":{"id":"d","type":"difference","children":[
                {"id":"b","type":"box","size":[120,80,)" +
                                   std::to_string(depth) + R"(]},
                {"id":"h","type":"cylinder","radius":4,"height":60,"transform":{"translate":[)" +
                                   std::to_string(holeX) + R"(,0,0]}}]}})",
                               "update.kerf");
    };
    vk::GpuVoxelizer editing(*context);
    Document doc = part(0, 18);
    const GridLayout layout = GridLayout::choose(compileTape(doc).bounds(), 1.0, {.maxTiles = 512});
    std::optional<vk::GpuVoxels> shown = editing.build(compileTape(doc), layout);
    ASSERT_TRUE(shown);
    std::optional<vk::GpuVoxels> before;
    const std::vector<std::pair<double, double>> edits{{20, 18}, {-35.5, 18}, {-35.5, 18.5}, {10, 18.5}};
    for (const auto& [x, depth] : edits) {
        SCOPED_TRACE("hole at " + std::to_string(x) + ", depth " + std::to_string(depth));
        const Document next = part(x, depth);
        const Tape tape = compileTape(next);
        ASSERT_EQ(GridLayout::choose(tape.bounds(), 1.0, {.maxTiles = 512}), layout);
        const std::vector<long> dirty = tilesAnEditReaches(doc, next, layout);
        ASSERT_FALSE(dirty.empty());
        const FlatVoxelBuffers shownBefore = shown->readBack(*context);
        vk::GpuVoxelizeReport report;
        std::optional<vk::GpuVoxels> updated = editing.update(*shown, tape, dirty, {}, &report);
        ASSERT_TRUE(updated) << report.whyNot;
        if (4 * dirty.size() <= std::size_t(layout.tileCount())) {
            EXPECT_EQ(report.updatedTiles, dirty.size()) << "an update, not a whole build";
            EXPECT_EQ(updated->nodes, shown->nodes) << "in the same pools";
        }
        std::printf("%zu of %ld tiles rebuilt; nodes %zu -> %zu\n", dirty.size(), layout.tileCount(), shown->nodeCount,
                    updated->nodeCount);
        const FlatVoxelBuffers cpu = FlatVoxelBuffers::flatten(voxelize(tape, layout));
        const VoxelComparison c = compareVoxels(cpu, updated->readBack(*context), layout.voxelSize);
        expectSameVoxels(c);
        // The build it came from is untouched.
        const VoxelComparison same = compareVoxels(shownBefore, shown->readBack(*context), layout.voxelSize);
        EXPECT_EQ(same.both, same.cpu);
        EXPECT_EQ(same.onlyOneSideNearZero + same.onlyOneSideElsewhere + same.distanceOff + same.normalOff, 0u);
        if (before) editing.recycle(std::move(*before));
        before = std::move(shown);
        shown = std::move(updated);
        doc = next;
    }
}

// The viewport's background builder: a new part gets its preview, then full
// depth; an edit on the same grid goes straight to full depth (the build on
// screen stays until then); a request made during a build supersedes it;
// the results are the voxels a direct build makes; an empty part is an
// empty result; a refusal is said with its revision.
TEST_F(GpuVoxelizerTest, TheViewportsWorkerBuildsPreviewThenFullAndTheNewestRequestWins)
{
    std::mutex m;
    std::condition_variable changed;
    int signals = 0;
    vk::GpuVoxelWorker worker(*context, [&] {
        std::lock_guard lock(m);
        ++signals;
        changed.notify_all();
    });
    // Waits for the worker to go idle; returns every result it published meanwhile, oldest first.
    const auto results = [&] {
        std::vector<std::unique_ptr<vk::GpuVoxelResult>> out;
        for (;;) {
            {
                std::unique_lock lock(m);
                changed.wait_for(lock, std::chrono::milliseconds(50));
            }
            if (auto r = worker.take()) out.push_back(std::move(r));
            if (!worker.busy()) {
                if (auto r = worker.take()) out.push_back(std::move(r));
                return out;
            }
        }
    };
    const auto board = [](double holeX) {
        return Document::parse(R"({"format":"kerf","version":1,"root":{"id":"d","type":"difference","children":[
                {"id":"b","type":"box","size":[400,40,18]},
                {"id":"h","type":"cylinder","radius":4,"height":60,"transform":{"translate":[)" +
                                   std::to_string(holeX) + R"(,0,0]}}]}})",
                               "worker.kerf");
    };
    const Document firstDoc = board(0), movedDoc = board(12);
    const auto tape = std::make_shared<const Tape>(compileTape(firstDoc));
    const GridLimits fewTiles{.maxTiles = 64}; // deep tiles: a preview two levels up
    const GridLayout layout = GridLayout::choose(tape->bounds(), 0.5, fewTiles);
    ASSERT_GE(layout.levels, 3);

    worker.request(vk::GpuVoxelRequest::of(1, tape, layout, 2));
    auto first = results();
    // Taken as they come: the preview, then full depth (a slow poll may see only the second).
    ASSERT_FALSE(first.empty());
    const vk::GpuVoxelResult& full = *first.back();
    EXPECT_TRUE(full.complete);
    EXPECT_EQ(full.revision, 1u);
    EXPECT_EQ(full.voxels->levels, layout.levels);
    EXPECT_TRUE(worker.refusal().empty());
    ASSERT_TRUE(full.features);
    EXPECT_EQ(full.features->size(), tape->features().size());
    if (first.size() == 2) {
        EXPECT_FALSE(first.front()->complete);
        EXPECT_EQ(first.front()->voxels->levels, layout.levels - 2);
        EXPECT_LT(first.front()->version, full.version);
    }
    const FlatVoxelBuffers cpu = FlatVoxelBuffers::flatten(voxelize(*tape, layout));
    expectSameVoxels(compareVoxels(cpu, full.voxels->readBack(*context), layout.voxelSize));

    // An edit on the same grid: no preview, only the tiles it reaches, and the voxels of the new part.
    const auto deeper = std::make_shared<const Tape>(compileTape(movedDoc));
    ASSERT_EQ(GridLayout::choose(deeper->bounds(), 0.5, fewTiles), layout);
    worker.recycle(std::move(first.front()));
    vk::GpuVoxelRequest edit = vk::GpuVoxelRequest::of(2, deeper, layout, 2);
    edit.dirtyTiles = tilesAnEditReaches(firstDoc, movedDoc, layout);
    edit.dirtySince = 1;
    ASSERT_LT(4 * edit.dirtyTiles->size(), std::size_t(layout.tileCount()));
    worker.request(edit);
    auto second = results();
    ASSERT_EQ(second.size(), 1u) << "an edit of the part on screen has no preview";
    EXPECT_TRUE(second.front()->complete);
    EXPECT_EQ(second.front()->revision, 2u);
    EXPECT_EQ(second.front()->report.updatedTiles, edit.dirtyTiles->size()) << "only the edit's tiles";
    expectSameVoxels(compareVoxels(FlatVoxelBuffers::flatten(voxelize(*deeper, layout)),
                                   second.front()->voxels->readBack(*context), layout.voxelSize));
    worker.recycle(std::move(first.back()));

    // Dirty tiles against a request the worker never saw (the viewport skipped
    // one): not trusted, the part is built whole.
    vk::GpuVoxelRequest gap = vk::GpuVoxelRequest::of(3, tape, layout, 2);
    gap.dirtyTiles = edit.dirtyTiles;
    gap.dirtySince = 99;
    worker.request(gap);
    auto third = results();
    ASSERT_EQ(third.size(), 1u);
    EXPECT_EQ(third.front()->report.updatedTiles, 0u) << "a whole build";
    expectSameVoxels(compareVoxels(cpu, third.front()->voxels->readBack(*context), layout.voxelSize));

    // Back to the CPU's snapshots: the worker lets go of its device memory,
    // and builds again when asked.
    worker.cancel();
    worker.recycle(std::move(second.front()));
    worker.recycle(std::move(third.front()));

    // Requests one after the other, faster than builds: the last one is what stays.
    for (std::uint64_t revision = 4; revision <= 6; ++revision)
        worker.request(vk::GpuVoxelRequest::of(revision, revision % 2 ? tape : deeper, layout, 2));
    auto burst = results();
    ASSERT_FALSE(burst.empty());
    EXPECT_EQ(burst.back()->revision, 6u);
    EXPECT_TRUE(burst.back()->complete);
    for (std::size_t i = 1; i < burst.size(); ++i)
        EXPECT_LT(burst[i - 1]->version, burst[i]->version);

    // An empty part: an empty result at once.
    worker.request(vk::GpuVoxelRequest::of(7, std::make_shared<const Tape>(), GridLayout{}, 2));
    auto empty = results();
    ASSERT_EQ(empty.size(), 1u);
    EXPECT_EQ(empty.front()->voxels->surfaceTiles, 0u);
    EXPECT_EQ(empty.front()->voxels->addresses(1).tiles, 0u) << "the tracer draws nothing";

    // Beyond the memory budget: refused in words, with its revision, nothing published.
    vk::GpuVoxelRequest tooBig = vk::GpuVoxelRequest::of(8, tape, GridLayout::choose(tape->bounds(), 0.1), 0);
    tooBig.memoryBudget = 1 << 20;
    worker.request(tooBig);
    EXPECT_TRUE(results().empty());
    EXPECT_NE(worker.refusal().find("device memory"), std::string::npos) << worker.refusal();
    EXPECT_EQ(worker.refusedRevision(), 8u);
    std::lock_guard lock(m);
    EXPECT_GT(signals, 0);
}

} // namespace
} // namespace kerf

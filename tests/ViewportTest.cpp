// The Vulkan compute tracer (on lavapipe in CI) against the CPU reference
// tracer: same algorithm, so depth agrees within a small tolerance on nearly
// every pixel, there is no hole where the reference has surface, and the
// validation layers report no error.

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/viewport/BrickRenderer.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/HeapAllocator.hpp"
#include "kerf/viewport/SceneRenderer.hpp"
#include "kerf/tracer/ViewController.hpp"
#include "kerf/viewport/VoxelStreamer.hpp"
#include "kerf/viewport/VulkanError.hpp"
#include "kerf/voxelizer/BrickLeaves.hpp"
#include "kerf/voxelizer/Voxelizer.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "support/GpuImageComparison.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <filesystem>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

// Under AddressSanitizer, LeakSanitizer reports allocations made by
// llvmpipe's JIT-compiled pipelines (frames in an "unknown module", not
// Kerf's code), so leak detection is off in this binary only. Kerf's own
// Vulkan objects are RAII-owned, and the validation layer checks them.
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }

namespace kerf {
namespace {

class EveryExample : public VulkanTracer, public ::testing::WithParamInterface<std::string> {};

TEST_P(EveryExample, MatchesTheCpuReferenceTracer)
{
    const Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / (GetParam() + ".kerf"));
    const Tape tape = compileTape(doc);
    // Coarse enough to keep the test quick on lavapipe; the algorithm is the same at any size.
    const double extent = std::max({tape.bounds().size().x, tape.bounds().size().y, tape.bounds().size().z});
    const GridLayout layout = GridLayout::choose(tape.bounds(), extent / 400.0);
    const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(voxelize(tape, layout));
    ASSERT_FALSE(buffers.tapes.empty()) << "surface tiles carry their exact tapes";
    vk::ComputeTracer tracer(*context);
    tracer.setVoxels(buffers);
    // The GPU refines Exact's listed rays with as many lanes a ray as its
    // subgroups hold (8 on lavapipe, 32 on NVIDIA); the reference the same.
    const int lanes = tracer.refineLanes();
    const auto cpuQuality = [&](TraceQuality q) {
        return q == TraceQuality::Exact && lanes == 0 ? TraceQuality::ExactEverywhere : q;
    };
    // Every quality: the voxels alone, the hybrid refinement on every ray,
    // and where the check of the voxel hits asks for it (four passes on the GPU).
    for (const TraceQuality quality : {TraceQuality::Voxels, TraceQuality::ExactEverywhere, TraceQuality::Exact}) {
        SCOPED_TRACE(std::string(traceQualityName(quality)));
        for (const char* view : {"iso", "front", "top"}) {
            const Camera camera = Camera::standardView(tape.bounds(), view, 320, 240);
            const TraceImage gpu = tracer.trace(camera, nullptr, {}, quality);
            const TraceImage cpu = traceVoxels(buffers, camera, 0, {}, cpuQuality(quality), {}, lanes);
            // Float arithmetic may differ in the last bits between the compilers
            // (fused multiply-adds): allow a hundredth of a voxel in depth.
            const Comparison c = compare(gpu, cpu, 0.01 * layout.voxelSize + 1e-4 * extent);
            SCOPED_TRACE(std::string(view) + " view");
            EXPECT_GT(c.bothHit, 400u) << "the part should show (thin parts seen edge-on fill little of the image)";
            EXPECT_LE(c.holes, c.pixels / 1000) << "pixels where the reference has surface and the GPU none";
            EXPECT_LE(c.extra, c.pixels / 1000);
            EXPECT_GE(double(c.depthClose), 0.995 * double(c.bothHit));
            EXPECT_GE(double(c.normalClose), 0.99 * double(c.bothHit));
            EXPECT_GE(double(c.featureSame), 0.99 * double(c.bothHit));
        }
        // A section through the middle, seen from the cut side: caps and all.
        const Section section = Section::alongAxis(0, tape.bounds().center().x);
        const Camera camera = Camera::standardView(tape.bounds(), "right", 320, 240);
        const TraceImage gpu = tracer.trace(camera, nullptr, section, quality);
        const TraceImage cpu = traceVoxels(buffers, camera, 0, section, cpuQuality(quality), {}, lanes);
        const Comparison c = compare(gpu, cpu, 0.01 * layout.voxelSize + 1e-4 * extent);
        std::size_t caps = 0;
        for (std::uint32_t f : cpu.feature) caps += f == kSectionCap;
        EXPECT_GT(caps, 0u) << "the plane through the middle cuts the part";
        // A cap only where the plane's point is inside the part (within the
        // voxels' own departure): the door frame's rails, whose faces lie on
        // lattice planes, were capped where the ray came through the groove.
        PointEvaluator<double> points;
        std::size_t capsOutside = 0;
        for (std::size_t i = 0; i < gpu.depth.size(); ++i) {
            if (gpu.feature[i] != kSectionCap) continue;
            const Ray r = camera.ray(int(i % std::size_t(gpu.width)), int(i / std::size_t(gpu.width)));
            const glm::dvec3 p = r.origin + double(gpu.depth[i]) * r.direction;
            capsOutside += points.evaluate(tape, p.x, p.y, p.z) > 0.25 * layout.voxelSize;
        }
        EXPECT_EQ(capsOutside, 0u) << "of " << caps << " caps";
        EXPECT_LE(c.holes, c.pixels / 1000);
        EXPECT_LE(c.extra, c.pixels / 1000);
        EXPECT_GE(double(c.depthClose), 0.995 * double(c.bothHit));
        EXPECT_GE(double(c.featureSame), 0.99 * double(c.bothHit));
    }
    EXPECT_EQ(context->validationErrors(), 0) << (context->validationMessages().empty()
                                                      ? std::string()
                                                      : context->validationMessages().front());
}

INSTANTIATE_TEST_SUITE_P(Examples, EveryExample,
                         ::testing::Values("side-chair", "bookshelf-side", "table-top", "stool", "door-frame"));

TEST_F(VulkanTracer, OrthographicViewsAndPartsFarFromTheOrigin)
{
    // A sphere 100 m from the origin: the eye is made grid-relative in double,
    // so the GPU sees small numbers and hits where the reference does.
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"s","type":"sphere",
        "radius":20,"transform":{"translate":[100000,-50000,2000]}}})",
                                         "far.kerf");
    const Tape tape = compileTape(doc);
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.25);
    const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(voxelize(tape, layout));
    vk::ComputeTracer tracer(*context);
    tracer.setVoxels(buffers);
    const Camera camera = Camera::standardView(tape.bounds(), "front", 200, 200, Projection::Orthographic);
    const TraceImage gpu = tracer.trace(camera);
    const TraceImage cpu = traceVoxels(buffers, camera);
    const Comparison c = compare(gpu, cpu, 0.01);
    EXPECT_GT(c.bothHit, 10000u);
    EXPECT_EQ(c.holes, 0u);
    EXPECT_GE(double(c.depthClose), 0.995 * double(c.bothHit));
    // The centre pixel's ray hits the sphere's front at the analytic depth.
    const std::size_t centre = gpu.index(100, 100);
    const double eyeToCentre = glm::length(camera.eye() - glm::dvec3(100000, -50000, 2000));
    EXPECT_NEAR(gpu.depth[centre], eyeToCentre - 20.0, 0.3);
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

TEST_F(VulkanTracer, ReportsWhichDeviceItUses)
{
    // The validation layers are installed by tools/install-deps.sh: when
    // their manifest is there, they must be on, or "no error" means nothing.
    if (std::filesystem::exists("/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json")) {
        EXPECT_TRUE(context->validationEnabled());
    }
    EXPECT_FALSE(context->deviceDescription().empty());
    EXPECT_GT(context->properties().limits.timestampPeriod, 0.0f);
}

bool sameImage(const TraceImage& a, const TraceImage& b)
{
    return a.depth == b.depth && a.feature == b.feature;
}

TEST_F(VulkanTracer, StreamsUnderTheBudgetAndSwitchesOnlyWhenEveryTileIsResident)
{
    Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf");
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 0, .threads = 2, .featureSize = 2.0, .onPublish = {}});
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(60)));
    const auto a = vox.snapshot();
    doc.root.find("dowel-hole-r")->transform.translate.x += 6.0;
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(60)));
    const auto b = vox.snapshot();

    const Camera camera = Camera::standardView(a->layout.bounds(), "iso", 240, 180);
    vk::ComputeTracer tracer(*context);
    tracer.setVoxels(FlatVoxelBuffers::flatten(*a));
    const TraceImage imageA = tracer.trace(camera);
    const TraceImage exactA = tracer.trace(camera, nullptr, {}, TraceQuality::Exact);
    ASSERT_FALSE(sameImage(imageA, exactA)) << "the hybrid refinement should show";
    tracer.setVoxels(FlatVoxelBuffers::flatten(*b));
    const TraceImage imageB = tracer.trace(camera);
    ASSERT_FALSE(sameImage(imageA, imageB)) << "the edit should show";

    const std::size_t budget = 256 * 1024;
    vk::VoxelStreamer streamer(*context, {.budgetBytesPerFrame = budget, .framesInFlight = 2, .initialHeapBytes = 4u << 20});
    auto frame = [&] {
        vk::FrameUpload up;
        context->submitAndWait([&](VkCommandBuffer cb) { up = streamer.recordFrame(cb); });
        EXPECT_LE(up.bytes, budget) << "a frame uploaded more than its budget";
        return up;
    };

    // First snapshot: nothing visible until every tile is resident.
    streamer.setTarget(a);
    int frames = 0;
    std::size_t bytesA = 0;
    for (;;) {
        const vk::FrameUpload up = frame();
        bytesA += up.bytes;
        ++frames;
        if (up.switched) break;
        ASSERT_FALSE(streamer.resident().valid());
        ASSERT_LT(frames, 10000);
    }
    EXPECT_GT(frames, 10) << "the budget should spread the upload over many frames";
    EXPECT_TRUE(sameImage(tracer.trace(camera, streamer.resident()), imageA));
    // The tiles' exact tapes travel in their blobs: the hybrid sees the same tapes.
    EXPECT_TRUE(sameImage(tracer.trace(camera, streamer.resident(), nullptr, {}, TraceQuality::Exact), exactA));

    // The edit: only the changed tiles travel, and the old picture stays
    // until they are all there.
    streamer.setTarget(b);
    std::size_t bytesB = 0;
    for (int f = 0;; ++f) {
        const vk::FrameUpload up = frame();
        bytesB += up.bytes;
        if (up.switched) break;
        EXPECT_TRUE(sameImage(tracer.trace(camera, streamer.resident()), imageA)) << "frame " << f;
        ASSERT_LT(f, 10000);
    }
    EXPECT_TRUE(sameImage(tracer.trace(camera, streamer.resident()), imageB));
    EXPECT_LT(bytesB * 5, bytesA) << "an edit re-uploads only the tiles it changed";
    EXPECT_TRUE(streamer.upToDate());
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

// Streaming a snapshot that outgrows the voxel heap moves every tile into a
// larger one over many frames; until the switch the old heap must stay
// alive and untouched, because the resident set still reads it.
TEST_F(VulkanTracer, AnOutgrownHeapStaysReadableUntilTheSwitch)
{
    const Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / "stool.kerf");
    const Tape tape = compileTape(doc);
    auto snapshotAt = [&](double featureSize) {
        return std::make_shared<const VoxelSnapshot>(voxelize(tape, GridLayout::choose(tape.bounds(), featureSize)));
    };
    const auto coarse = snapshotAt(4.0), fine = snapshotAt(1.0);
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 160, 120);
    const TraceImage expected = traceVoxels(FlatVoxelBuffers::flatten(*coarse), camera);

    const std::size_t budget = 1u << 20;
    vk::VoxelStreamer streamer(*context, {.budgetBytesPerFrame = budget, .framesInFlight = 2, .initialHeapBytes = 1u << 20});
    vk::ComputeTracer tracer(*context);
    auto frame = [&] {
        vk::FrameUpload up;
        context->submitAndWait([&](VkCommandBuffer cb) { up = streamer.recordFrame(cb); });
        return up;
    };
    streamer.setTarget(coarse);
    for (int i = 0; i < 1000 && !frame().switched; ++i) {
    }
    ASSERT_TRUE(streamer.resident().valid());
    const std::size_t heapBefore = streamer.heapCapacity();
    streamer.setTarget(fine);
    ASSERT_GT(streamer.heapCapacity(), heapBefore) << "the fine snapshot should need a larger heap";
    int frames = 0;
    for (;; ++frames) {
        const vk::FrameUpload up = frame();
        if (up.switched) break;
        ASSERT_LT(frames, 10000);
        // Every frame until the switch still shows the coarse snapshot, intact.
        const TraceImage now = tracer.trace(camera, streamer.resident());
        const Comparison c = compare(now, expected, 1e-3 * glm::length(tape.bounds().size()));
        ASSERT_EQ(c.holes + c.extra, 0u) << "frame " << frames;
        ASSERT_EQ(c.depthClose, c.bothHit) << "frame " << frames;
    }
    EXPECT_GT(frames, 4) << "the upload should span more frames than are in flight";
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

// A target replaced before it became resident (an edit, or File > New,
// while the last version still streams) leaves tiles that nobody shows.
// Their placements must go with them: the streamer knows tiles by their
// address, and a tile made later at a freed tile's address was once taken
// for it (a box drawn with pieces of the chair open before New). Here
// every tile lives in storage the test owns, so the new part's tiles are
// made exactly where the abandoned part's were.
TEST_F(VulkanTracer, ATileMadeWhereAnAbandonedTileWasIsUploadedAsItself)
{
    struct Slot {
        alignas(TileData) unsigned char bytes[sizeof(TileData)];
        bool live = false;
    };
    std::vector<std::unique_ptr<Slot>> slots;
    // `from`'s tiles rebuilt in the test's slots: a free slot first, in order.
    const auto inSlots = [&](const VoxelSnapshot& from) {
        auto snap = std::make_shared<VoxelSnapshot>(from);
        std::size_t next = 0;
        for (auto& t : snap->tiles) {
            if (!t) continue;
            while (next < slots.size() && slots[next]->live) ++next;
            if (next == slots.size()) slots.push_back(std::make_unique<Slot>());
            Slot* slot = slots[next].get();
            slot->live = true;
            t = std::shared_ptr<const TileData>(new (slot->bytes) TileData(*t), [slot](const TileData* d) {
                d->~TileData();
                slot->live = false;
            });
        }
        return std::shared_ptr<const VoxelSnapshot>(std::move(snap));
    };
    const auto voxelsOf = [](const char* example, double featureSize) {
        const Tape tape = compileTape(Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / example));
        return voxelize(tape, GridLayout::choose(tape.bounds(), featureSize));
    };

    const std::size_t budget = 64 * 1024;
    vk::VoxelStreamer streamer(*context, {.budgetBytesPerFrame = budget, .framesInFlight = 2, .initialHeapBytes = 16u << 20});
    auto frame = [&] {
        vk::FrameUpload up;
        context->submitAndWait([&](VkCommandBuffer cb) { up = streamer.recordFrame(cb); });
        return up;
    };
    // The chair, some of it uploaded; then New: nothing to show for a moment.
    {
        auto chair = inSlots(voxelsOf("side-chair.kerf", 2.0));
        streamer.setTarget(chair);
        for (int i = 0; i < 8; ++i) ASSERT_FALSE(frame().switched);
    }
    streamer.setTarget(nullptr);
    ASSERT_TRUE(std::none_of(slots.begin(), slots.end(), [](const auto& s) { return s->live; }))
        << "the abandoned chair's tiles should be let go";
    // The stool, made in the chair's slots, streams as the stool.
    const VoxelSnapshot stoolVoxels = voxelsOf("stool.kerf", 2.0);
    auto stool = inSlots(stoolVoxels);
    streamer.setTarget(stool);
    for (int i = 0;; ++i) {
        if (frame().switched) break;
        ASSERT_LT(i, 100000);
    }
    const Camera camera = Camera::standardView(stool->layout.bounds(), "iso", 160, 120);
    vk::ComputeTracer tracer(*context);
    tracer.setVoxels(FlatVoxelBuffers::flatten(stoolVoxels));
    EXPECT_TRUE(sameImage(tracer.trace(camera, streamer.resident()), tracer.trace(camera)));
    // Once the frames in flight are done, the heap holds the stool alone.
    for (int i = 0; i < 4; ++i) frame();
    std::size_t stoolBytes = 0;
    for (const auto& t : stool->tiles)
        if (t && t->state == TileState::Surface) stoolBytes += t->bytes();
    EXPECT_LE(streamer.heapBytesInUse(), stoolBytes + stoolBytes / 4 + 64 * stool->tiles.size())
        << "the abandoned chair's heap ranges should be freed";
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
    stool.reset();
    streamer.setTarget(nullptr);
}

// An empty part (everything hidden) publishes a grid of no tiles: it
// streams and traces as nothing, with no zero-sized copy.
TEST_F(VulkanTracer, AnEmptyPartStreamsAsNothing)
{
    const Document doc = Document::parse(
        R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","children":[{"id":"s","type":"sphere","radius":5,"visible":false}]}})",
        "empty.kerf");
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 0, .threads = 2, .featureSize = 0.0, .onPublish = {}});
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(60)));
    vk::VoxelStreamer streamer(*context);
    streamer.setTarget(vox.snapshot());
    vk::FrameUpload up;
    context->submitAndWait([&](VkCommandBuffer cb) { up = streamer.recordFrame(cb); });
    EXPECT_TRUE(up.switched);
    vk::ComputeTracer tracer(*context);
    const TraceImage image = tracer.trace(Camera::standardView(Aabb{glm::dvec3(-10), glm::dvec3(10)}, "iso", 32, 24),
                                          streamer.resident());
    for (std::size_t i = 0; i < image.depth.size(); ++i) EXPECT_FALSE(image.hit(i));
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

TEST_F(VulkanTracer, ScenesLargerThanABindingStillTrace)
{
    // lavapipe caps a storage-buffer binding at 128 MiB; the tracer reaches
    // the heap by device address, so a larger scene works there too.
    const Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf");
    const Tape tape = compileTape(doc);
    auto snap = std::make_shared<VoxelSnapshot>(voxelize(tape, GridLayout::choose(tape.bounds(), 0.5)));
    snap->version = 1;
    ASSERT_GT(snap->bytes(), std::size_t(128) << 20);
    vk::VoxelStreamer streamer(*context, {.budgetBytesPerFrame = std::size_t(64) << 20, .framesInFlight = 2,
                                          .initialHeapBytes = std::size_t(16) << 20});
    streamer.setTarget(snap);
    for (int f = 0; f < 100 && !streamer.upToDate(); ++f)
        context->submitAndWait([&](VkCommandBuffer cb) { streamer.recordFrame(cb); });
    ASSERT_TRUE(streamer.upToDate());
    EXPECT_GT(streamer.heapCapacity(), std::size_t(128) << 20);
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 160, 120);
    vk::ComputeTracer tracer(*context);
    const TraceImage gpu = tracer.trace(camera, streamer.resident());
    const TraceImage cpu = traceVoxels(FlatVoxelBuffers::flatten(*snap), camera);
    const Comparison c = compare(gpu, cpu, 0.01);
    EXPECT_GT(c.bothHit, 1000u);
    EXPECT_LE(c.holes, c.pixels / 1000);
    EXPECT_GE(double(c.depthClose), 0.995 * double(c.bothHit));
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

// A rod (a long box as an OFF mesh) through a red cube, seen from the front.
std::filesystem::path writeRod(const std::filesystem::path& dir, double y)
{
    std::filesystem::create_directories(dir);
    const auto file = dir / "rod.off";
    std::ofstream out(file);
    out << "OFF\n8 12 0\n";
    for (int c = 0; c < 8; ++c)
        out << (c & 1 ? 60 : -60) << " " << y + (c & 2 ? 3 : -3) << " " << (c & 4 ? 3 : -3) << "\n";
    const int faces[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                              {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    for (const auto& f : faces) out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
    return file;
}

TEST_F(VulkanTracer, MeshesAndThePartHideEachOtherByDepth)
{
    const auto dir = std::filesystem::temp_directory_path() / ("kerf-mesh-" + std::to_string(::getpid()));
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"cube","type":"box",
        "size":[40,40,40],"color":"#ff0000"}})", "cube.kerf");
    const Tape tape = compileTape(doc);
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.5);
    const FlatVoxelBuffers voxels = FlatVoxelBuffers::flatten(voxelize(tape, layout));
    vk::ComputeTracer tracer(*context);
    tracer.setVoxels(voxels);
    vk::BrickRenderer bricks(*context);
    bricks.setBricks(BrickLeaves::fromVoxels(voxels));
    // Front view, orthographic, framing x in [-80, 80].
    const Camera camera = Camera::orthographic({0, -200, 0}, {0, 0, 0}, {0, 0, 1}, 120.0, 320, 240);
    auto pixelOf = [&](double x, double z) {
        return std::pair<int, int>(int((x / 60.0 * 0.5 * (240.0 / 320.0) + 0.5) * 320.0 + 0.5 * 0),
                                   int((0.5 - z / 120.0) * 240.0));
    };
    auto colourAt = [&](const RgbaImage& img, double x, double z) {
        const auto [px, py] = pixelOf(x, z);
        const std::uint8_t* p = &img.pixels[(std::size_t(py) * std::size_t(img.width) + std::size_t(px)) * 4];
        return glm::ivec3(p[0], p[1], p[2]);
    };
    auto isBlue = [](glm::ivec3 c) { return c.b > c.r + 30; };
    auto isRed = [](glm::ivec3 c) { return c.r > c.b + 30; };

    // Either renderer of the part: the compute tracer or the brick renderer.
    for (const bool withBricks : {false, true}) {
        SCOPED_TRACE(withBricks ? "brick renderer" : "compute tracer");
        vk::SceneRenderer renderer(*context);
        auto draw = [&](vk::SceneRenderer& r) {
            return withBricks ? r.render(bricks, camera, tape.features())
                              : r.render(tracer, tracer.voxels(), camera, tape.features());
        };
        PlacedMesh rod;
        rod.id = "rod";
        rod.color = {0.0f, 0.05f, 1.0f};
        // Through the cube's middle: hidden inside it, visible on both sides.
        rod.mesh = loadTriangleMesh(writeRod(dir, 0.0));
        renderer.setMeshes({rod});
        const RgbaImage through = draw(renderer);
        EXPECT_TRUE(isRed(colourAt(through, 0, 0))) << "the cube hides the rod inside it";
        EXPECT_TRUE(isBlue(colourAt(through, 45, 0))) << "the rod shows beside the cube";
        EXPECT_TRUE(isBlue(colourAt(through, -45, 0)));
        EXPECT_TRUE(isRed(colourAt(through, 10, 12)));
        // In front of the cube (y = -30, the cube's front face is y = -20): the rod hides the cube.
        rod.mesh = loadTriangleMesh(writeRod(dir, -30.0));
        renderer.setMeshes({rod});
        const RgbaImage front = draw(renderer);
        EXPECT_TRUE(isBlue(colourAt(front, 0, 0))) << "the rod in front hides the cube";
        EXPECT_TRUE(isRed(colourAt(front, 10, 12)));
        // Behind it: hidden where the cube is.
        rod.mesh = loadTriangleMesh(writeRod(dir, 30.0));
        renderer.setMeshes({rod});
        const RgbaImage behind = draw(renderer);
        EXPECT_TRUE(isRed(colourAt(behind, 0, 0)));
        EXPECT_TRUE(isBlue(colourAt(behind, 45, 0)));
    }
    std::filesystem::remove_all(dir);
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

TEST_F(VulkanTracer, TracesOnlyWhenTheViewOrTheVoxelsChange)
{
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"s","type":"sphere","radius":10}})",
                                         "s.kerf");
    const Tape tape = compileTape(doc);
    vk::ComputeTracer tracer(*context);
    tracer.setVoxels(FlatVoxelBuffers::flatten(voxelize(tape, GridLayout::choose(tape.bounds(), 0.5))));
    vk::SceneRenderer renderer(*context);
    const Camera a = Camera::standardView(tape.bounds(), "iso", 160, 120);
    const RgbaImage first = renderer.render(tracer, tracer.voxels(), a, tape.features());
    EXPECT_TRUE(renderer.lastFrameTraced());
    // Same view and voxels: shading only, and the same picture.
    const RgbaImage again = renderer.render(tracer, tracer.voxels(), a, tape.features());
    EXPECT_FALSE(renderer.lastFrameTraced());
    EXPECT_EQ(first.pixels, again.pixels);
    // Another view, another size, new voxels: traced again.
    renderer.render(tracer, tracer.voxels(), Camera::standardView(tape.bounds(), "top", 160, 120), tape.features());
    EXPECT_TRUE(renderer.lastFrameTraced());
    renderer.render(tracer, tracer.voxels(), Camera::standardView(tape.bounds(), "top", 200, 120), tape.features());
    EXPECT_TRUE(renderer.lastFrameTraced());
    tracer.setVoxels(FlatVoxelBuffers::flatten(voxelize(tape, GridLayout::choose(tape.bounds(), 1.0))));
    renderer.render(tracer, tracer.voxels(), Camera::standardView(tape.bounds(), "top", 200, 120), tape.features());
    EXPECT_TRUE(renderer.lastFrameTraced());
    // The quality switch: traced again.
    vk::SceneOptions exact;
    exact.quality = TraceQuality::Exact;
    renderer.render(tracer, tracer.voxels(), Camera::standardView(tape.bounds(), "top", 200, 120), tape.features(),
                    exact);
    EXPECT_TRUE(renderer.lastFrameTraced());
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

TEST_F(VulkanTracer, TheGridShowsUnderAnEmptyPart)
{
    // A new part (nothing in it yet) shows the ground grid as the viewport
    // frames it (ViewportWidget: the view of a 200 mm box round the origin).
    // A newcomer met a blank gradient: the empty part's grid of no tiles had
    // a box of no size at its origin, and the ground grid was sized by it.
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","children":[]}})",
                                         "new.kerf");
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 0, .threads = 2, .featureSize = 0.0, .onPublish = {}});
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(60)));
    vk::VoxelStreamer streamer(*context);
    streamer.setTarget(vox.snapshot());
    context->submitAndWait([&](VkCommandBuffer cb) { streamer.recordFrame(cb); });
    const vk::VoxelAddresses nothing = vk::VoxelAddresses::of(streamer.resident());
    vk::ComputeTracer tracer(*context);
    vk::SceneRenderer renderer(*context);
    ViewController view;
    view.setStandardView("iso", Aabb{glm::dvec3(-100), glm::dvec3(100)}, 320.0 / 240.0);
    const Camera camera = view.camera(320, 240, streamer.resident().layout.bounds());
    vk::SceneOptions options;
    options.lights = ShadeOptions::forCamera(camera);
    const RgbaImage bare = renderer.render(tracer, nothing, camera, {}, options);
    options.grid = true;
    const RgbaImage grid = renderer.render(tracer, nothing, camera, {}, options);
    std::size_t differ = 0;
    for (std::size_t i = 0; i + 3 < grid.pixels.size(); i += 4)
        differ += std::abs(int(grid.pixels[i]) - int(bare.pixels[i])) > 8;
    EXPECT_GT(differ, std::size_t(320 * 240 / 100)) << "the grid's lines cover some of the picture";
    EXPECT_TRUE(streamer.resident().layout.bounds().isEmpty());
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

TEST(ReferenceMesh, MissingAndBrokenFilesAreNamedAndLeftOut)
{
    const auto dir = std::filesystem::temp_directory_path() / ("kerf-meshref-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "broken.stl") << "this is not a mesh";
    writeRod(dir, 0.0);
    // A named pipe named like a mesh: reading it waited for a writer for
    // ever (the application hung at open).
    ASSERT_EQ(::mkfifo((dir / "pipe.stl").c_str(), 0600), 0);
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"s","type":"sphere","radius":5},
        "meshes":[{"id":"gone","path":"missing.stl"},{"id":"bad","path":"broken.stl"},{"id":"ok","path":"rod.off"},
                  {"id":"pipe","path":"pipe.stl"}]})",
                                         "with-meshes.kerf");
    std::vector<std::string> problems;
    const auto meshes = loadReferenceMeshes(doc, dir, problems);
    ASSERT_EQ(meshes.size(), 1u);
    EXPECT_EQ(meshes[0].id, "ok");
    EXPECT_EQ(meshes[0].mesh.triangles(), 12u);
    ASSERT_EQ(problems.size(), 3u);
    EXPECT_NE(problems[0].find("mesh 'gone'"), std::string::npos);
    EXPECT_NE(problems[0].find("no such file"), std::string::npos);
    EXPECT_NE(problems[1].find("mesh 'bad'"), std::string::npos);
    EXPECT_NE(problems[2].find("mesh 'pipe'"), std::string::npos);
    EXPECT_NE(problems[2].find("is a named pipe (FIFO), not a mesh file"), std::string::npos) << problems[2];
    std::filesystem::remove_all(dir);
}

TEST(HeapAllocator, FirstFitMergesFreedNeighbours)
{
    vk::HeapAllocator h(240, 24);
    const auto a = h.allocate(30), b = h.allocate(24), c = h.allocate(100);
    ASSERT_TRUE(a && b && c);
    EXPECT_EQ(*a, 0u);
    EXPECT_EQ(*b, 48u);
    EXPECT_EQ(*c, 72u);
    EXPECT_FALSE(h.allocate(100).has_value());
    h.release(*b, 24);
    h.release(*a, 30);
    EXPECT_EQ(h.largestFree(), 72u); // a and b merged
    h.release(*c, 100);
    EXPECT_EQ(h.largestFree(), 240u);
    EXPECT_EQ(h.used(), 0u);
    EXPECT_THROW(h.release(0, 24), std::logic_error);  // already free
    EXPECT_THROW(h.release(48, 24), std::logic_error); // inside a free range
    const auto d = h.allocate(24);
    ASSERT_TRUE(d);
    h.release(*d, 24);
    EXPECT_THROW(h.release(*d, 24), std::logic_error); // twice
}

} // namespace
} // namespace kerf

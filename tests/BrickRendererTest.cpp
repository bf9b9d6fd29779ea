// The brick renderer (on lavapipe in CI) against the CPU reference tracer on
// the same voxels: the bricks hold the contree's samples and the texture
// unit interpolates them trilinearly, so the picture is the voxels' picture
// up to the filter's fixed-point weights and the march's sampling.

#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/tracer/Section.hpp"
#include "kerf/viewport/BrickAtlas.hpp"
#include "kerf/viewport/BrickRenderer.hpp"
#include "kerf/voxelizer/BrickLeaves.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "support/GpuImageComparison.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <future>

namespace kerf {
namespace {

class BrickRendererOnEveryExample : public VulkanTracer, public ::testing::WithParamInterface<std::string> {};

TEST_P(BrickRendererOnEveryExample, MatchesTheCpuReferenceTracer)
{
    const Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / (GetParam() + ".kerf"));
    const Tape tape = compileTape(doc);
    const double extent = std::max({tape.bounds().size().x, tape.bounds().size().y, tape.bounds().size().z});
    const GridLayout layout = GridLayout::choose(tape.bounds(), extent / 400.0);
    const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(voxelize(tape, layout));
    const BrickLeaves bricks = BrickLeaves::fromVoxels(buffers);
    vk::BrickRenderer renderer(*context);
    renderer.setBricks(bricks);
    ASSERT_EQ(renderer.brickCount(), bricks.bricks.size());
    for (const Projection projection : {Projection::Perspective, Projection::Orthographic})
        for (const char* view : {"iso", "front", "top", "right"}) {
            const Camera camera = Camera::standardView(tape.bounds(), view, 320, 240, projection);
            const TraceImage gpu = renderer.render(camera);
            const TraceImage cpu = traceVoxels(buffers, camera, 0, {}, TraceQuality::Voxels);
            // The texture unit weighs the eight samples with a fixed-point
            // fraction (8 bits on most hardware): a hit moves by up to about
            // a hundredth of a voxel, more where the ray grazes the surface.
            const Comparison c = compare(gpu, cpu, 0.05 * layout.voxelSize + 1e-4 * extent);
            SCOPED_TRACE(std::string(view) + (projection == Projection::Orthographic ? " orthographic" : " perspective"));
            std::printf("%s %s%s: %zu hit, holes %zu, extra %zu, depth off %zu, normal off %zu, feature off %zu\n",
                        GetParam().c_str(), view, projection == Projection::Orthographic ? " ortho" : "", c.bothHit,
                        c.holes, c.extra, c.bothHit - c.depthClose, c.bothHit - c.normalClose,
                        c.bothHit - c.featureSame);
            EXPECT_GT(c.bothHit, 400u);
            EXPECT_LE(c.holes, c.pixels / 1000) << "pixels where the reference has surface and the bricks none";
            EXPECT_LE(c.extra, c.pixels / 1000);
            EXPECT_GE(double(c.depthClose), 0.995 * double(c.bothHit));
            EXPECT_GE(double(c.normalClose), 0.99 * double(c.bothHit));
            // The feature is the nearest sample's. In a parallel view along an
            // axis a column of pixel centres can lie exactly halfway between
            // two lattice planes whose samples carry different features, and
            // which is nearer is the last bit of the hit's position: the
            // bookshelf side from the right, at y = 71.5 voxels, 227 of 8,365
            // pixels at the same depth on lavapipe, 252 on an H200.
            EXPECT_GE(double(c.featureSame), 0.95 * double(c.bothHit));
        }
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

// Section planes through the middle of the part along each axis, cutting
// either way: the bricks cut as the CPU reference tracer cuts, the caps
// (kSectionCap, the plane's normal, on the plane) where it has them. Each
// plane passes through full tiles and full nodes, which have no bricks: the
// cap there comes from the first brick the ray enters beyond the plane.
TEST_P(BrickRendererOnEveryExample, CutsSectionsAsTheCpuReferenceTracer)
{
    const Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / (GetParam() + ".kerf"));
    const Tape tape = compileTape(doc);
    const Aabb box = tape.bounds();
    const double extent = std::max({box.size().x, box.size().y, box.size().z});
    const GridLayout layout = GridLayout::choose(box, extent / 400.0);
    const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(voxelize(tape, layout));
    vk::BrickRenderer renderer(*context);
    renderer.setBricks(BrickLeaves::fromVoxels(buffers));
    std::size_t capsSeen = 0;
    int capsViews = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (const bool flip : {false, true})
            for (const bool onLattice : {false, true}) {
                // Near the middle: a third of a voxel off the lattice, or on a lattice plane.
                const double middle = 0.5 * (box.min[axis] + box.max[axis]);
                const double lattice = layout.origin[axis] +
                                       std::round((middle - layout.origin[axis]) / layout.voxelSize) * layout.voxelSize;
                const double at = onLattice ? lattice : lattice + layout.voxelSize / 3.0;
                const Section section = Section::alongAxis(axis, at, flip);
                // An oblique view from the side cut away, so that the cap faces the eye.
                glm::dvec3 away(1.0, -1.0, 1.0);
                away[axis] = section.normal[axis];
                const glm::dvec3 centre = 0.5 * (box.min + box.max), eye = centre + 2.5 * extent * glm::normalize(away);
                for (const Projection projection : {Projection::Perspective, Projection::Orthographic}) {
                    const Camera camera =
                        projection == Projection::Perspective
                            ? Camera::perspective(eye, centre, {0.0, 0.0, 1.0}, 30.0, 320, 240)
                            : Camera::orthographic(eye, centre, {0.0, 0.0, 1.0}, 1.5 * extent, 320, 240);
                    const TraceImage gpu = renderer.render(camera, nullptr, section);
                    const TraceImage cpu = traceVoxels(buffers, camera, 0, section, TraceQuality::Voxels);
                    const Comparison c = compare(gpu, cpu, 0.05 * layout.voxelSize + 1e-4 * extent);
                    std::size_t capsCpu = 0, capsGpu = 0, capsBoth = 0, capsOnPlane = 0;
                    for (std::size_t i = 0; i < cpu.depth.size(); ++i) {
                        if (cpu.hit(i) && cpu.feature[i] == kSectionCap) ++capsCpu;
                        if (!(gpu.hit(i) && gpu.feature[i] == kSectionCap)) continue;
                        ++capsGpu;
                        capsBoth += cpu.hit(i) && cpu.feature[i] == kSectionCap;
                        const Ray r =
                            camera.ray(int(i % std::size_t(camera.width())), int(i / std::size_t(camera.width())));
                        const glm::dvec3 p = r.origin + double(gpu.depth[i]) * r.direction;
                        capsOnPlane += std::fabs(glm::dot(p, section.normal) - section.offset) < 1e-3 * extent &&
                                       glm::length(glm::dvec3(gpu.normal[i]) - section.normal) < 1e-6;
                    }
                    capsSeen += capsCpu;
                    capsViews += capsCpu > 50;
                    SCOPED_TRACE(GetParam() + " axis " + std::to_string(axis) + (flip ? " flipped" : "") +
                                 (onLattice ? " on the lattice" : "") +
                                 (projection == Projection::Orthographic ? " orthographic" : " perspective"));
                    std::printf(
                        "%s axis %d%s%s%s: %zu hit, holes %zu, extra %zu, depth off %zu, normal off %zu, feature off "
                        "%zu, caps %zu (bricks %zu, both %zu, on the plane %zu)\n",
                        GetParam().c_str(), axis, flip ? " flipped" : "", onLattice ? " on the lattice" : "",
                        projection == Projection::Orthographic ? " ortho" : "", c.bothHit, c.holes, c.extra,
                        c.bothHit - c.depthClose, c.bothHit - c.normalClose, c.bothHit - c.featureSame, capsCpu, capsGpu,
                        capsBoth, capsOnPlane);
                    EXPECT_LE(c.holes, c.pixels / 1000) << "pixels where the reference has surface and the bricks none";
                    EXPECT_LE(c.extra, c.pixels / 1000);
                    EXPECT_GE(double(c.depthClose), 0.995 * double(c.bothHit));
                    EXPECT_GE(double(c.normalClose), 0.99 * double(c.bothHit));
                    EXPECT_GE(double(c.featureSame), 0.95 * double(c.bothHit));
                    EXPECT_GE(double(capsBoth), 0.99 * double(capsCpu)) << "caps the bricks left out";
                    EXPECT_EQ(capsOnPlane, capsGpu) << "caps off the plane or with another normal";
                    // The texture unit's fixed-point weights move a silhouette
                    // by a pixel here and there (on an H200 up to 3 more cap
                    // pixels than the reference in a view; none on lavapipe).
                    EXPECT_LE(capsGpu - capsBoth, capsCpu / 100 + 5) << "caps where the reference has none";
                }
            }
    EXPECT_GT(capsSeen, 1000u) << "planes through the middle of a part cut it somewhere";
    EXPECT_GT(capsViews, 7) << "the caps of at least two planes, seen from both sides";
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

// A camera close enough to the surface to be inside a brick (zoomed in on a
// face): the brick must still draw its surface (the renderer draws the
// cubes' far faces, which are in front of such an eye).
TEST_F(VulkanTracer, BricksDrawTheSurfaceOfTheBrickTheEyeIsIn)
{
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"cube","type":"box",
        "size":[41.4,41.4,41.4]}})", "cube.kerf");
    const Tape tape = compileTape(doc);
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.5);
    const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(voxelize(tape, layout));
    vk::BrickRenderer renderer(*context);
    renderer.setBricks(BrickLeaves::fromVoxels(buffers));
    // 0.2 mm in front of the cube's front face (y = -20.7), looking at it
    // and a little across: the bricks there span y from -24 to -20 mm, so
    // the eye is in the one that holds the face.
    for (const Projection projection : {Projection::Perspective, Projection::Orthographic}) {
        SCOPED_TRACE(projection == Projection::Orthographic ? "orthographic" : "perspective");
        const Camera camera = projection == Projection::Perspective
                                  ? Camera::perspective({1.3, -20.9, 0.9}, {3, 0, 2}, {0, 0, 1}, 60.0, 160, 120)
                                  : Camera::orthographic({1.3, -20.9, 0.9}, {1.3, 0, 0.9}, {0, 0, 1}, 6.0, 160, 120);
        const TraceImage gpu = renderer.render(camera);
        const TraceImage cpu = traceVoxels(buffers, camera, 0, {}, TraceQuality::Voxels);
        const Comparison c = compare(gpu, cpu, 0.05 * layout.voxelSize);
        EXPECT_EQ(c.holes, 0u);
        EXPECT_EQ(c.extra, 0u);
        EXPECT_GE(double(c.depthClose), 0.995 * double(c.bothHit));
        EXPECT_GT(c.bothHit, 15000u) << "the face fills the picture";
    }
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

// The upload in pieces (a viewport's frames, each within its upload
// budget): until the last row is on the device the bricks drawn before are
// drawn, exactly; after it, the new bricks, exactly as an upload in one
// piece draws them. A budget smaller than one row copies nothing unless a
// row is asked for.
TEST_F(VulkanTracer, BricksUploadedInPiecesDrawTheOldBricksUntilTheLastPiece)
{
    auto bricksOf = [](const char* json) {
        const Tape tape = compileTape(Document::parse(json, "part.kerf"));
        return BrickLeaves::fromVoxels(FlatVoxelBuffers::flatten(voxelize(tape, GridLayout::choose(tape.bounds(), 0.5))));
    };
    const BrickLeaves before = bricksOf(R"({"format":"kerf","version":1,"root":{"id":"cube","type":"box",
        "size":[30,30,30]}})");
    const BrickLeaves after = bricksOf(R"({"format":"kerf","version":1,"root":{"id":"ball","type":"sphere",
        "radius":16}})");
    const Camera camera = Camera::standardView(Aabb{{-17, -17, -17}, {17, 17, 17}}, "iso", 160, 120,
                                               Projection::Perspective);
    vk::BrickRenderer whole(*context);
    whole.setBricks(after);
    const TraceImage expected = whole.render(camera);

    vk::BrickRenderer pieces(*context);
    pieces.setBricks(before);
    const TraceImage old = pieces.render(camera);
    const vk::BrickAtlas atlas = vk::BrickAtlas::pack(after, pieces.maxImageDimension3D());
    const std::size_t rows = atlas.rows(), rowBytes = atlas.rowBytes();
    ASSERT_GT(rows, 20u);
    const std::size_t budget = (rows / 7) * rowBytes + rowBytes / 2; // rows/7 whole rows fit
    pieces.stage(after.bricks, atlas);
    EXPECT_TRUE(pieces.uploading());

    vk::BrickUpload tiny;
    context->submitAndWait([&](VkCommandBuffer cb) { tiny = pieces.recordUpload(cb, rowBytes - 1); });
    EXPECT_EQ(tiny.bytes, 0u);
    EXPECT_EQ(tiny.rowsLeft, rows);
    context->submitAndWait([&](VkCommandBuffer cb) { tiny = pieces.recordUpload(cb, rowBytes - 1, true); });
    EXPECT_EQ(tiny.bytes, rowBytes) << "one row when asked for, over the budget";

    int frames = 0;
    for (bool completed = false; !completed;) {
        vk::BrickUpload up;
        context->submitAndWait([&](VkCommandBuffer cb) { up = pieces.recordUpload(cb, budget); });
        ++frames;
        ASSERT_LE(frames, 10);
        EXPECT_LE(up.bytes, budget);
        EXPECT_GT(up.bytes, 0u);
        completed = up.completed;
        EXPECT_EQ(pieces.uploading(), !completed);
        const TraceImage drawn = pieces.render(camera);
        if (!completed) {
            EXPECT_EQ(pieces.brickCount(), before.bricks.size());
            EXPECT_EQ(drawn.depth, old.depth) << "frame " << frames << ": the old bricks, untouched";
            EXPECT_EQ(up.rowsLeft, rows - 1 - std::size_t(frames) * (rows / 7));
        } else {
            EXPECT_EQ(up.rowsLeft, 0u);
            EXPECT_EQ(pieces.brickCount(), after.bricks.size());
            EXPECT_EQ(drawn.depth, expected.depth) << "the new bricks, as uploaded whole";
            EXPECT_EQ(drawn.feature, expected.feature);
        }
    }
    EXPECT_EQ(frames, int((rows - 1 + rows / 7 - 1) / (rows / 7)));
    EXPECT_NE(old.depth, expected.depth) << "the two parts must look different for this test to say anything";
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

// Bricks prepared on another thread (as the viewport's brick-making task
// does) go up in rows within the budget they were prepared for without a
// frame allocating device memory, and draw as an upload in one piece does;
// unprepared, the frames allocate it (what the count says).
TEST_F(VulkanTracer, PreparedBricksGoUpWithoutAFrameAllocating)
{
    const Tape tape = compileTape(Document::parse(R"({"format":"kerf","version":1,"root":{"id":"ball",
        "type":"sphere","radius":16}})", "part.kerf"));
    const BrickLeaves leaves =
        BrickLeaves::fromVoxels(FlatVoxelBuffers::flatten(voxelize(tape, GridLayout::choose(tape.bounds(), 0.5))));
    const Camera camera = Camera::standardView(Aabb{{-17, -17, -17}, {17, 17, 17}}, "iso", 160, 120,
                                               Projection::Perspective);
    vk::BrickRenderer whole(*context);
    whole.setBricks(leaves);
    const TraceImage expected = whole.render(camera);

    for (const bool prepared : {true, false}) {
        SCOPED_TRACE(prepared ? "prepared" : "staged as they are");
        vk::BrickRenderer renderer(*context);
        vk::BrickAtlas atlas = vk::BrickAtlas::pack(leaves, renderer.maxImageDimension3D());
        const std::size_t rows = atlas.rows(), rowBytes = atlas.rowBytes();
        ASSERT_GT(rows, 20u);
        const std::size_t budget = (rows / 5) * rowBytes;
        if (prepared) {
            vk::PreparedBricks made = std::async(std::launch::async, [&] {
                                          return vk::BrickRenderer::prepare(*context, leaves.bricks, std::move(atlas),
                                                                            budget);
                                      }).get();
            EXPECT_EQ(made.brickCount(), leaves.bricks.size());
            EXPECT_GE(made.stagingBytes(), budget);
            renderer.stage(std::move(made));
        } else {
            renderer.stage(leaves.bricks, std::move(atlas));
        }
        int frames = 0;
        for (bool completed = false; !completed; ++frames) {
            ASSERT_LE(frames, 10);
            context->submitAndWait([&](VkCommandBuffer cb) { completed = renderer.recordUpload(cb, budget).completed; });
        }
        EXPECT_EQ(std::size_t(frames), (rows + rows / 5 - 1) / (rows / 5));
        // Unprepared: the staging memory in the first frame, the instance records in the last.
        EXPECT_EQ(renderer.frameAllocations(), prepared ? 0u : 2u);
        const TraceImage drawn = renderer.render(camera);
        EXPECT_EQ(drawn.depth, expected.depth);
        EXPECT_EQ(drawn.feature, expected.feature);
    }
    EXPECT_EQ(context->validationErrors(), 0) << allMessages(*context);
}

INSTANTIATE_TEST_SUITE_P(Examples, BrickRendererOnEveryExample,
                         ::testing::Values("side-chair", "bookshelf-side", "table-top", "stool", "door-frame",
                                           "turned-leg"));

} // namespace
} // namespace kerf

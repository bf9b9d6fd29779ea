// Tiles hidden behind the part: the occlusion map from a picture, and the
// voxelizer keeping hidden tiles coarse until a picture shows them.

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/tracer/ViewController.hpp"
#include "kerf/voxelizer/OcclusionMap.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "kerf/voxelizer/Voxelizer.hpp"

#include "support/QuietWait.hpp"

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include <chrono>
#include <filesystem>
#include <cmath>
#include <limits>
#include <random>
#include <thread>

namespace kerf {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A wide plate (its front face at y = -55) in front of a ball at the origin:
// seen from the front, the plate hides the ball.
Document plateAndBall(bool plateVisible = true)
{
    return Document::parse(std::string(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","children":[
        {"id":"plate","type":"box","size":[160,10,160],"transform":{"translate":[0,-50,0]},"visible":)") +
                               (plateVisible ? "true" : "false") + R"(},
        {"id":"ball","type":"sphere","radius":20}]}})",
                           "plate-and-ball.kerf");
}

// Tiles of 3 levels (32 mm at 0.5 mm voxels), so that a coarse pass has
// two levels to drop.
GridLimits threeLevels()
{
    GridLimits limits;
    limits.minLevels = 3;
    return limits;
}

Camera frontCamera(int w = 320, int h = 240)
{
    return Camera::perspective({0, -400, 0}, {0, 0, 0}, {0, 0, 1}, 30.0, w, h);
}

TEST(OcclusionMap, ProjectsWhereTheCamerasRaysGo)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-60.0, 60.0);
    const Aabb part{{-50, -50, -50}, {50, 50, 50}};
    for (const Projection projection : {Projection::Perspective, Projection::Orthographic}) {
        const Camera camera = Camera::standardView(part, "iso", 400, 300, projection);
        OcclusionMap map;
        map.view = viewRequirement(camera);
        map.width = camera.width();
        map.height = camera.height();
        for (int i = 0; i < 200; ++i) {
            const glm::dvec3 p(u(rng), u(rng), u(rng));
            glm::dvec2 px;
            ASSERT_TRUE(map.project(p, px));
            // The ray through that image position passes through p.
            const Ray ray = camera.ray(px.x, px.y);
            const double t = glm::dot(p - ray.origin, ray.direction);
            EXPECT_LT(glm::length(ray.origin + t * ray.direction - p), 1e-6) << "point " << i;
        }
    }
}

TEST(OcclusionMap, EachBlockKeepsItsFarthestRayAndAMissKeepsItOpen)
{
    const Camera camera = frontCamera(20, 10);
    std::vector<float> depth(200, 5.0f);
    depth[3] = 9.0f;                                  // block (0, 0)
    depth[2 * 20 + 12] = kInf;                        // block (1, 0): a ray that saw nothing
    depth[9 * 20 + 19] = std::nanf("");               // block (2, 1): treated as nothing
    const OcclusionMap map = OcclusionMap::fromDepths(viewRequirement(camera), 20, 10, depth, 8);
    ASSERT_EQ(map.columns, 3);
    ASSERT_EQ(map.rows, 2);
    EXPECT_EQ(map.farthest[0], 9.0f);
    EXPECT_EQ(map.farthest[1], kInf);
    EXPECT_EQ(map.farthest[2], 5.0f);
    EXPECT_EQ(map.farthest[5], kInf);
    EXPECT_THROW(OcclusionMap::fromDepths(viewRequirement(camera), 20, 11, depth), std::invalid_argument);
}

TEST(OcclusionMap, HidesOnlyWhatEveryRayMeetsSooner)
{
    const Camera camera = frontCamera();
    const Tape tape = compileTape(plateAndBall());
    TraceImage picture = traceExact(tape, camera, 1e-3);
    const OcclusionMap map = OcclusionMap::fromDepths(viewRequirement(camera), picture.width, picture.height,
                                                      picture.depth);
    const Aabb ball{{-20, -20, -20}, {20, 20, 20}};
    EXPECT_TRUE(map.hides(ball, 1.0));
    EXPECT_FALSE(map.hides(ball, 400.0)) << "not when the surface may move that far";
    EXPECT_FALSE(map.hides({{-20, -70, -20}, {20, -60, 20}}, 1.0)) << "in front of the plate";
    EXPECT_FALSE(map.hides({{-20, -54, -20}, {20, -40, 20}}, 1.0)) << "the plate's front face itself";
    EXPECT_FALSE(map.hides({{-20, -420, -20}, {20, -380, 20}}, 1.0)) << "around the eye";
    EXPECT_FALSE(map.hides({{300, 0, -20}, {340, 40, 20}}, 1.0)) << "outside the picture";
    // Beside the plate the rays miss: a box there is seen, behind the plate or not.
    EXPECT_FALSE(map.hides({{90, 0, -20}, {130, 40, 20}}, 1.0));

    // One pixel of the ball's picture that sees through: the ball is visible.
    glm::dvec2 centre;
    ASSERT_TRUE(map.project({0, 0, 0}, centre));
    picture.depth[picture.index(int(centre.x), int(centre.y))] = kInf;
    const OcclusionMap holed =
        OcclusionMap::fromDepths(viewRequirement(camera), picture.width, picture.height, picture.depth);
    EXPECT_FALSE(holed.hides(ball, 1.0));
}

TEST(RefinementPlan, HiddenTilesStayCoarseAndAnotherViewsPictureIsIgnored)
{
    const Tape tape = compileTape(plateAndBall());
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.5, threeLevels());
    ASSERT_EQ(layout.levels, 3);
    const VoxelSnapshot snap = voxelize(tape, layout);
    const Camera camera = frontCamera();
    ViewRequirement view = viewRequirement(camera);
    view.pixelsPerVoxel = 0.01; // every tile in sight needs full depth
    const TraceImage picture = traceExact(tape, camera, 1e-3);
    auto map = std::make_shared<OcclusionMap>(
        OcclusionMap::fromDepths(view, picture.width, picture.height, picture.depth));

    RefinementOptions ro;
    ro.view = view;
    ro.coarseLevels = 1;
    const RefinementPlan seen = planRefinement(layout, snap.tiles, ro);
    EXPECT_EQ(seen.hidden, 0u);
    ro.occlusion = map;
    const RefinementPlan hidden = planRefinement(layout, snap.tiles, ro);
    EXPECT_GT(hidden.hidden, 0u);
    EXPECT_LT(hidden.estimatedBytes, seen.estimatedBytes);
    int ballTiles = 0;
    for (long i = 0; i < layout.tileCount(); ++i) {
        const auto& t = snap.tiles[std::size_t(i)];
        if (!t || t->state != TileState::Surface) continue;
        const Aabb box = layout.tileBox(layout.tileCoord(i));
        if (box.min.y < -30.0) { // the plate's tiles: its front face is in sight
            if (box.min.y < -55.0) {
                EXPECT_EQ(hidden.levels[std::size_t(i)], layout.levels) << "tile " << i;
            }
            continue;
        }
        ++ballTiles;
        EXPECT_EQ(seen.levels[std::size_t(i)], layout.levels) << "tile " << i;
        EXPECT_EQ(hidden.levels[std::size_t(i)], 1) << "tile " << i << " is behind the plate";
    }
    EXPECT_GT(ballTiles, 0);

    // A picture of another view says nothing here.
    ViewRequirement other = view;
    other.eye.x += 1.0;
    auto stale = std::make_shared<OcclusionMap>(*map);
    stale->view = other;
    ro.occlusion = stale;
    EXPECT_EQ(planRefinement(layout, snap.tiles, ro).hidden, 0u);
}

// The loop the viewport closes: a picture hides the ball, an edit of the
// ball then builds it coarse; hiding the plate, the next picture shows the
// ball and it refines, without any other request.
TEST(Voxelizer, KeepsHiddenTilesCoarseUntilAPictureShowsThem)
{
    Document doc = plateAndBall();
    const Camera camera = frontCamera();
    ViewRequirement view = viewRequirement(camera);
    view.pixelsPerVoxel = 0.01;
    Voxelizer vox({.limits = threeLevels(), .coarseLevelDrop = 2, .threads = 2, .featureSize = 0.5, .onPublish = {}});
    vox.setView(view);
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(120)));
    auto picture = [&] {
        const TraceImage image = traceVoxels(FlatVoxelBuffers::flatten(*vox.snapshot()), camera);
        return std::make_shared<const OcclusionMap>(
            OcclusionMap::fromDepths(view, image.width, image.height, image.depth));
    };
    EXPECT_EQ(vox.snapshot()->hiddenTiles, 0u) << "no picture yet";
    // (Each edit may change the part's bounds, so the grid: read the snapshot's.)
    auto ballLevels = [&](int& lo, int& hi) {
        lo = 99;
        hi = 0;
        const auto s = vox.snapshot();
        const GridLayout& layout = s->layout;
        for (long i = 0; i < layout.tileCount(); ++i) {
            const auto& t = s->tiles[std::size_t(i)];
            if (!t || t->state != TileState::Surface || layout.tileBox(layout.tileCoord(i)).min.y < -30.0) continue;
            lo = std::min(lo, t->levels);
            hi = std::max(hi, t->levels);
        }
    };

    // The picture shows only the plate; the ball is then edited (it grows):
    // its tiles are rebuilt at the coarse depth only.
    vox.setOcclusion(picture());
    doc.root.find("ball")->as<SphereParams>().radius = 21.0;
    std::uint64_t revision = vox.setDocument(doc);
    ASSERT_TRUE(vox.waitFor(revision, true, std::chrono::seconds(120)));
    int lo = 0, hi = 0;
    ballLevels(lo, hi);
    EXPECT_GT(vox.snapshot()->hiddenTiles, 0u);
    EXPECT_EQ(hi, vox.snapshot()->layout.levels - 2) << "hidden: the coarse pass's depth";

    // A picture that shows nothing new (the viewport's next frame) plans
    // nothing: the loop through the viewport ends there.
    ASSERT_TRUE(QuietWait(vox, revision));
    const std::uint64_t version = vox.snapshot()->version;
    vox.setOcclusion(picture());
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_EQ(vox.snapshot()->version, version);
    EXPECT_EQ(vox.lastStats().revision, revision);

    // The plate goes; the next picture sees the ball, and its tiles refine.
    doc.root.find("plate")->visible = false;
    revision = vox.setDocument(doc);
    ASSERT_TRUE(vox.waitFor(revision, true, std::chrono::seconds(120)));
    ASSERT_TRUE(QuietWait(vox, revision));
    vox.setOcclusion(picture());
    ASSERT_TRUE(QuietWait(vox, revision + 1)) << "the picture plans the document again";
    ballLevels(lo, hi);
    EXPECT_EQ(lo, vox.snapshot()->layout.levels) << "every tile of the ball in sight is at full depth";
    EXPECT_EQ(vox.snapshot()->hiddenTiles, 0u);
}

// What the occlusion saves must not show: the chair seen close up, built
// with the view alone and with the view and a picture of it (taken from
// coarser voxels, as the viewport's last frame would be), traces the same
// picture: the hidden tiles are never reached.
TEST(Voxelizer, HiddenTilesDoNotChangeThePicture)
{
    Document doc = Document::load(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf");
    doc.settings.featureSize = 1.0;
    const Tape tape = compileTape(doc);
    ViewController controller;
    controller.setStandardView("iso", tape.bounds(), 4.0 / 3.0);
    controller.zoom(1.0 / 4.0, glm::dvec3(225.0, -240.0, 450.0)); // the seat's front corner
    const Camera camera = controller.camera(480, 360, tape.bounds());
    ViewRequirement view = viewRequirement(camera);
    view.pixelsPerVoxel = 0.25; // finer than the pixels: every tile in sight at full depth
    const TraceImage coarse =
        traceVoxels(FlatVoxelBuffers::flatten(voxelize(tape, GridLayout::choose(tape.bounds(), 4.0))), camera);
    const auto picture = std::make_shared<const OcclusionMap>(
        OcclusionMap::fromDepths(view, coarse.width, coarse.height, coarse.depth));

    auto build = [&](bool withPicture) {
        Voxelizer vox({.limits = threeLevels(), .coarseLevelDrop = 2, .threads = 2, .featureSize = 0.0, .onPublish = {}});
        vox.setView(view);
        if (withPicture) vox.setOcclusion(picture);
        EXPECT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(120)));
        return vox.snapshot();
    };
    const auto seen = build(false), hidden = build(true);
    ASSERT_EQ(seen->layout, hidden->layout);
    ASSERT_GE(seen->layout.levels, 3);
    EXPECT_EQ(seen->hiddenTiles, 0u);
    EXPECT_GT(hidden->hiddenTiles, 10u);
    EXPECT_LT(hidden->bytes(), seen->bytes() * 9 / 10) << "the hidden tiles cost less";
    const TraceImage a = traceVoxels(FlatVoxelBuffers::flatten(*seen), camera);
    const TraceImage b = traceVoxels(FlatVoxelBuffers::flatten(*hidden), camera);
    std::size_t hits = 0, differ = 0;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        hits += a.hit(i);
        if (a.hit(i) != b.hit(i) || (a.hit(i) && std::fabs(a.depth[i] - b.depth[i]) > 1e-3f)) ++differ;
    }
    EXPECT_GT(hits, a.depth.size() / 4);
    EXPECT_EQ(differ, 0u) << "of " << hits << " pixels on the part";
}

} // namespace
} // namespace kerf

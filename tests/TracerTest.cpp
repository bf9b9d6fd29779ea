// The tracer: cameras, the voxel reference tracer against the exact sphere
// tracer (hit mask, depth, normals), single rays with known answers, tiles
// of mixed depths, shading and PNG output.

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/ExactRefinement.h"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/tracer/Image.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

namespace kerf {
namespace {

namespace fs = std::filesystem;

Document doc(const std::string& root)
{
    return Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf");
}

Tape sphereTape(double radius)
{
    return compileTape(doc(R"({"id":"s","type":"sphere","radius":)" + std::to_string(radius) + "}"));
}

FlatVoxelBuffers voxels(const Tape& tape, double featureSize, GridLimits limits = {})
{
    const GridLayout layout = GridLayout::choose(tape.bounds(), featureSize, limits);
    VoxelizeOptions options;
    options.threads = 2;
    return FlatVoxelBuffers::flatten(voxelize(tape, layout, options));
}

struct Agreement {
    double maskAgree = 0.0;    // fraction of pixels where both hit or both miss
    double depthWithin = 0.0;  // of pixels both hit: |depth difference| <= tolerance
    double normalWithin = 0.0; // of pixels both hit: angle <= normalDegrees
    double featureAgree = 0.0; // of pixels both hit: same feature
    int hits = 0;
};

Agreement compare(const TraceImage& voxel, const TraceImage& exact, double depthTolerance, double normalDegrees)
{
    Agreement a;
    int agree = 0, depthOk = 0, normalOk = 0, featureOk = 0, both = 0;
    const double cosMax = std::cos(normalDegrees * std::numbers::pi / 180.0);
    for (std::size_t i = 0; i < voxel.depth.size(); ++i) {
        const bool hv = voxel.hit(i), he = exact.hit(i);
        agree += hv == he;
        if (!hv || !he) continue;
        ++both;
        depthOk += std::abs(double(voxel.depth[i]) - double(exact.depth[i])) <= depthTolerance;
        normalOk += glm::dot(voxel.normal[i], exact.normal[i]) >= cosMax;
        featureOk += voxel.feature[i] == exact.feature[i];
    }
    a.hits = both;
    a.maskAgree = double(agree) / double(voxel.depth.size());
    a.depthWithin = both ? double(depthOk) / both : 1.0;
    a.normalWithin = both ? double(normalOk) / both : 1.0;
    a.featureAgree = both ? double(featureOk) / both : 1.0;
    std::printf("    %d hits; mask %.4f, depth %.4f, normal %.4f, feature %.4f\n", both, a.maskAgree, a.depthWithin,
                a.normalWithin, a.featureAgree);
    return a;
}

// Traces the same view both ways and checks the agreement the viewport needs.
void expectAgreement(const Tape& tape, const FlatVoxelBuffers& buffers, double voxelSize, std::string_view view,
                     int width = 160, int height = 120, double normalFraction = 0.95)
{
    SCOPED_TRACE(std::string(view));
    const Camera camera = Camera::standardView(tape.bounds(), view, width, height);
    const TraceImage v = traceVoxels(buffers, camera, 2);
    const TraceImage e = traceExact(tape, camera, 1e-3, 2);
    const Agreement a = compare(v, e, voxelSize, 5.0);
    EXPECT_GT(a.hits, width * height / 20); // the part is in the picture
    EXPECT_GE(a.maskAgree, 0.995);
    EXPECT_GE(a.depthWithin, 0.995);
    // Interpolated normals round off creases over a voxel or so: most, not all, pixels agree.
    EXPECT_GE(a.normalWithin, normalFraction);
}

TEST(TracerCamera, StandardViewsLookWhereTheySay)
{
    const Aabb box{{-10, -20, -30}, {10, 20, 30}};
    struct Expect {
        const char* name;
        glm::dvec3 forward;
    };
    for (const Expect& x : {Expect{"front", {0, 1, 0}}, Expect{"back", {0, -1, 0}}, Expect{"left", {1, 0, 0}},
                            Expect{"right", {-1, 0, 0}}, Expect{"top", {0, 0, -1}}, Expect{"bottom", {0, 0, 1}},
                            Expect{"iso", glm::normalize(glm::dvec3(-1, 1, -1))}}) {
        SCOPED_TRACE(x.name);
        const Camera c = Camera::standardView(box, x.name, 64, 48);
        EXPECT_NEAR(glm::dot(c.forward(), x.forward), 1.0, 1e-12);
        // The centre of the image looks at the box's centre, from outside its bounding sphere.
        const Ray r = c.ray(32.0, 24.0);
        EXPECT_NEAR(glm::length(glm::cross(r.direction, box.center() - r.origin)), 0.0, 1e-9);
        EXPECT_GT(glm::length(r.origin - box.center()), 0.5 * glm::length(box.size()));
    }
    // Z is up in the side views; X is to the right in front, top and bottom.
    EXPECT_NEAR(Camera::standardView(box, "front", 64, 48).up().z, 1.0, 1e-12);
    EXPECT_NEAR(Camera::standardView(box, "top", 64, 48).right().x, 1.0, 1e-12);
    EXPECT_NEAR(Camera::standardView(box, "bottom", 64, 48).right().x, 1.0, 1e-12);
    EXPECT_THROW(Camera::standardView(box, "sideways", 64, 48), std::invalid_argument);
}

TEST(TracerCamera, RaysGoThroughPixelCentres)
{
    const Camera p = Camera::perspective({0, -100, 0}, {0, 0, 0}, {0, 0, 1}, 90.0, 4, 2);
    // Pixel (3, 0) is the top-right one: right and up of the axis.
    const Ray r = p.ray(3, 0);
    EXPECT_GT(r.direction.x, 0.0);
    EXPECT_GT(r.direction.z, 0.0);
    EXPECT_NEAR(glm::length(r.direction), 1.0, 1e-12);
    // 90 degrees vertically: the top edge of the image is at 45 degrees.
    const Ray top = p.ray(2.0, 0.0);
    EXPECT_NEAR(top.direction.z, top.direction.y, 1e-12);

    const Camera o = Camera::orthographic({0, -100, 0}, {0, 0, 0}, {0, 0, 1}, 20.0, 4, 2);
    const Ray a = o.ray(0, 0), b = o.ray(3, 1);
    EXPECT_EQ(a.direction, glm::dvec3(0, 1, 0));
    EXPECT_NEAR(a.origin.z, 5.0, 1e-12);  // a quarter of the 20 mm height above the axis
    EXPECT_NEAR(b.origin.x, 15.0, 1e-12); // the image is 40 mm wide; pixel centres 10 mm apart
    EXPECT_NEAR(a.origin.y, -100.0, 1e-12);
}

TEST(TracerRay, HitsASphereAtTheAnalyticDistance)
{
    const Tape tape = sphereTape(10.0);
    const FlatVoxelBuffers buffers = voxels(tape, 0.5);
    const RayHit h = traceRay(buffers, Ray{{-50, 0, 0}, {1, 0, 0}});
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.depth, 40.0, buffers.layout.voxelSize);
    EXPECT_NEAR(h.normal.x, -1.0, 0.01);
    EXPECT_EQ(h.feature, 0u);
    // Off axis: the chord's near end, where the surface is slanted.
    const RayHit off = traceRay(buffers, Ray{{-50, 6, 0}, {1, 0, 0}});
    ASSERT_TRUE(off.hit());
    EXPECT_NEAR(off.depth, 50.0 - 8.0, buffers.layout.voxelSize);
    EXPECT_NEAR(glm::dot(off.normal, glm::vec3(-0.8f, 0.6f, 0.0f)), 1.0, 0.01);
}

TEST(TracerRay, MissesAreMisses)
{
    const Tape tape = sphereTape(10.0);
    const FlatVoxelBuffers buffers = voxels(tape, 0.5);
    // Never enters the grid.
    EXPECT_FALSE(traceRay(buffers, Ray{{-50, 40, 0}, {1, 0, 0}}).hit());
    EXPECT_FALSE(traceRay(buffers, Ray{{-50, 0, 0}, {-1, 0, 0}}).hit());
    // Crosses the grid beside the sphere (the grid's corner region).
    EXPECT_FALSE(traceRay(buffers, Ray{{-50, 9.5, 9.5}, {1, 0, 0}}).hit());
    // Starts beyond it, looking away; and an empty grid.
    EXPECT_FALSE(traceRay(buffers, Ray{{0, 0, 50}, {0, 0, 1}}).hit());
    EXPECT_FALSE(traceRay(FlatVoxelBuffers{}, Ray{{-50, 0, 0}, {1, 0, 0}}).hit());
    // Axis-aligned rays exactly on tile boundaries still work.
    const glm::dvec3 lo = buffers.layout.origin;
    const RayHit h = traceRay(buffers, Ray{{lo.x + buffers.layout.tileSize, lo.y - 5.0, 0.0}, {0, 1, 0}});
    EXPECT_EQ(h.hit(), std::abs(lo.x + buffers.layout.tileSize) < 10.0);
}

TEST(TracerRay, FacesOnLatticePlanesAreHit)
{
    // The box's faces lie exactly on voxel corner planes, where the stored
    // distance is exactly zero (the table top's faces do this at 1 mm).
    const Tape tape = compileTape(doc(R"({"id":"b","type":"box","size":[10,10,10]})"));
    GridLayout layout;
    layout.origin = glm::dvec3(-16.0);
    layout.dims = glm::ivec3(2);
    layout.tileSize = 16.0;
    layout.levels = 2;
    layout.voxelSize = 1.0;
    const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(voxelize(tape, layout));
    const RayHit h = traceRay(buffers, Ray{{-50, 0.3, 0.2}, {1, 0, 0}});
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.depth, 45.0, 1e-3);
    EXPECT_NEAR(h.normal.x, -1.0, 1e-3);
    // Along a tile boundary and a face at once (the plane x = 0 splits the grid).
    const RayHit down = traceRay(buffers, Ray{{0, 0, 50}, {0, 0, -1}});
    ASSERT_TRUE(down.hit());
    EXPECT_NEAR(down.depth, 45.0, 1e-3);
    // Grazing along a face plane: it meets the box's edge.
    const RayHit graze = traceRay(buffers, Ray{{-50, -5, 0.2}, {1, 0, 0}});
    ASSERT_TRUE(graze.hit());
    EXPECT_NEAR(graze.depth, 45.0, layout.voxelSize);
}

TEST(TracerRay, AFullTileIsHitAtItsFace)
{
    // A full tile that no populated voxel shields (inconsistent data): the
    // safety net reports its face rather than seeing through the solid.
    FlatVoxelBuffers b;
    b.layout.dims = {3, 1, 1};
    b.layout.tileSize = 10.0;
    b.layout.levels = 1;
    b.layout.voxelSize = 2.5;
    b.tiles = {voxel::kEmptyTile, voxel::kFullTile, voxel::kEmptyTile};
    const RayHit h = traceRay(b, glm::vec3(-5.0f, 5.0f, 5.0f), glm::vec3(1.0f, 0.0f, 0.0f));
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.depth, 15.0f, 1e-4f);
    EXPECT_EQ(h.normal, glm::vec3(-1.0f, 0.0f, 0.0f));
    const RayHit back = traceRay(b, glm::vec3(35.0f, 5.0f, 5.0f), glm::vec3(-1.0f, 0.0f, 0.0f));
    EXPECT_NEAR(back.depth, 15.0f, 1e-4f);
    EXPECT_EQ(back.normal, glm::vec3(1.0f, 0.0f, 0.0f));
}

TEST(TracerRay, ImagesDoNotDependOnTheThreadCount)
{
    const Tape tape = sphereTape(10.0);
    const FlatVoxelBuffers buffers = voxels(tape, 1.0);
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 64, 48);
    const TraceImage one = traceVoxels(buffers, camera, 1), two = traceVoxels(buffers, camera, 2);
    EXPECT_EQ(one.depth, two.depth);
    EXPECT_EQ(one.feature, two.feature);
    const TraceImage exactOne = traceExact(tape, camera, 1e-3, 1), exactTwo = traceExact(tape, camera, 1e-3, 2);
    EXPECT_EQ(exactOne.depth, exactTwo.depth);
}

TEST(TracerAgreement, Sphere)
{
    const Tape tape = sphereTape(25.0);
    const FlatVoxelBuffers buffers = voxels(tape, 1.0);
    expectAgreement(tape, buffers, buffers.layout.voxelSize, "iso");
    expectAgreement(tape, buffers, buffers.layout.voxelSize, "top");
}

TEST(TracerAgreement, RotatedBox)
{
    const Tape tape = compileTape(doc(R"({"id":"b","type":"box","size":[60,40,25],"round":2,)"
                                      R"("transform":{"rotate":[0,0,30]}})"));
    const FlatVoxelBuffers buffers = voxels(tape, 1.0);
    expectAgreement(tape, buffers, buffers.layout.voxelSize, "iso");
    expectAgreement(tape, buffers, buffers.layout.voxelSize, "front");
}

TEST(TracerAgreement, SideChair)
{
    const Tape tape = compileTape(Document::load(fs::path(KERF_EXAMPLES_DIR) / "side-chair.kerf"));
    const FlatVoxelBuffers buffers = voxels(tape, 2.0);
    expectAgreement(tape, buffers, buffers.layout.voxelSize, "iso", 320, 240);
    expectAgreement(tape, buffers, buffers.layout.voxelSize, "right", 200, 150);
}

TEST(TracerAgreement, AFaceOnALatticePlaneHasNoHoles)
{
    // At 1.8 mm the turned leg's pommel top lies on a lattice plane: the
    // interval of a box just under it was the double field's (a hair below
    // 0: full), while its corners on the face read exactly 0 in float
    // (outside), so neither layer of voxels was populated there and rays
    // went through the face, 26 mm deep (found by the GPU voxelizer's test).
    const Tape tape = compileTape(Document::load(fs::path(KERF_EXAMPLES_DIR) / "turned-leg.kerf"));
    const FlatVoxelBuffers buffers = voxels(tape, 1.8);
    expectAgreement(tape, buffers, buffers.layout.voxelSize, "iso", 120, 240, 0.9);
}

TEST(TracerAgreement, TilesOfMixedDepths)
{
    // A grid deep enough to drop a level: then every other tile is built one
    // level shallower (4x coarser voxels), as the coarse pass of the
    // background voxelizer leaves them.
    const Tape tape = compileTape(doc(R"({"id":"u","type":"union","children":[)"
                                      R"({"id":"s","type":"sphere","radius":14},)"
                                      R"({"id":"b","type":"box","size":[40,8,8],"transform":{"rotate":[20,0,10]}}]})"));
    GridLimits limits;
    limits.maxTiles = 64;
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.25, limits);
    ASSERT_GE(layout.levels, 2);
    VoxelSnapshot snap;
    snap.layout = layout;
    snap.features = tape.sharedFeatures();
    snap.tiles.resize(std::size_t(layout.tileCount()));
    TileBuildScratch scratch;
    int shallow = 0, deep = 0;
    for (long i = 0; i < layout.tileCount(); ++i) {
        const glm::ivec3 t = layout.tileCoord(i);
        const int levels = (t.x + t.y + t.z) % 2 ? layout.levels - 1 : layout.levels;
        auto tile = buildTile(tape, layout, t, levels, scratch);
        ASSERT_TRUE(tile);
        if (tile->state == TileState::Surface) ++(levels == layout.levels ? deep : shallow);
        if (tile->state != TileState::Empty) snap.tiles[std::size_t(i)] = std::make_shared<const TileData>(*tile);
    }
    ASSERT_GT(shallow, 0);
    ASSERT_GT(deep, 0);
    const FlatVoxelBuffers buffers = FlatVoxelBuffers::flatten(snap);
    const double coarse = layout.voxelSizeAt(layout.levels - 1);
    expectAgreement(tape, buffers, coarse, "iso", 160, 120, 0.9);
    expectAgreement(tape, buffers, coarse, "front", 160, 120, 0.9);
    // The hybrid refinement sees through a tile's depth to the exact field:
    // coarse and fine tiles alike agree to a hundredth of a coarse voxel.
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 160, 120);
    const Agreement a = compare(traceVoxels(buffers, camera, 2, {}, TraceQuality::Exact),
                                traceExact(tape, camera, 1e-3, 2), 0.01 * coarse, 2.0);
    EXPECT_GE(a.maskAgree, 0.999);
    EXPECT_GE(a.depthWithin, 0.99);
    EXPECT_GE(a.normalWithin, 0.99);
}

// A newcomer's side table, cut across X at 0: a leg 180 mm behind the plane
// was drawn hatched, as if cut, at the plane's depth: the cap was still
// pending after 180 mm of empty tiles, and the leg's face, on a voxel face
// (a round millimetre), gives 0 at the ray's entry, which counts as inside.
TEST(TracerSection, AFaceFarBehindThePlaneIsNoCut)
{
    const Tape tape = compileTape(doc(R"({"id":"u","type":"union","children":[
        {"id":"top","type":"box","size":[500,400,20],"transform":{"translate":[0,0,490]}},
        {"id":"leg","type":"box","size":[40,40,480],"transform":{"translate":[-200,-150,240]}}]})"));
    for (const double featureSize : {0.5, 1.0, 2.0}) {
        const FlatVoxelBuffers buffers = voxels(tape, featureSize);
        const Section section = Section::alongAxis(0, 0.0); // keeps x <= 0
        for (const TraceQuality quality : {TraceQuality::Voxels, TraceQuality::Exact}) {
            int caps = 0, rays = 0;
            // Straight along -X onto the leg's face at x = -180, and at an angle.
            for (const glm::dvec3 direction : {glm::dvec3(-1, 0, 0), glm::normalize(glm::dvec3(-1, 0.1, 0.05))})
                for (double y = -165; y <= -135; y += 3)
                    for (double z = 20; z <= 460; z += 20) {
                        Ray r;
                        r.direction = direction;
                        r.origin = glm::dvec3(-180, y, z) - 300.0 * direction; // 300 mm before the face
                        const RayHit h = traceRay(buffers, r, section, quality);
                        ++rays;
                        ASSERT_TRUE(h.hit()) << featureSize << " mm, y " << y << ", z " << z;
                        caps += h.feature == kSectionCap;
                        EXPECT_NEAR(h.depth, 300.0, 0.5 * featureSize) << featureSize << " mm, y " << y << ", z " << z;
                    }
            EXPECT_EQ(caps, 0) << "of " << rays << " rays at " << featureSize << " mm";
        }
        // The top, which the plane does cut, still shows its cap there.
        Ray r;
        r.origin = {100, 0, 490};
        r.direction = {-1, 0, 0};
        const RayHit h = traceRay(buffers, r, section);
        EXPECT_EQ(h.feature, kSectionCap);
        EXPECT_NEAR(h.depth, 100.0, 1e-3);
    }
}

// A newcomer's wall-cabinet side with a dado, cut across Y and seen in
// perspective: a strip of the dado's wall was drawn hatched as cut. The wall
// lies on lattice planes; a ray that started on the plane inside the groove
// crossed unpopulated (outside) cells and entered the wall's voxel where the
// field is exactly 0, which the cap took for inside. A cap is only where the
// plane's point is inside the part.
TEST(TracerSection, AWallOnLatticePlanesSeenInPerspectiveIsNoCut)
{
    const Tape tape = compileTape(doc(R"({"id":"side","type":"difference","children":[
        {"id":"panel","type":"box","size":[600,300,19.05],"transform":{"translate":[0,0,9.525]}},
        {"id":"dado","type":"box","size":[18,320,8],"transform":{"translate":[0,0,17.05]}}]})"));
    PointEvaluator<double> points;
    const Section section = Section::alongAxis(1, -113.0, true);
    for (const double featureSize : {0.5, 1.0}) {
        const FlatVoxelBuffers buffers = voxels(tape, featureSize);
        const Camera camera = Camera::perspective({0, -400, 10}, {0, -113, 10}, {0, 0, 1}, 8.0, 220, 160);
        for (const TraceQuality quality : {TraceQuality::Voxels, TraceQuality::Exact}) {
            const TraceImage image = traceVoxels(buffers, camera, 2, section, quality);
            int caps = 0, capsOutside = 0;
            for (int y = 0; y < image.height; ++y)
                for (int x = 0; x < image.width; ++x) {
                    if (image.feature[image.index(x, y)] != kSectionCap) continue;
                    ++caps;
                    const Ray r = camera.ray(x, y);
                    const glm::dvec3 p = r.origin + double(image.depth[image.index(x, y)]) * r.direction;
                    // Outside by more than the voxels' own departure near the
                    // groove's inner corners (0.09 of a voxel seen there).
                    capsOutside += points.evaluate(tape, p.x, p.y, p.z) > 0.25 * featureSize;
                }
            EXPECT_GT(caps, 1000) << featureSize << " mm: the plane cuts the panel";
            EXPECT_EQ(capsOutside, 0) << "of " << caps << " caps at " << featureSize << " mm, "
                                      << traceQualityName(quality);
        }
    }
}

// A section view is the exact image of the part intersected with the kept
// half-space: the cut face of that solid is the plane, where the voxel
// tracer reports the cap.
TEST(TracerSection, MatchesTheExactImageOfTheClippedPart)
{
    const char* part = R"({"id":"u","type":"difference","children":[)"
                       R"({"id":"b","type":"box","size":[60,40,30],"round":3,"transform":{"rotate":[0,0,20]}},)"
                       R"({"id":"h","type":"cylinder","radius":6,"height":50,"transform":{"translate":[5,2,0]}}]})";
    const Tape tape = compileTape(doc(part));
    const FlatVoxelBuffers buffers = voxels(tape, 0.5);
    for (const auto& [section, view] : {std::pair{Section::alongAxis(0, 3.0), "right"},
                                        std::pair{Section::alongAxis(2, -4.0, true), "bottom"},
                                        std::pair{Section::alongAxis(1, 1.0), "iso"}}) {
        SCOPED_TRACE(view);
        // The kept half-space as a document node: dot(n, p) <= offset.
        char clip[256];
        std::snprintf(clip, sizeof clip, R"({"id":"cut","type":"halfspace","normal":[%g,%g,%g],"offset":%.17g})",
                      section.normal.x, section.normal.y, section.normal.z, section.offset);
        const Tape clipped = compileTape(
            doc(std::string(R"({"id":"i","type":"intersection","children":[)") + part + "," + clip + "]}"));
        const Camera camera = Camera::standardView(tape.bounds(), view, 160, 120);
        const TraceImage v = traceVoxels(buffers, camera, 2, section);
        const TraceImage e = traceExact(clipped, camera, 1e-3, 2);
        const Agreement a = compare(v, e, 0.5, 5.0);
        EXPECT_GE(a.maskAgree, 0.99);
        EXPECT_GE(a.depthWithin, 0.99);
        EXPECT_GE(a.normalWithin, 0.95);
        // The cap shows where the exact image hits the plane, and carries the plane's normal.
        std::size_t caps = 0, capsOnPlane = 0;
        for (std::size_t i = 0; i < v.depth.size(); ++i) {
            if (v.feature[i] != kSectionCap) continue;
            ++caps;
            const Ray r = camera.ray(int(i % 160), int(i / 160));
            const glm::dvec3 p = r.origin + double(v.depth[i]) * r.direction;
            capsOnPlane += std::fabs(glm::dot(p, section.normal) - section.offset) < 1e-3;
            EXPECT_LT(glm::length(glm::dvec3(v.normal[i]) - section.normal), 1e-6);
        }
        if (std::string_view(view) != "iso") {
            EXPECT_GT(caps, 1000u);
        }
        EXPECT_EQ(capsOnPlane, caps);
    }
    // Disabled: the same picture as without a section.
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 80, 60);
    EXPECT_EQ(traceVoxels(buffers, camera, 2, Section{}).depth, traceVoxels(buffers, camera, 2).depth);
}

// ---- The hybrid refinement (TraceQuality::Exact) ----

// How an image departs from the exact one, over every pixel and over the
// pixels at the exact image's edges (silhouettes, creases, rims: where a
// neighbour misses or turns by more than 20 degrees).
struct Departure {
    double maskAgree = 0.0, meanDepth = 0.0, normalWithin = 0.0; // all pixels (depth, normals: hit both ways)
    double edgeMaskAgree = 0.0, edgeMeanDepth = 0.0, edgeNormalWithin = 0.0;
    int edgePixels = 0;
};

Departure departure(const TraceImage& img, const TraceImage& exact, double normalDegrees = 2.0)
{
    const double cosMax = std::cos(normalDegrees * std::numbers::pi / 180.0);
    const double cosEdge = std::cos(20.0 * std::numbers::pi / 180.0);
    struct Sums {
        int pixels = 0, agree = 0, both = 0, normalOk = 0;
        double depth = 0.0;
    } all, edge;
    for (int y = 0; y < exact.height; ++y)
        for (int x = 0; x < exact.width; ++x) {
            const std::size_t i = exact.index(x, y);
            bool isEdge = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= exact.width || ny >= exact.height) continue;
                    const std::size_t j = exact.index(nx, ny);
                    if (exact.hit(i) != exact.hit(j) ||
                        (exact.hit(i) && glm::dot(exact.normal[i], exact.normal[j]) < cosEdge))
                        isEdge = true;
                }
            for (Sums* s : {&all, isEdge ? &edge : nullptr}) {
                if (!s) continue;
                ++s->pixels;
                s->agree += img.hit(i) == exact.hit(i);
                if (!img.hit(i) || !exact.hit(i)) continue;
                ++s->both;
                s->depth += std::abs(double(img.depth[i]) - double(exact.depth[i]));
                s->normalOk += glm::dot(img.normal[i], exact.normal[i]) >= cosMax;
            }
        }
    Departure d;
    d.maskAgree = double(all.agree) / std::max(1, all.pixels);
    d.meanDepth = all.depth / std::max(1, all.both);
    d.normalWithin = double(all.normalOk) / std::max(1, all.both);
    d.edgePixels = edge.pixels;
    d.edgeMaskAgree = double(edge.agree) / std::max(1, edge.pixels);
    d.edgeMeanDepth = edge.depth / std::max(1, edge.both);
    d.edgeNormalWithin = double(edge.normalOk) / std::max(1, edge.both);
    std::printf("    mask %.4f, mean depth error %.4f mm, normals within 2 deg %.4f; %d edge pixels: mask %.4f, "
                "depth %.4f mm, normals %.4f\n",
                d.maskAgree, d.meanDepth, d.normalWithin, d.edgePixels, d.edgeMaskAgree, d.edgeMeanDepth,
                d.edgeNormalWithin);
    return d;
}

// A part made of sharp edges, rims and creases: two boxes meeting at an
// angle (a concave crease where they intersect), less a tilted cylinder
// (a hole with a sharp rim), voxelized coarsely (2 mm voxels on a 60 mm part).
const char* kSharpPart = R"({"id":"d","type":"difference","children":[
    {"id":"u","type":"union","children":[
      {"id":"b","type":"box","size":[60,40,30],"transform":{"rotate":[0,0,20]}},
      {"id":"c","type":"box","size":[20,50,12],"transform":{"translate":[-18,-10,14],"rotate":[30,0,0]}}]},
    {"id":"h","type":"cylinder","radius":9,"height":50,"transform":{"translate":[8,2,0],"rotate":[10,0,0]}}]})";

TEST(TracerExact, SharpensEdgesAndIntersections)
{
    const Tape tape = compileTape(doc(kSharpPart));
    const FlatVoxelBuffers buffers = voxels(tape, 2.0);
    ASSERT_FALSE(buffers.tapes.empty());
    for (const char* view : {"iso", "top", "front"}) {
        SCOPED_TRACE(view);
        const Camera camera = Camera::standardView(tape.bounds(), view, 320, 240);
        const TraceImage exact = traceExact(tape, camera, 1e-3, 2);
        std::printf("  %s, voxels:\n", view);
        const Departure v = departure(traceVoxels(buffers, camera, 2, {}, TraceQuality::Voxels), exact);
        std::printf("  %s, hybrid:\n", view);
        const Departure h = departure(traceVoxels(buffers, camera, 2, {}, TraceQuality::Exact), exact);
        ASSERT_GT(h.edgePixels, 1000);
        // Everywhere: depth to a hundredth of a millimetre (the voxels:
        // a tenth), normals within 2 degrees on nearly every pixel.
        EXPECT_LT(h.meanDepth, 0.01);
        EXPECT_LT(h.meanDepth, v.meanDepth / 5.0);
        EXPECT_GE(h.maskAgree, 0.999);
        EXPECT_GE(h.normalWithin, 0.995);
        EXPECT_GT(h.normalWithin, v.normalWithin + 0.1);
        // At the edges, where the voxels round off and fill in (there about
        // 80% of the pixels agree in coverage, 15% in normal).
        EXPECT_GE(h.edgeMaskAgree, 0.98);
        EXPECT_GT(h.edgeMaskAgree, v.edgeMaskAgree + 0.1);
        EXPECT_LT(h.edgeMeanDepth, v.edgeMeanDepth / 10.0);
        EXPECT_GE(h.edgeNormalWithin, 0.97);
        EXPECT_GT(h.edgeNormalWithin, v.edgeNormalWithin + 0.5);
    }
}

TEST(TracerExact, AgreesWithTheExactTracerOnEveryShape)
{
    // The voxel agreement tests, held to a tighter standard. Depth is
    // compared across the surface (the depth difference times the cosine
    // of the incidence): along rays grazing a silhouette the two tracers'
    // stopping rules (field below 1e-3 mm, below 1e-3 voxel) put equally
    // good hits far apart in depth.
    const Tape sphere = sphereTape(25.0);
    const Tape chair = compileTape(Document::load(fs::path(KERF_EXAMPLES_DIR) / "side-chair.kerf"));
    const Tape rotated = compileTape(doc(R"({"id":"b","type":"box","size":[60,40,25],"round":2,)"
                                         R"("transform":{"rotate":[0,0,30]}})"));
    for (const auto& [tape, featureSize] :
         {std::pair<const Tape*, double>{&sphere, 1.0}, {&rotated, 1.0}, {&chair, 2.0}}) {
        const FlatVoxelBuffers buffers = voxels(*tape, featureSize);
        for (const char* view : {"iso", "right"}) {
            SCOPED_TRACE(view);
            const Camera camera = Camera::standardView(tape->bounds(), view, 200, 150);
            const TraceImage h = traceVoxels(buffers, camera, 2, {}, TraceQuality::Exact);
            const TraceImage e = traceExact(*tape, camera, 1e-3, 2);
            const Agreement a = compare(h, e, 0.02 * featureSize, 2.0);
            int both = 0, across = 0;
            for (int y = 0; y < camera.height(); ++y)
                for (int x = 0; x < camera.width(); ++x) {
                    const std::size_t i = h.index(x, y);
                    if (!h.hit(i) || !e.hit(i)) continue;
                    ++both;
                    const double cosine = std::abs(glm::dot(glm::dvec3(e.normal[i]), camera.ray(x, y).direction));
                    across += std::abs(double(h.depth[i]) - double(e.depth[i])) * cosine <= 0.01 * featureSize;
                }
            EXPECT_GE(a.maskAgree, 0.999);
            EXPECT_GE(double(across), 0.999 * both);
            EXPECT_GE(a.normalWithin, 0.99);
            EXPECT_GE(a.featureAgree, 0.99);
        }
    }
}

TEST(TracerExact, TilesWithoutATapeAreTracedOnTheirVoxels)
{
    const Tape tape = compileTape(doc(kSharpPart));
    FlatVoxelBuffers buffers = voxels(tape, 2.0);
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 160, 120);
    const TraceImage voxelOnly = traceVoxels(buffers, camera, 2);
    const TraceImage hybrid = traceVoxels(buffers, camera, 2, {}, TraceQuality::Exact);
    EXPECT_NE(voxelOnly.depth, hybrid.depth) << "the refinement should change the picture";
    // The voxel path does not look at the tapes.
    FlatVoxelBuffers stripped = buffers;
    for (TileEntry& e : stripped.entries) e.tape = voxel::kNoTape;
    stripped.tapes.clear();
    EXPECT_EQ(traceVoxels(stripped, camera, 2).depth, voxelOnly.depth);
    // Without tapes, the exact quality falls back to the voxels, tile by tile.
    const TraceImage fallback = traceVoxels(stripped, camera, 2, {}, TraceQuality::Exact);
    EXPECT_EQ(fallback.depth, voxelOnly.depth);
    EXPECT_EQ(fallback.feature, voxelOnly.feature);
    // The cost measure: exact evaluations only where the refinement runs.
    const Ray centre = camera.ray(80, 60);
    EXPECT_EQ(traceRay(buffers, centre).evaluations, 0u);
    const RayHit refined = traceRay(buffers, centre, {}, TraceQuality::ExactEverywhere);
    ASSERT_TRUE(refined.hit());
    EXPECT_GT(refined.evaluations, 7u); // at least the normal's and the feature's
    // Exact checks the voxel hit with two evaluations (VoxelHitCheck.hpp) at least.
    EXPECT_GE(traceRay(buffers, centre, {}, TraceQuality::Exact).evaluations, 2u);
}

TEST(TracerExact, RefinesOnlyTheRaysTheCheckCannotConfirmForTheSamePicture)
{
    // TraceQuality::Exact checks each voxel hit on the exact field and
    // refines only the rays it cannot confirm (VoxelHitCheck.hpp):
    // against the exact tracer it must draw the picture that refining every
    // ray draws, at a fraction of the evaluations.
    const Tape sharp = compileTape(doc(kSharpPart));
    const Tape chair = compileTape(Document::load(fs::path(KERF_EXAMPLES_DIR) / "side-chair.kerf"));
    PointEvaluator<double> points;
    for (const auto& [tape, featureSize] : {std::pair<const Tape*, double>{&sharp, 2.0}, {&chair, 2.0}, {&chair, 0.5}}) {
        SCOPED_TRACE(featureSize);
        const FlatVoxelBuffers buffers = voxels(*tape, featureSize);
        for (const char* view : {"iso", "right"})
        // The refinement's lanes a ray: the CPU's and lavapipe's 8, NVIDIA's 32.
        for (const int lanes : {KERF_EDGE_REFINE_LANES, KERF_EDGE_REFINE_MAX_LANES}) {
            SCOPED_TRACE(view);
            SCOPED_TRACE(lanes);
            const Camera camera = Camera::standardView(tape->bounds(), view, 200, 150);
            const TraceImage e = traceExact(*tape, camera, 1e-4, 2);
            const Agreement everywhere =
                compare(traceVoxels(buffers, camera, 2, {}, TraceQuality::ExactEverywhere), e, 0.02 * featureSize, 2.0);
            std::size_t refined = 0, hits = 0, confirmed = 0, evaluationsExact = 0, evaluationsEverywhere = 0;
            TraceImage checked(camera.width(), camera.height());
            for (int y = 0; y < camera.height(); ++y)
                for (int x = 0; x < camera.width(); ++x) {
                    const Ray ray = camera.ray(x, y);
                    const RayHit h = traceRay(buffers, ray, {}, TraceQuality::Exact, lanes);
                    const std::size_t i = checked.index(x, y);
                    checked.depth[i] = h.depth;
                    checked.normal[i] = h.normal;
                    checked.feature[i] = h.feature;
                    evaluationsExact += h.evaluationsInARow;
                    evaluationsEverywhere += traceRay(buffers, ray, {}, TraceQuality::ExactEverywhere).evaluationsInARow;
                    hits += h.hit();
                    refined += h.refined;
                    if (h.hit() && !h.refined && h.evaluations > 0) {
                        // A confirmed hit lies on the exact surface.
                        ++confirmed;
                        const glm::dvec3 p = ray.origin + double(h.depth) * ray.direction;
                        EXPECT_LT(std::abs(points.evaluate(*tape, p.x, p.y, p.z)),
                                  KERF_EDGE_CHECK_ON_SURFACE * buffers.layout.voxelSize + 1e-6 * double(h.depth))
                            << "pixel " << x << "," << y;
                    }
                }
            const Agreement a = compare(checked, e, 0.02 * featureSize, 2.0);
            EXPECT_GE(a.maskAgree, everywhere.maskAgree - 0.001);
            EXPECT_GE(a.depthWithin, everywhere.depthWithin - 0.002);
            EXPECT_GE(a.normalWithin, everywhere.normalWithin - 0.002);
            EXPECT_GE(a.featureAgree, everywhere.featureAgree - 0.002);
            EXPECT_GT(confirmed, hits / 2) << "most hits are confirmed";
            EXPECT_LT(refined, hits / 2);
            // Fewer evaluations one after another (a refined ray's rounds
            // count once: its lanes evaluate together on the GPU); far fewer
            // where edges are not most of the picture (the chair from the
            // side is mostly edges at this size).
            EXPECT_LT(evaluationsExact, evaluationsEverywhere);
            if (tape == &chair && std::string(view) == "iso") {
                EXPECT_LT(evaluationsExact, evaluationsEverywhere / 2);
            }
            // traceVoxels draws what traceRay answers, ray by ray.
            EXPECT_EQ(traceVoxels(buffers, camera, 2, {}, TraceQuality::Exact, {}, lanes).depth, checked.depth);
        }
    }
}

TEST(TracerExact, ARayMeetingTwoSurfacesWithinASpanStopsAtTheFirst)
{
    // Where an edge of one board passes just in front of another's face,
    // the refinement's points can land outside the first and on the second
    // (within eps of it): the span between them then holds the first
    // crossing too, and the hit must be that one, with its normal. Taking
    // the span's end showed the face behind on 66 pixels of this part at
    // 800x600.
    const Tape tape = compileTape(doc(kSharpPart));
    const FlatVoxelBuffers buffers = voxels(tape, 0.5);
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 400, 300);
    const TraceImage exact = traceExact(tape, camera, 1e-5, 2);
    for (const int lanes : {KERF_EDGE_REFINE_LANES, KERF_EDGE_REFINE_MAX_LANES}) {
        SCOPED_TRACE(lanes);
        const TraceImage image = traceVoxels(buffers, camera, 2, {}, TraceQuality::Exact, {}, lanes);
        int both = 0, turned = 0;
        for (std::size_t i = 0; i < image.depth.size(); ++i) {
            if (!image.hit(i) || !exact.hit(i)) continue;
            ++both;
            turned += glm::dot(image.normal[i], exact.normal[i]) < std::cos(10.0f * 3.14159265f / 180.0f);
        }
        ASSERT_GT(both, 20000);
        std::printf("    %d lanes: %d of %d pixels hit both with normals more than 10 degrees apart\n", lanes, turned,
                    both);
        EXPECT_LE(turned, both / 4000);
    }
}

TEST(TracerExact, SectionsAndCapsStillMatchTheExactImage)
{
    const char* part = R"({"id":"u","type":"difference","children":[)"
                       R"({"id":"b","type":"box","size":[60,40,30],"round":3,"transform":{"rotate":[0,0,20]}},)"
                       R"({"id":"h","type":"cylinder","radius":6,"height":50,"transform":{"translate":[5,2,0]}}]})";
    const Tape tape = compileTape(doc(part));
    const FlatVoxelBuffers buffers = voxels(tape, 1.0);
    const Section section = Section::alongAxis(0, 3.0);
    const Tape clipped = compileTape(doc(std::string(R"({"id":"i","type":"intersection","children":[)") + part +
                                         R"(,{"id":"cut","type":"halfspace","normal":[1,0,0],"offset":3}]})"));
    const Camera camera = Camera::standardView(tape.bounds(), "right", 160, 120);
    const TraceImage v = traceVoxels(buffers, camera, 2, section, TraceQuality::Exact);
    const Agreement a = compare(v, traceExact(clipped, camera, 1e-3, 2), 0.05, 5.0);
    EXPECT_GE(a.maskAgree, 0.995);
    EXPECT_GE(a.depthWithin, 0.99);
    EXPECT_GE(a.normalWithin, 0.98);
    std::size_t caps = 0;
    for (std::uint32_t f : v.feature) caps += f == kSectionCap;
    EXPECT_GT(caps, 1000u);
}

TEST(TracerImage, ShadesHitsAndBackground)
{
    TraceImage img(2, 1);
    img.depth[1] = 10.0f;
    img.normal[1] = {0, 0, 1};
    img.feature[1] = 0;
    Feature red;
    red.hasColor = true;
    red.color = {255, 0, 0};
    const RgbaImage out = shade(img, {red});
    ASSERT_EQ(out.pixels.size(), 8u);
    EXPECT_EQ(out.pixels[3], 255);
    EXPECT_GT(out.pixels[4], 100); // the red feature, lit from above
    EXPECT_EQ(out.pixels[5], 0);
    EXPECT_EQ(out.pixels[6], 0);
    EXPECT_NE(out.pixels[0], out.pixels[4]); // background is not the part
}

TEST(TracerImage, WritesPngAtomically)
{
    const fs::path dir = fs::temp_directory_path() / ("kerf-tracer-test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path file = dir / "out.png";
    std::vector<std::uint8_t> rgba(3 * 2 * 4, 200);
    writePng(file, rgba.data(), 3, 2);
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GE(bytes.size(), 8u);
    EXPECT_EQ(bytes.substr(1, 3), "PNG");
    // Nothing but the target in the folder: the temporary is gone.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
    // A target that cannot be written throws and leaves nothing behind.
    EXPECT_THROW(writePng(dir / "missing-folder" / "x.png", rgba.data(), 3, 2), std::runtime_error);
    fs::remove_all(dir);
}

} // namespace
} // namespace kerf

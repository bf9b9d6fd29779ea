// The voxelizer against exact evaluation: stored corners equal the exact
// field, every voxel the surface crosses is populated and none is farther
// from the surface than its diagonal; incremental rebuilds equal full ones;
// cancellation never publishes a partial tile; memory follows surface area.

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/DirtyRegion.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"
#include "kerf/voxelizer/VoxelQuery.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "kerf/voxelizer/RefinementPlan.hpp"
#include "kerf/voxelizer/Voxelizer.hpp"
#include "support/QuietWait.hpp"
#include "support/RandomShapes.hpp"

#include "kerf/document/Limits.hpp"

#include <gtest/gtest.h>

#include <thread>

#include <glm/glm.hpp>

#include <mutex>
#include <set>

namespace kerf {
namespace {

Document parse(const std::string& root, double featureSize)
{
    return Document::parse(R"({"format":"kerf","version":1,"settings":{"feature_size":)" + std::to_string(featureSize) +
                               R"(},"root":)" + root + "}",
                           "test.kerf");
}

const char* kSphere = R"({"id":"s","type":"sphere","radius":10})";
const char* kRotatedBox =
    R"({"id":"b","type":"box","size":[30,14,9],"round":2,"transform":{"rotate":[20,35,-15],"translate":[3,-2,1]}})";
const char* kBoardWithHoles = R"({"id":"d","type":"difference","children":[
    {"id":"board","type":"box","size":[60,30,12],"round":1},
    {"id":"holes","type":"array","count":[3,1,1],"step":[18,0,0],"transform":{"translate":[-18,0,0]},
     "children":[{"id":"hole","type":"cylinder","radius":4,"height":20}]},
    {"id":"groove","type":"box","size":[70,4,5],"transform":{"translate":[0,9,6]}}]})";

struct Checked {
    long voxels = 0, corners = 0, normalsWithin1Degree = 0;
};

// Every populated voxel: corners straddle the surface in the stored data,
// stored distances equal exact double evaluation (within the encoding's
// quantization), every corner within a voxel diagonal of the surface.
Checked checkAgainstExact(const Tape& tape, const VoxelSnapshot& snap)
{
    Checked c;
    PointEvaluator<double> exact;
    GradientEvaluator<double> grad;
    const GridLayout& g = snap.layout;
    for (long i = 0; i < g.tileCount(); ++i) {
        const auto& tile = snap.tiles[std::size_t(i)];
        if (!tile) continue;
        const double h = g.voxelSizeAt(tile->levels);
        const glm::dvec3 base = g.tileBox(g.tileCoord(i)).min;
        const double quantum = voxel::kDistanceRange * h / 32767.0;
        forEachVoxel(*tile, float(h), [&](const glm::ivec3& v, const VoxelCorners& k) {
            ++c.voxels;
            bool neg = false, pos = false;
            for (int q = 0; q < 8; ++q) {
                const glm::dvec3 p = base + h * (glm::dvec3(v) + glm::dvec3(q & 1, (q >> 1) & 1, q >> 2));
                const double e = exact.evaluate(tape, p.x, p.y, p.z);
                ++c.corners;
                EXPECT_NEAR(k.distance[q], e, quantum + 1e-4 + 1e-6 * h) << "tile " << i;
                EXPECT_LE(std::fabs(e), std::sqrt(3.0) * h + 1e-6) << "corner farther than a diagonal";
                neg = neg || k.distance[q] < 0.0f;
                pos = pos || k.distance[q] >= 0.0f;
                const Dual<double> d = grad.evaluate(tape, p.x, p.y, p.z);
                const glm::dvec3 n = glm::normalize(glm::dvec3(d.d[0], d.d[1], d.d[2]));
                if (glm::dot(n, glm::dvec3(k.normal[q])) > std::cos(glm::radians(1.0))) ++c.normalsWithin1Degree;
            }
            EXPECT_TRUE(neg && pos) << "populated voxel without a sign change";
        });
    }
    return c;
}

// Dense sampling of the whole grid at half-voxel spacing: every voxel in
// which the exact field takes both signs by more than `tolerance` must be
// populated.
long checkCompleteness(const Tape& tape, const VoxelSnapshot& snap, double toleranceInVoxels)
{
    PointEvaluator<double> exact;
    const GridLayout& g = snap.layout;
    long crossed = 0;
    for (long i = 0; i < g.tileCount(); ++i) {
        const auto& tile = snap.tiles[std::size_t(i)];
        const int levels = tile ? tile->levels : g.levels;
        const int n = 1 << (2 * levels);
        const double h = g.voxelSizeAt(levels);
        const double tol = toleranceInVoxels * h;
        const glm::dvec3 base = g.tileBox(g.tileCoord(i)).min;
        // Cheap rejection: no sample in this tile can be near the surface.
        const double centre = exact.evaluate(tape, base.x + 0.5 * g.tileSize, base.y + 0.5 * g.tileSize,
                                             base.z + 0.5 * g.tileSize);
        if (std::fabs(centre) > g.tileSize) continue;
        const int m = 2 * n + 1;
        std::vector<double> s(std::size_t(m) * m * m);
        for (int z = 0; z < m; ++z)
            for (int y = 0; y < m; ++y)
                for (int x = 0; x < m; ++x) {
                    const glm::dvec3 p = base + 0.5 * h * glm::dvec3(x, y, z);
                    s[std::size_t(x + m * (y + m * z))] = exact.evaluate(tape, p.x, p.y, p.z);
                }
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    bool neg = false, pos = false;
                    for (int k = 0; k < 27; ++k) {
                        const double v = s[std::size_t((2 * x + k % 3) + m * ((2 * y + (k / 3) % 3) + m * (2 * z + k / 9)))];
                        neg = neg || v < -tol;
                        pos = pos || v > tol;
                    }
                    if (!(neg && pos)) continue;
                    ++crossed;
                    const bool populated = tile && findVoxel(*tile, {x, y, z}, float(h)).has_value();
                    EXPECT_TRUE(populated) << "tile " << i << " voxel (" << x << ", " << y << ", " << z << ")";
                    if (!populated) return crossed;
                }
    }
    return crossed;
}

struct Part {
    const char* name;
    const char* json;
    double featureSize;
};
void PrintTo(const Part& p, std::ostream* os) { *os << p.name; }

class VoxelizeAgainstExact : public ::testing::TestWithParam<Part> {};

TEST_P(VoxelizeAgainstExact, CornersSurfaceAndCompleteness)
{
    const Document d = parse(GetParam().json, GetParam().featureSize);
    const Tape tape = compileTape(d);
    const GridLayout g = GridLayout::choose(tape.bounds(), GetParam().featureSize);
    EXPECT_DOUBLE_EQ(g.voxelSize, GetParam().featureSize) << "the feature size is never rounded";
    const VoxelSnapshot snap = voxelize(tape, g);
    const Checked c = checkAgainstExact(tape, snap);
    EXPECT_GT(c.voxels, 1000);
    EXPECT_GT(c.normalsWithin1Degree, c.corners * 95 / 100);
    // Not vacuous: many voxels are crossed. (Faces lying exactly on lattice
    // planes have corners at 0, which count as outside: their voxels are
    // populated without a robust sign change, so this is not all of them.)
    EXPECT_GT(checkCompleteness(tape, snap, 0.02), 1000);
}

INSTANTIATE_TEST_SUITE_P(Parts, VoxelizeAgainstExact,
                         ::testing::Values(Part{"Sphere", kSphere, 0.5}, Part{"RotatedRoundedBox", kRotatedBox, 0.4},
                                           Part{"BoardWithHoles", kBoardWithHoles, 0.5}),
                         [](const auto& p) { return std::string(p.param.name); });

TEST(Voxelize, RandomTreesMatchExactEvaluation)
{
    test::RandomShapes r(17);
    for (int t = 0; t < 12; ++t) {
        Document d = test::RandomShapes::document(r.tree(3));
        const Tape tape = compileTape(d);
        if (tape.empty() || tape.bounds().isEmpty()) continue;
        const GridLayout g = GridLayout::choose(tape.bounds(), 1.0);
        const VoxelSnapshot snap = voxelize(tape, g);
        checkAgainstExact(tape, snap);
        if (HasFailure()) return;
    }
}

TEST(Voxelize, ACornerAHairInsideTheSurfaceReadsBackInside)
{
    // The lattice point (10, 0, 0) lies 1e-5 mm inside a sphere of radius
    // 10.00001 (a third of a distance quantum at 0.5 mm voxels): its voxel is
    // populated, so the stored corner must read back negative. Rounded to
    // zero, it read as outside, and a clang build of the random-tree test
    // above (whose trees differed from GCC's: argument evaluation order) hit
    // exactly that: "populated voxel without a sign change".
    const Document d = parse(R"({"id":"s","type":"sphere","radius":10.00001})", 0.5);
    const Tape tape = compileTape(d);
    const VoxelSnapshot snap = voxelize(tape, GridLayout::choose(tape.bounds(), 0.5));
    const Checked c = checkAgainstExact(tape, snap);
    EXPECT_GT(c.voxels, 1000);
}

TEST(Voxelize, MemoryGrowsWithSurfaceAreaNotVolume)
{
    // Same feature size, radius doubled: area x4, volume x8.
    auto bytes = [](double radius) {
        const Document d = parse(R"({"id":"s","type":"sphere","radius":)" + std::to_string(radius) + "}", 0.5);
        const Tape tape = compileTape(d);
        return double(voxelize(tape, GridLayout::choose(tape.bounds(), 0.5)).bytes());
    };
    const double small = bytes(12.0), large = bytes(24.0);
    const double ratio = large / small;
    EXPECT_GT(ratio, 3.0);
    EXPECT_LT(ratio, 5.5) << "memory should scale like the area (4x), not the volume (8x)";
}

TEST(Voxelize, OneThreadAndTwoGiveIdenticalTiles)
{
    const Document d = parse(kBoardWithHoles, 0.5);
    const Tape tape = compileTape(d);
    const GridLayout g = GridLayout::choose(tape.bounds(), 0.5);
    const VoxelSnapshot a = voxelize(tape, g, {.levels = -1, .threads = 1});
    const VoxelSnapshot b = voxelize(tape, g, {.levels = -1, .threads = 2});
    ASSERT_EQ(a.tiles.size(), b.tiles.size());
    const FlatVoxelBuffers fa = FlatVoxelBuffers::flatten(a), fb = FlatVoxelBuffers::flatten(b);
    EXPECT_EQ(fa.tiles, fb.tiles);
    EXPECT_EQ(fa.bytes(), fb.bytes());
    EXPECT_EQ(0, std::memcmp(fa.vertices.data(), fb.vertices.data(), fa.vertices.size() * sizeof(voxel::Vertex)));
}

TEST(GridLayout, ChoosesWholeTilesAndSaysWhenTheDepthRunsOut)
{
    const Aabb chair{{-226, -241, 0}, {226, 262, 882}};
    const GridLayout g = GridLayout::choose(chair, 0.5);
    EXPECT_DOUBLE_EQ(g.voxelSize, 0.5);
    EXPECT_LE(g.tileCount(), 32 * 32 * 32);
    EXPECT_TRUE(g.bounds().contains(chair.min) && g.bounds().contains(chair.max));
    EXPECT_TRUE(g.note.empty());
    // 0.01 mm on a 5 m part needs more than the addressing allows.
    const GridLayout deep = GridLayout::choose(Aabb{{0, 0, 0}, {5000, 400, 30}}, 0.0001, {.maxTiles = 32768, .maxLevels = 6});
    EXPECT_GT(deep.voxelSize, 0.0001);
    EXPECT_FALSE(deep.note.empty());
    EXPECT_LE(deep.tileCount(), 32768);
    EXPECT_TRUE(GridLayout::choose(Aabb::empty(), 1.0).empty());
    EXPECT_TRUE(GridLayout::choose(Aabb::empty(), 1.0).bounds().isEmpty()); // not a point at the origin
    // The default feature size stays within what a document may set.
    EXPECT_DOUBLE_EQ(defaultFeatureSize(Aabb::centered(glm::dvec3(1e-300))), limits::kMinFeatureSize);
    EXPECT_DOUBLE_EQ(defaultFeatureSize(Aabb::centered(glm::dvec3(1e12))), limits::kMaxFeatureSize);
    EXPECT_DOUBLE_EQ(defaultFeatureSize(Aabb::centered(glm::dvec3(500.0))), 1.0);
    // A 200 km sphere at 1e-6 mm (both within the format's limits): 1e13
    // tiles a side at the shallowest depth, which an int held as INT_MIN, a
    // negative count that passed as fitting (the application then crashed).
    for (const double radius : {1e5, 1e8}) {
        const GridLayout huge = GridLayout::choose(Aabb::centered(glm::dvec3(radius)), 1e-6);
        EXPECT_GT(huge.dims.x, 0) << radius;
        EXPECT_GT(huge.tileCount(), 0) << radius;
        EXPECT_LE(huge.tileCount(), 32768) << radius;
        EXPECT_GT(huge.voxelSize, 1e-6) << radius;
        EXPECT_FALSE(huge.note.empty()) << radius;
        EXPECT_TRUE(huge.bounds().contains(glm::dvec3(radius)) && huge.bounds().contains(glm::dvec3(-radius)));
    }
}

TEST(VoxelFormat, CompactEncodingErrors)
{
    test::RandomShapes r(3);
    double worstAngle = 0.0;
    for (int i = 0; i < 100000; ++i) {
        glm::dvec3 n = r.vec(-1, 1);
        if (glm::length(n) < 1e-3) continue;
        n = glm::normalize(n);
        const glm::vec3 back = voxel::decodeNormal(voxel::encodeNormal(glm::vec3(n)));
        worstAngle = std::max(worstAngle, glm::degrees(std::acos(std::min(1.0, glm::dot(glm::dvec3(back), n)))));
    }
    EXPECT_LT(worstAngle, 0.05); // degrees: two snorm16 in the octahedral square
    for (float d : {-0.99f, -0.25f, 0.0f, 0.3f, 0.999f}) {
        const std::uint32_t p = voxel::encodeDistanceFeature(d, 0.5f, 1234);
        EXPECT_NEAR(voxel::decodeDistance(p, 0.5f), d, 1.0 / 32767.0 + 1e-7);
        EXPECT_EQ(voxel::decodeFeature(p), 1234u);
    }
    // The sign survives: inside stays inside however close to the surface
    // (within one quantum of the value), outside and zero stay outside.
    for (float d : {-1e-30f, -1e-9f, -1e-6f, -1e-5f}) {
        const float back = voxel::decodeDistance(voxel::encodeDistanceFeature(d, 0.5f, 7), 0.5f);
        EXPECT_LT(back, 0.0f) << d;
        EXPECT_NEAR(back, d, 1.0 / 32767.0 + 1e-7);
    }
    for (float d : {0.0f, -0.0f, 1e-30f, 1e-6f})
        EXPECT_GE(voxel::decodeDistance(voxel::encodeDistanceFeature(d, 0.5f, 7), 0.5f), 0.0f) << d;
}

// --- The background voxelizer -------------------------------------------------

bool sameTile(const TileData* a, const TileData* b, const std::vector<Feature>& fa, const std::vector<Feature>& fb)
{
    if (!a || !b) return !a && !b;
    if (a->state != b->state || a->levels != b->levels || a->unresolved != b->unresolved ||
        a->nodes.size() != b->nodes.size() ||
        a->leafData.size() != b->leafData.size() || a->vertices.size() != b->vertices.size())
        return false;
    for (std::size_t i = 0; i < a->nodes.size(); ++i)
        if (a->nodes[i].header != b->nodes[i].header || a->nodes[i].mask() != b->nodes[i].mask()) return false;
    for (std::size_t i = 0; i < a->leafData.size(); ++i)
        if (a->leafData[i].corner != b->leafData[i].corner) return false;
    for (std::size_t i = 0; i < a->vertices.size(); ++i) {
        const auto& va = a->vertices[i];
        const auto& vb = b->vertices[i];
        if (va.normal != vb.normal || (va.distanceFeature & 0xFFFF) != (vb.distanceFeature & 0xFFFF)) return false;
        // Feature indices may differ between registries; the node they name may not.
        if (fa[voxel::decodeFeature(va.distanceFeature)].nodeId != fb[voxel::decodeFeature(vb.distanceFeature)].nodeId)
            return false;
    }
    return true;
}

// The snapshot equals a full voxelization of `doc` at the snapshot's depth.
void expectEqualsFullRebuild(const VoxelSnapshot& snap, const Document& doc)
{
    const Tape tape = compileTape(doc);
    const GridLayout g = GridLayout::choose(tape.bounds(), *doc.settings.featureSize);
    ASSERT_TRUE(snap.layout == g);
    const VoxelSnapshot full = voxelize(tape, g);
    long differing = 0;
    for (std::size_t i = 0; i < full.tiles.size(); ++i)
        if (!sameTile(snap.tiles[i].get(), full.tiles[i].get(), *snap.features, *full.features)) ++differing;
    EXPECT_EQ(differing, 0) << "tiles differing from a full rebuild";
}

Document editableDoc()
{
    return parse(R"({"id":"root","type":"union","blend":2,"children":[
        {"id":"d","type":"difference","children":[
          {"id":"board","type":"box","size":[80,40,12],"round":1},
          {"id":"hole1","type":"cylinder","radius":4,"height":20,"transform":{"translate":[-25,0,0]}},
          {"id":"hole2","type":"cylinder","radius":4,"height":20,"transform":{"translate":[25,0,0]}}]},
        {"id":"knob","type":"sphere","radius":6,"transform":{"translate":[0,0,8]}},
        {"id":"pins","type":"array","count":[4,1,1],"step":[12,0,0],"transform":{"translate":[-18,15,6]},
         "children":[{"id":"pin","type":"cylinder","radius":1.5,"height":8}]}]})",
                 0.5);
}

TEST(Voxelizer, RandomEditSequencesEqualAFullRebuild)
{
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 1, .threads = 2, .featureSize = 0.0, .onPublish = {}});
    Document doc = editableDoc();
    std::uint64_t rev = vox.setDocument(doc);
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
    test::RandomShapes r(99);
    for (int step = 0; step < 12; ++step) {
        const int kind = r.integer(0, 4);
        Node* n = nullptr;
        switch (kind) {
        case 0: // move a hole within the board (the grid keeps its size)
            n = doc.root.find(r.chance(0.5) ? "hole1" : "hole2");
            n->transform.translate.x = r.uniform(-30, 30);
            break;
        case 1:
            n = doc.root.find("knob");
            n->as<SphereParams>().radius = r.uniform(3, 7);
            break;
        case 2:
            n = doc.root.find("pin");
            n->visible = !n->visible;
            break;
        case 3: {
            n = doc.root.find("d");
            if (n->children.size() > 3 || r.chance(0.5)) {
                if (n->children.size() > 1) {
                    n->children.pop_back();
                }
            } else {
                Node h = makeNode(NodeType::Cylinder, "extra" + std::to_string(step));
                h.params = CylinderParams{2.5, 30};
                h.transform.translate = {r.uniform(-30, 30), r.uniform(-12, 12), 0};
                n->children.push_back(h);
            }
            break;
        }
        default:
            doc.root.find("pins")->as<ArrayParams>().step.x = r.uniform(8, 14);
            break;
        }
        rev = vox.setDocument(doc);
        // Half of the edits arrive before the previous one finished (cancellation).
        if (r.chance(0.5)) {
            ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
        }
    }
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
    const auto snap = vox.snapshot();
    EXPECT_TRUE(snap->complete);
    EXPECT_EQ(snap->documentRevision, rev);
    expectEqualsFullRebuild(*snap, doc);
}

// Requests that change the grid (an emptied part, a grown one) cancelled in
// quick succession, then back to the first: the unfinished tiles of a grid
// that is gone must not leak into the next one (they once did: a division by
// zero on the empty grid's dimensions, out-of-range tiles on others).
TEST(Voxelizer, CancelledGridChangesEqualAFullRebuild)
{
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 1, .threads = 2, .featureSize = 0.0, .onPublish = {}});
    Document doc = editableDoc();
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(60)));
    Document empty = doc;
    for (auto& c : empty.root.children) c.visible = false;
    Document grown = doc;
    grown.root.find("knob")->transform.translate.z += 80.0;
    // Each request is let start (its work under way, its unfinished tiles
    // recorded) before the next one cancels it.
    auto started = [&](std::uint64_t r) {
        for (int i = 0; i < 60000 && vox.progress().revision < r; ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        ASSERT_GE(vox.progress().revision, r);
    };
    std::uint64_t rev = 0;
    for (int round = 0; round < 4; ++round) {
        started(vox.setDocument(grown));
        started(vox.setDocument(empty));
        started(vox.setDocument(grown));
        rev = vox.setDocument(doc);
        if (round % 2) {
            ASSERT_TRUE(vox.waitFor(rev, false, std::chrono::seconds(60)));
        }
    }
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
    expectEqualsFullRebuild(*vox.snapshot(), doc);
    rev = vox.setDocument(empty);
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
    EXPECT_EQ(vox.snapshot()->layout.tileCount(), 0);
}

// --- Modelling only what the view needs ---------------------------------------


// A camera 30 mm in front of the board's left end, looking along +Y: it sees
// that end up close (fine voxels); the rest of the part is outside the
// picture (the coarse depth).
ViewRequirement closeUpView(const Aabb& bounds, bool rightEnd = false)
{
    ViewRequirement v;
    v.eye = glm::dvec3(rightEnd ? bounds.max.x - 10.0 : bounds.min.x + 10.0, bounds.min.y - 30.0, 5.0);
    v.forward = {0, 1, 0};
    v.right = {1, 0, 0};
    v.up = {0, 0, 1};
    v.halfHeight = std::tan(15.0 * 3.14159265358979 / 180.0);
    v.aspect = 16.0 / 9.0;
    v.imageHeight = 1080;
    return v;
}

// The snapshot's tiles are exactly buildTile's at the depth each has, and
// tiles without records are empty or full as a fresh build says.
void expectTilesMatchTheirDepth(const VoxelSnapshot& snap, const Tape& tape)
{
    TileBuildScratch scratch;
    long checked = 0;
    for (long i = 0; i < snap.layout.tileCount(); ++i) {
        const auto& t = snap.tiles[std::size_t(i)];
        const int levels = t && t->state == TileState::Surface ? t->levels : snap.layout.levels;
        auto again = buildTile(tape, snap.layout, snap.layout.tileCoord(i), levels, scratch);
        ASSERT_TRUE(again);
        if (!t || t->state != TileState::Surface) {
            const TileState was = t ? t->state : TileState::Empty;
            ASSERT_EQ(int(again->state), int(was)) << "tile " << i << " should have been rebuilt";
            continue;
        }
        ASSERT_TRUE(sameTile(t.get(), &*again, *snap.features, tape.features())) << "tile " << i;
        ++checked;
    }
    EXPECT_GT(checked, 0);
}

TEST(RefinementPlan, FineNearTheEyeCoarseFarAndOutOfView)
{
    const Document doc = editableDoc();
    const Tape tape = compileTape(doc);
    GridLimits limits;
    limits.maxTiles = 512;
    const GridLayout g = GridLayout::choose(tape.bounds(), 0.1, limits);
    ASSERT_GE(g.levels, 3);
    const VoxelSnapshot uniform = voxelize(tape, g);
    RefinementOptions none;
    const RefinementPlan full = planRefinement(g, uniform.tiles, none);
    for (std::size_t i = 0; i < uniform.tiles.size(); ++i) {
        if (uniform.tiles[i] && uniform.tiles[i]->state == TileState::Surface) {
            EXPECT_EQ(full.levels[i], g.levels) << "without a view, every tile goes to full depth";
        }
    }
    EXPECT_NEAR(double(full.estimatedBytes), double(uniform.bytes()), 0.01 * double(uniform.bytes()));

    RefinementOptions ro;
    ro.view = closeUpView(tape.bounds());
    ro.coarseLevels = 1;
    const RefinementPlan plan = planRefinement(g, uniform.tiles, ro);
    double nearestFull = 1e30, farthestFull = 0.0;
    int deepest = 0, shallowest = 99;
    for (std::size_t i = 0; i < uniform.tiles.size(); ++i) {
        if (!uniform.tiles[i] || uniform.tiles[i]->state != TileState::Surface) continue;
        const Aabb box = g.tileBox(g.tileCoord(long(i)));
        const int level = plan.levels[i];
        deepest = std::max(deepest, level);
        shallowest = std::min(shallowest, level);
        // Whatever depth, its voxels project to at most a pixel where it is seen.
        if (ro.view->sees(box) && level < g.levels) {
            EXPECT_LE(g.voxelSizeAt(level), ro.view->pixelSizeAt(ro.view->depthOf(box)) * 1.000001);
        }
        if (level == g.levels) {
            nearestFull = std::min(nearestFull, box.min.x);
            farthestFull = std::max(farthestFull, box.min.x);
        }
        if (!ro.view->sees(box)) {
            EXPECT_EQ(level, ro.coarseLevels) << "out of view: the coarse depth";
        }
    }
    EXPECT_EQ(deepest, g.levels) << "tiles next to the eye need the feature size";
    EXPECT_LT(shallowest, g.levels) << "far tiles need less";
    EXPECT_LT(plan.estimatedBytes, uniform.bytes() / 2);
}

TEST(RefinementPlan, TheBudgetCoarsensTheFarthestTilesFirst)
{
    const Tape tape = compileTape(editableDoc());
    GridLimits limits;
    limits.maxTiles = 512;
    const GridLayout g = GridLayout::choose(tape.bounds(), 0.25, limits);
    const VoxelSnapshot uniform = voxelize(tape, g);
    RefinementOptions ro;
    ro.focus = glm::dvec3(-40, 0, 0);
    ro.memoryBudgetBytes = uniform.bytes() / 3;
    const RefinementPlan plan = planRefinement(g, uniform.tiles, ro);
    EXPECT_LE(plan.estimatedBytes, ro.memoryBudgetBytes);
    EXPECT_GT(plan.coarsenedForBudget, 0u);
    double nearestCoarsened = 1e30, farthestKept = 0.0;
    for (std::size_t i = 0; i < uniform.tiles.size(); ++i) {
        if (!uniform.tiles[i] || uniform.tiles[i]->state != TileState::Surface) continue;
        const double d = glm::length(g.tileBox(g.tileCoord(long(i))).center() - ro.focus);
        if (plan.levels[i] < g.levels) {
            nearestCoarsened = std::min(nearestCoarsened, d);
        } else {
            farthestKept = std::max(farthestKept, d);
        }
    }
    EXPECT_GE(nearestCoarsened, farthestKept) << "a nearer tile was coarsened while a farther one kept its depth";
}

TEST(Voxelizer, TheCoarsePassKeepsToTheMemoryBudget)
{
    // A feature size far too fine for the part: the coarse pass built every
    // tile at its depth whatever the budget, and the application grew by
    // 250 MB a second on a 2 m panel at 2 um until the system killed it.
    // Here a cabinet side at 10 um (the coarse pass alone about 280 MB)
    // under a budget of 16 MB: every snapshot published keeps to it, and
    // the panel shows.
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"settings":{"feature_size":0.01},
        "root":{"id":"side","type":"box","size":[600,300,18]}})",
                                         "side.kerf");
    constexpr std::size_t kBudget = std::size_t(16) << 20;
    std::atomic<std::size_t> largest{0}, published{0};
    VoxelizerOptions options;
    options.threads = 2;
    options.memoryBudgetBytes = kBudget;
    options.onPublish = [&](std::shared_ptr<const VoxelSnapshot> s) {
        largest = std::max(largest.load(), s->bytes());
        ++published;
    };
    Voxelizer vox(options);
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(120)));
    EXPECT_GE(published.load(), 1u);
    EXPECT_LE(largest.load(), kBudget);
    const auto s = vox.snapshot();
    EXPECT_GT(s->coarsenedForBudget, 0u) << "the status bar says the budget is reached";
    EXPECT_GT(s->populatedVoxels(), 0u) << "the panel shows";
}

TEST(Voxelizer, RefinesWhatTheViewNeedsAndFollowsTheView)
{
    Document doc = editableDoc();
    doc.settings.featureSize = 0.1;
    const Tape tape = compileTape(doc);
    GridLimits limits;
    limits.maxTiles = 512;
    Voxelizer vox({.limits = limits, .coarseLevelDrop = 2, .threads = 2, .featureSize = 0.0, .onPublish = {}});
    ViewRequirement left = closeUpView(tape.bounds());
    vox.setView(left);
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(120)));
    const auto a = vox.snapshot();
    expectTilesMatchTheirDepth(*a, tape);
    const VoxelSnapshot uniform = voxelize(tape, a->layout);
    std::printf("close-up: %zu bytes against %zu uniform, %zu tiles out of view\n", a->bytes(), uniform.bytes(),
                a->outsideView);
    EXPECT_GT(a->outsideView, 0u);
    EXPECT_LT(a->bytes(), uniform.bytes() * 3 / 5) << "a close-up needs far less than the whole part at full depth";

    // Turn around: look at the right end from beyond it. Tiles there refine.
    const ViewRequirement right = closeUpView(tape.bounds(), true);
    const std::uint64_t before = vox.lastStats().revision;
    vox.setView(right);
    ASSERT_TRUE(QuietWait(vox, before + 1));
    const auto b = vox.snapshot();
    EXPECT_GT(vox.lastStats().refinedTiles, 0u);
    EXPECT_EQ(vox.lastStats().dirtyTiles, 0u) << "the document did not change";
    expectTilesMatchTheirDepth(*b, tape);
    int deepRight = 0;
    for (long i = 0; i < b->layout.tileCount(); ++i) {
        const auto& t = b->tiles[std::size_t(i)];
        if (t && t->state == TileState::Surface && t->levels == b->layout.levels &&
            b->layout.tileBox(b->layout.tileCoord(i)).max.x > tape.bounds().max.x - 5.0)
            ++deepRight;
    }
    EXPECT_GT(deepRight, 0) << "the right end, now near the eye, is at full depth";
}

// Edits while tiles of several depths coexist (a view keeps far tiles
// coarse): every tile still equals a fresh build of the final document at
// its depth (the dirty region of each depth reaches as far as its samples).
TEST(Voxelizer, EditsAmongTilesOfMixedDepthsEqualFreshBuilds)
{
    Document doc = editableDoc();
    doc.settings.featureSize = 0.1;
    GridLimits limits;
    limits.maxTiles = 512;
    Voxelizer vox({.limits = limits, .coarseLevelDrop = 2, .threads = 2, .featureSize = 0.0, .onPublish = {}});
    vox.setView(closeUpView(compileTape(doc).bounds()));
    std::uint64_t rev = vox.setDocument(doc);
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(120)));
    test::RandomShapes r(7);
    for (int step = 0; step < 6; ++step) {
        Node* n = doc.root.find(r.chance(0.5) ? "hole1" : "knob");
        n->transform.translate.x = r.uniform(-30, 30);
        n->transform.translate.y = r.uniform(-5, 5);
        rev = vox.setDocument(doc);
        if (r.chance(0.5)) {
            ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(120)));
        }
    }
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(120)));
    const auto snap = vox.snapshot();
    std::set<int> depths;
    for (const auto& t : snap->tiles)
        if (t && t->state == TileState::Surface) depths.insert(t->levels);
    EXPECT_GT(depths.size(), 1u) << "the view should leave tiles of several depths";
    expectTilesMatchTheirDepth(*snap, compileTape(doc));
}

TEST(Voxelizer, StaysWithinTheMemoryBudgetAndSaysSo)
{
    Document doc = editableDoc();
    doc.settings.featureSize = 0.1;
    const Tape tape = compileTape(doc);
    GridLimits limits;
    limits.maxTiles = 512;
    const VoxelSnapshot uniform = voxelize(tape, GridLayout::choose(tape.bounds(), 0.1, limits));
    const std::size_t budget = uniform.bytes() / 4;
    Voxelizer vox({.limits = limits, .coarseLevelDrop = 1, .threads = 2, .featureSize = 0.0, .onPublish = {},
                   .memoryBudgetBytes = budget});
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(120)));
    const auto snap = vox.snapshot();
    EXPECT_GT(snap->coarsenedForBudget, 0u);
    EXPECT_EQ(vox.lastStats().coarsenedForBudget, snap->coarsenedForBudget);
    // The estimate scales the coarse pass by 16 per level: the real bytes stay near it.
    EXPECT_LE(snap->bytes(), budget * 5 / 4);
    expectTilesMatchTheirDepth(*snap, tape);
}

TEST(Voxelizer, AnEditRebuildsOnlyTheTilesItReaches)
{
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 1, .threads = 2, .featureSize = 0.0, .onPublish = {}});
    Document doc = editableDoc();
    std::uint64_t rev = vox.setDocument(doc);
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
    const auto before = vox.snapshot();
    doc.root.find("hole1")->transform.translate.x = -22.0; // move one hole by 3 mm
    rev = vox.setDocument(doc);
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
    const auto after = vox.snapshot();
    const VoxelizerStats stats = vox.lastStats();
    EXPECT_GT(stats.dirtyTiles, 0u);
    EXPECT_LT(stats.dirtyTiles * 4, stats.tilesInGrid) << "a small edit rebuilt most of the grid";
    // Tiles outside the edit's reach are the very same objects as before.
    const Aabb reach = Aabb{{-29.5, -4.5, -10.5}, {-17.5, 4.5, 10.5}}.grown(4 * after->layout.voxelSize);
    std::size_t untouchedShared = 0, touched = 0;
    for (long i = 0; i < after->layout.tileCount(); ++i) {
        if (after->layout.tileBox(after->layout.tileCoord(i)).overlaps(reach)) {
            ++touched;
            continue;
        }
        EXPECT_EQ(after->tiles[std::size_t(i)], before->tiles[std::size_t(i)]) << "tile " << i << " was rebuilt";
        ++untouchedShared;
    }
    EXPECT_GT(untouchedShared, touched);
    expectEqualsFullRebuild(*after, doc);
}

// Parameters (issue 16): an edit of a parameter changes the numbers of the
// features whose expressions use it, and only their tiles are rebuilt.
TEST(Voxelizer, AParameterEditRebuildsOnlyTheTilesOfTheFeaturesThatUseIt)
{
    const std::string text = R"({"format":"kerf","version":1,"settings":{"feature_size":0.5},
        "parameters":[{"name":"hole","expression":"4mm","unit":"length"},{"name":"board","expression":"12"}],
        "root":{"id":"root","type":"union","children":[
          {"id":"d","type":"difference","children":[
            {"id":"top","type":"box","size":[80,40,"board"],"round":1},
            {"id":"hole1","type":"cylinder","radius":"hole","height":20,"transform":{"translate":[-25,0,0]}}]},
          {"id":"far","type":"box","size":[10,10,10],"transform":{"translate":[0,0,40]}}]}})";
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 1, .threads = 2, .featureSize = 0.0, .onPublish = {}});
    Document doc = Document::parse(text, "parametric.kerf");
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(60)));
    const auto before = vox.snapshot();
    doc.parameters[0].expression = "5mm"; // the hole, 1 mm wider
    doc = doc.resolved();
    ASSERT_EQ(doc.root.find("hole1")->as<CylinderParams>().radius, 5.0);
    ASSERT_TRUE(vox.waitFor(vox.setDocument(doc), true, std::chrono::seconds(60)));
    const auto after = vox.snapshot();
    const VoxelizerStats stats = vox.lastStats();
    EXPECT_GT(stats.dirtyTiles, 0u);
    EXPECT_LT(stats.dirtyTiles * 4, stats.tilesInGrid) << "a parameter of one hole rebuilt most of the grid";
    // The far box and the board away from the hole are the very same tiles as before.
    const Aabb reach = Aabb{{-30, -5, -10}, {-20, 5, 10}}.grown(4 * after->layout.voxelSize);
    for (long i = 0; i < after->layout.tileCount(); ++i) {
        if (!after->layout.tileBox(after->layout.tileCoord(i)).overlaps(reach)) {
            EXPECT_EQ(after->tiles[std::size_t(i)], before->tiles[std::size_t(i)]) << "tile " << i << " was rebuilt";
        }
    }
    expectEqualsFullRebuild(*after, doc);
}

TEST(Voxelizer, PublicationsAreConsistentAndNeverHoldPartialTiles)
{
    std::mutex m;
    std::vector<std::shared_ptr<const VoxelSnapshot>> published;
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 2, .threads = 2, .featureSize = 0.0,
                   .onPublish = [&](std::shared_ptr<const VoxelSnapshot> s) {
                       std::lock_guard lock(m);
                       published.push_back(std::move(s));
                   }});
    std::vector<Document> docs;
    Document doc = editableDoc();
    for (int i = 0; i < 5; ++i) {
        doc.root.find("knob")->as<SphereParams>().radius = 4.0 + i;
        docs.push_back(doc);
        vox.setDocument(doc); // no waiting: most of these are cancelled
    }
    ASSERT_TRUE(vox.waitFor(5, true, std::chrono::seconds(60)));
    std::lock_guard lock(m);
    ASSERT_FALSE(published.empty());
    std::uint64_t lastVersion = 0;
    for (const auto& s : published) {
        EXPECT_GT(s->version, lastVersion);
        lastVersion = s->version;
        // Every tile equals a fresh build of its revision's document at its depth.
        const Document& d = docs[s->documentRevision - 1];
        const Tape tape = compileTape(d);
        TileBuildScratch scratch;
        for (long i = 0; i < s->layout.tileCount(); ++i) {
            const auto& t = s->tiles[std::size_t(i)];
            const int levels = t ? t->levels : s->layout.levels;
            auto fresh = buildTile(tape, s->layout, s->layout.tileCoord(i), levels, scratch);
            ASSERT_TRUE(fresh.has_value());
            // Null where the voxelizer keeps nothing: empty, and settled at this depth.
            const bool kept = fresh->state != TileState::Empty || (fresh->unresolved && levels < s->layout.levels);
            const TileData* f = kept ? &*fresh : nullptr;
            ASSERT_TRUE(sameTile(t.get(), f, *s->features, *tape.sharedFeatures()))
                << "revision " << s->documentRevision << " tile " << i;
        }
    }
    EXPECT_TRUE(published.back()->complete);
    EXPECT_EQ(published.back()->documentRevision, 5u);
}

// A newcomer's drawer: its 6 mm bottom, from z = 10 to 16, lay between the
// corners of the coarse pass's 8 mm voxels (at z = 8 and 16), so its tiles
// came out empty there, and the fine pass refined only tiles with a surface:
// the bottom never showed in the view (kerf render, which builds at full
// depth at once, drew it). A tile empty only at its depth is refined.
TEST(Voxelizer, APlateBetweenTheCoarseVoxelsCornersIsFoundByTheFinePass)
{
    Document doc = parse(R"({"id":"root","type":"union","children":[
        {"id":"front","type":"box","size":[600,18,160],"transform":{"translate":[0,9,80]}},
        {"id":"back","type":"box","size":[576,12,144],"transform":{"translate":[0,444,88]}},
        {"id":"bottom","type":"box","size":[587,432,6],"transform":{"translate":[0,234,13]}}]})",
                         0.5);
    std::mutex m;
    std::shared_ptr<const VoxelSnapshot> preview; // the first publication: the coarse pass's
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 2, .threads = 2, .featureSize = 0.0,
                   .onPublish = [&](std::shared_ptr<const VoxelSnapshot> s) {
                       std::lock_guard lock(m);
                       if (!preview) preview = std::move(s);
                   }});
    const std::uint64_t rev = vox.setDocument(doc);
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
    const auto snap = vox.snapshot();
    ASSERT_TRUE(snap->complete);
    // Already in the preview: the tile under the bottom's middle has its
    // surface (built a level deeper than the coarse pass's), so the board
    // does not vanish from the view while the fine pass runs.
    {
        std::lock_guard lock(m);
        ASSERT_TRUE(preview && !preview->complete);
        const glm::ivec3 under = glm::ivec3(glm::floor((glm::dvec3(0, 234, 13) - preview->layout.origin) /
                                                       preview->layout.tileSize));
        const auto& tile = preview->tiles[std::size_t(preview->layout.tileIndex(under))];
        ASSERT_TRUE(tile);
        EXPECT_EQ(tile->state, TileState::Surface);
        EXPECT_LT(tile->levels, preview->layout.levels);
    }
    // The scenario: the coarse voxels' corners step over the bottom.
    ASSERT_EQ(snap->layout.levels, 3);
    const double coarseVoxel = snap->layout.voxelSizeAt(1);
    const double below = std::floor((10.0 - snap->layout.origin.z) / coarseVoxel) * coarseVoxel + snap->layout.origin.z;
    ASSERT_GE(below + coarseVoxel, 16.0) << "the bottom should lie between two coarse corners";
    expectEqualsFullRebuild(*snap, doc);
}

TEST(Voxelizer, CoarsePublicationComesFirst)
{
    std::mutex m;
    std::vector<std::pair<bool, int>> seen; // complete, shallowest depth
    Voxelizer vox({.limits = {}, .coarseLevelDrop = 1, .threads = 2, .featureSize = 0.0,
                   .onPublish = [&](std::shared_ptr<const VoxelSnapshot> s) {
                       std::lock_guard lock(m);
                       seen.emplace_back(s->complete, s->shallowestLevels());
                   }});
    const auto rev = vox.setDocument(editableDoc());
    ASSERT_TRUE(vox.waitFor(rev, true, std::chrono::seconds(60)));
    std::lock_guard lock(m);
    ASSERT_GE(seen.size(), 2u);
    EXPECT_FALSE(seen.front().first);
    EXPECT_TRUE(seen.back().first);
    EXPECT_LT(seen.front().second, seen.back().second);
}

TEST(DirtyRegion, ColourAndNameChangesNeedNoRebuild)
{
    Document a = editableDoc(), b = a;
    b.root.find("knob")->color = Color{200, 10, 10};
    b.root.find("board")->name = "Seat board";
    const DirtyRegion r = dirtyRegion(a, b, 1.0);
    EXPECT_FALSE(r.geometryChanged);
    EXPECT_TRUE(r.boxes.empty());
}

} // namespace
} // namespace kerf

// Detail thinner than a cell that the cells' corners never see (issue 13):
// found by the mesher, measured, and answered with the feature size that
// resolves it; contacts and thick parts reaching into a cell are not detail.

#include "kerf/document/Document.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace kerf {
namespace {

constexpr double kPi = 3.14159265358979323846;

Document parse(const std::string& root)
{
    return Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf");
}

struct Meshed {
    Mesh mesh;
    MeshStats stats;
};

Meshed meshAt(const Document& doc, double featureSize)
{
    MeshOptions o;
    o.featureSize = featureSize;
    Meshed m;
    std::optional<Mesh> mesh = meshPart(doc, o, {}, &m.stats);
    EXPECT_TRUE(mesh.has_value());
    if (mesh) m.mesh = std::move(*mesh);
    return m;
}

TEST(HiddenDetail, AShellThinnerThanACellIsReportedAndTheSizeGivenResolvesIt)
{
    // A 0.05 mm shell at 0.1 mm cells: most lattice points miss it, and the
    // mesh is thousands of fragments.
    const Document doc = parse(R"({"id":"s","type":"shell","thickness":0.05,"children":[
        {"id":"b","type":"sphere","radius":3}]})");
    const Meshed coarse = meshAt(doc, 0.1);
    EXPECT_GT(checkMesh(coarse.mesh).components, 100u);
    ASSERT_GT(coarse.stats.hiddenDetailCells, 0u);
    EXPECT_TRUE(coarse.stats.hiddenDetailIsMaterial);
    EXPECT_NEAR(coarse.stats.hiddenDetailThickness, 0.05, 0.001);
    EXPECT_NEAR(glm::length(coarse.stats.hiddenDetailAt), 3.0 - 0.025, 0.01); // inside the wall
    const double finer = finerFeatureSize(coarse.stats);
    EXPECT_DOUBLE_EQ(finer, 0.02);

    const Meshed fine = meshAt(doc, finer);
    EXPECT_EQ(fine.stats.hiddenDetailCells, 0u);
    EXPECT_EQ(finerFeatureSize(fine.stats), 0.0);
    const MeshReport r = checkMesh(fine.mesh);
    EXPECT_TRUE(r.closed() && r.manifold() && r.oriented());
    EXPECT_EQ(r.components, 2u); // the outer and the inner face of one wall
    const double exact = 4.0 / 3.0 * kPi * (27.0 - std::pow(2.95, 3));
    EXPECT_NEAR(r.volume, exact, 0.03 * exact);
}

TEST(HiddenDetail, TwoBoardsHalfAMillimetreApartAreNeverFusedWithoutAWord)
{
    // Two boards 0.5 mm apart at 2 mm cells, the gap moved across a cell in
    // steps of a quarter millimetre: where no lattice point falls in it the cells fuse the boards,
    // and that must be reported as a gap (a property of every position).
    int hidden = 0;
    for (int k = 0; k < 8; ++k) {
        const double shift = 0.25 * k;
        char root[512];
        // Board a from x = -20 to the gap, b from the gap to 20: the part's
        // bounds, and with them the lattice, stay where they are.
        const double lo = shift - 0.25, hi = shift + 0.25;
        std::snprintf(root, sizeof root, R"({"id":"u","type":"union","children":[
            {"id":"a","type":"box","size":[%.17g,30,18],"transform":{"translate":[%.17g,0,0]}},
            {"id":"b","type":"box","size":[%.17g,30,18],"transform":{"translate":[%.17g,0,0]}}]})",
                      lo + 20.0, 0.5 * (lo - 20.0), 20.0 - hi, 0.5 * (hi + 20.0));
        const Meshed coarse = meshAt(parse(root), 2.0);
        const std::size_t components = checkMesh(coarse.mesh).components;
        if (components == 2) continue; // the lattice saw the gap
        ++hidden;
        ASSERT_GT(coarse.stats.hiddenDetailCells, 0u) << "shift " << shift << ": fused without a report";
        EXPECT_FALSE(coarse.stats.hiddenDetailIsMaterial);
        EXPECT_NEAR(coarse.stats.hiddenDetailThickness, 0.5, 0.01);
        EXPECT_NEAR(coarse.stats.hiddenDetailAt.x, shift, 0.01);
        const double finer = finerFeatureSize(coarse.stats);
        EXPECT_DOUBLE_EQ(finer, 0.2);
        if (hidden == 1) {
            const Meshed fine = meshAt(parse(root), finer);
            EXPECT_EQ(fine.stats.hiddenDetailCells, 0u);
            EXPECT_EQ(checkMesh(fine.mesh).components, 2u);
        }
    }
    EXPECT_GT(hidden, 0) << "no position hid the gap: the test tests nothing";
}

TEST(HiddenDetail, ThinWallsAndSlotsOfEveryOrientationAreFound)
{
    struct Case {
        const char* part;
        bool material;
        double thickness;
    };
    const Case cases[] = {
        // A plate 0.3 mm thick, tilted.
        {R"({"id":"p","type":"box","size":[30,20,0.3],"transform":{"rotate":[3,7,0]}})", true, 0.3},
        // A comb of 0.35 mm slots, turned 20 degrees.
        {R"({"id":"d","type":"difference","children":[{"id":"b","type":"box","size":[20,10,10]},
            {"id":"a","type":"array","count":[12,1,1],"step":[1.5,0,0],"transform":{"translate":[-8.25,0,3]},
             "children":[{"id":"slot","type":"box","size":[0.35,12,8],"transform":{"rotate":[0,0,20]}}]}]})",
         false, 0.35},
        // A pin 0.4 mm across.
        {R"({"id":"c","type":"cylinder","radius":0.2,"height":20,"transform":{"rotate":[10,20,30]}})", true, 0.4},
    };
    for (const Case& c : cases) {
        for (const double h : {1.0, 0.7}) {
            const Meshed m = meshAt(parse(c.part), h);
            const std::string what = std::string(c.part).substr(0, 50) + " at " + std::to_string(h);
            ASSERT_GT(m.stats.hiddenDetailCells, 0u) << what;
            EXPECT_EQ(m.stats.hiddenDetailIsMaterial, c.material) << what;
            EXPECT_NEAR(m.stats.hiddenDetailThickness, c.thickness, 0.02) << what;
            EXPECT_LE(finerFeatureSize(m.stats), 0.5 * c.thickness) << what;
        }
    }
}

TEST(HiddenDetail, ContactsAndThickPartsReachingIntoACellAreNotDetail)
{
    const char* parts[] = {
        // Two spheres touching: the crevice around the contact narrows to
        // nothing at every cell size.
        R"({"id":"u","type":"union","children":[{"id":"a","type":"sphere","radius":5},
            {"id":"b","type":"sphere","radius":5,"transform":{"translate":[10,0,0]}}]})",
        // A round rail lying on a board (a line contact).
        R"({"id":"u","type":"union","children":[{"id":"a","type":"box","size":[40,30,6]},
            {"id":"b","type":"cylinder","radius":4,"height":36,"transform":{"translate":[0.3,0,7],"rotate":[0,90,0]}}]})",
        // A rail entering a stile, both with rounded edges: a small notch
        // where the roundings cross.
        R"({"id":"u","type":"union","children":[
            {"id":"s","type":"box","size":[20,60,20],"round":1.5,"transform":{"translate":[-10,0,10]}},
            {"id":"r","type":"box","size":[22,20,20],"round":1.5,"transform":{"translate":[10,10,10]}}]})",
        // Thick parts, turned so that their edges and caps reach into cells.
        R"({"id":"b","type":"box","size":[18,40,30],"transform":{"rotate":[17,29,41]}})",
        R"({"id":"s","type":"sphere","radius":7.3})",
        R"({"id":"d","type":"difference","children":[{"id":"b","type":"box","size":[30,30,18]},
            {"id":"h","type":"cylinder","radius":2.5,"height":13,"transform":{"translate":[3,4,3],"rotate":[0,90,0]}}]})",
    };
    for (const char* part : parts) {
        for (const double h : {1.0, 0.7}) {
            const Meshed m = meshAt(parse(part), h);
            EXPECT_EQ(m.stats.hiddenDetailCells, 0u)
                << std::string(part).substr(0, 60) << " at " << h << ": " << m.stats.hiddenDetailThickness << " mm at "
                << m.stats.hiddenDetailAt.x << ", " << m.stats.hiddenDetailAt.y << ", " << m.stats.hiddenDetailAt.z;
        }
    }
}

TEST(HiddenDetail, TheBookshelfSideAtFourMillimetresHidesItsOneMillimetreWall)
{
    // Between the toe-kick notch (top at z = 70) and the bottom dado (from
    // z = 71) one millimetre of panel remains, at x 1..9, y 10..60.
    const Document doc = Document::load(std::string(KERF_EXAMPLES_DIR) + "/bookshelf-side.kerf");
    const Meshed m = meshAt(doc, 4.0);
    ASSERT_GT(m.stats.hiddenDetailCells, 0u);
    EXPECT_TRUE(m.stats.hiddenDetailIsMaterial);
    EXPECT_NEAR(m.stats.hiddenDetailThickness, 1.0, 0.01);
    const glm::dvec3 at = m.stats.hiddenDetailAt;
    EXPECT_TRUE(at.x > 1.0 && at.x < 9.0 && at.y > 10.0 && at.y < 60.0 && at.z > 70.0 && at.z < 71.0)
        << at.x << ", " << at.y << ", " << at.z;
    EXPECT_DOUBLE_EQ(finerFeatureSize(m.stats), 0.5);
}

} // namespace
} // namespace kerf

// The export (issue 13): meshes sized by a tolerance, square edges, and
// files that a slicer reads as one closed solid.

#include "kerf/accuracy/SurfaceDistance.hpp"
#include "kerf/document/Affine.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/mesher/MeshFile.hpp"
#include "kerf/mesher/SelfIntersections.hpp"
#include "support/MeshFileReader.hpp"
#include "TriangleClearance.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include <glm/glm.hpp>

#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <unistd.h>

namespace kerf {
namespace {

Document parse(const std::string& root)
{
    return Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf");
}

struct Case {
    const char* name;
    const char* root;
    double featureSize;
};
// ctest's test names carry the parameter as printed: the name, not the bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class ToleranceCases : public ::testing::TestWithParam<Case> {};

INSTANTIATE_TEST_SUITE_P(
    Parts, ToleranceCases,
    ::testing::Values(
        Case{"sphere", R"({"id":"s","type":"sphere","radius":10})", 1.0},
        Case{"box", R"({"id":"b","type":"box","transform":{"translate":[0.3,0.2,0.1],"rotate":[10,20,30]},"size":[40,30,18]})", 2.0},
        Case{"cylinder", R"({"id":"c","type":"cylinder","transform":{"rotate":[0,90,0]},"radius":7,"height":60})", 2.0},
        Case{"foot", R"({"id":"i","type":"intersection","children":[{"id":"c","type":"cone","transform":{"translate":[0.3,0.2,10]},"radius_bottom":14,"radius_top":20,"height":40},{"id":"h","type":"halfspace","normal":[0,0,-1],"offset":0}]})", 2.0},
        Case{"holed", R"({"id":"d","type":"difference","children":[{"id":"b","type":"box","size":[60,40,18]},{"id":"c","type":"cylinder","transform":{"translate":[5.3,2.1,4]},"radius":4,"height":20}]})", 1.0}),
    [](const auto& test) { return std::string(test.param.name); });

TEST_P(ToleranceCases, KeepsToTheTolerance)
{
    const Document doc = parse(GetParam().root);
    MeshOptions o;
    o.featureSize = GetParam().featureSize;
    o.tolerance = 0.01;
    MeshStats stats;
    const auto mesh = meshPart(doc, o, {}, &stats);
    ASSERT_TRUE(mesh);
    std::printf("lattice %zu -> %zu triangles, collapses %llu, splits %llu, worst %g, over %llu\n",
                stats.latticeTriangles, stats.triangles, (unsigned long long)stats.collapses,
                (unsigned long long)stats.splits, stats.worstSample, (unsigned long long)stats.trianglesOverTolerance);
    const MeshReport r = checkMesh(*mesh);
    EXPECT_TRUE(r.watertight());
    EXPECT_LE(stats.worstSample, o.tolerance);
}


// ---------------------------------------------------------------------------
// The written file, read back by the suite's own reader (support/
// MeshFileReader: STL welded by float32 position, 3MF by index), against
// the exact surface.

std::filesystem::path scratch(const std::string& name)
{
    const auto dir = std::filesystem::temp_directory_path() / ("kerf-export-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir / name;
}

struct FileCase {
    const char* name;
    std::string root;
    double featureSize;
    double volume; // mm^3, closed form; 0 where there is none
    /// Whether the simplified export keeps every triangle within the
    /// tolerance. Not yet where bodies touch along an edge, where faces
    /// meet at a tangent, and where float32 cannot hold the tolerance (issue
    /// 13, open; the exporter says so, and these cases check that what it
    /// says is what the file holds).
    bool holdsTolerance = true;
    /// The same as 3MF, which writes a part far from the origin next to its
    /// middle (float32 there steps by nanometres, not micrometres).
    bool holdsToleranceAs3mf = holdsTolerance;
};
void PrintTo(const FileCase& c, std::ostream* os) { *os << c.name; }

// Parts built to break an exporter: bodies touching face to face and edge to
// edge, tools flush with the body's faces, faces on lattice planes and corners
// on lattice points, a wall of about one cell, a blend, faces meeting at a
// tangent, the same part far from the origin.
std::vector<FileCase> fileCases()
{
    std::vector<FileCase> cases = {
        {"touching_faces", R"({"id":"u","type":"union","children":[
            {"id":"a","type":"box","size":[40,20,18],"transform":{"translate":[-20,0,0]}},
            {"id":"b","type":"box","size":[40,20,18],"transform":{"translate":[20,0,0]}}]})",
         1.0, 80.0 * 20.0 * 18.0},
        // Two boards that share only an edge: the exact solid is not a
        // 2-manifold there, and the file (which must be) keeps a few
        // triangles over the tolerance where a thin bridge joins the two (16
        // at 0.01 mm, up to 0.21 mm off).
        {"touching_edges", R"({"id":"u","type":"union","children":[
            {"id":"a","type":"box","size":[20,20,18],"transform":{"translate":[-10,-10,0]}},
            {"id":"b","type":"box","size":[20,20,18],"transform":{"translate":[10,10,0]}}]})",
         1.0, 0.0, false},
        {"flush_tool", R"({"id":"d","type":"difference","children":[
            {"id":"b","type":"box","size":[60,40,18]},
            {"id":"t","type":"box","size":[20,40,6],"transform":{"translate":[0,0,6]}}]})",
         1.0, 60.0 * 40.0 * 18.0 - 20.0 * 40.0 * 6.0},
        {"lattice_faces", R"({"id":"b","type":"box","size":[40,30,20]})", 0.5, 40.0 * 30.0 * 20.0},
        {"lattice_faces_coarse", R"({"id":"b","type":"box","size":[40,30,20]})", 2.0, 40.0 * 30.0 * 20.0},
        {"thin_wall", R"({"id":"s","type":"shell","thickness":1.5,"children":[
            {"id":"b","type":"box","size":[40,30,20],"round":3}]})",
         1.0, 0.0},
        {"blend", R"({"id":"u","type":"union","blend":4,"children":[
            {"id":"a","type":"box","size":[40,20,18]},
            {"id":"c","type":"cylinder","radius":6,"height":40,"transform":{"translate":[0,0,20]}}]})",
         1.0, 0.0},
        {"sphere", R"({"id":"s","type":"sphere","radius":10})", 1.0, 4.0 / 3.0 * 3.14159265358979 * 1000.0},
        // A board whose faces and edges lie on the planes and lines of the
        // lattice centred on it: there the marching cubes cut its edges off
        // by up to 0.29 mm, the simplification grew the cuts into fans from
        // a vertex off the edge, and no split mended those (11 triangles up
        // to 0.22 mm off at 0.01 mm). Now exact, in its 12 triangles
        // (ExportedFileSimplified.ABoardIsItsTwelveTriangles).
        {"board_on_lattice", R"({"id":"b","type":"box","size":[18,100,100],"transform":{"translate":[0,50,50]}})", 1.0,
         18.0 * 100.0 * 100.0},
        // A shelf-pin hole whose rim lies on the face's lattice plane and
        // whose sides touch lattice planes (y = 28 and 33).
        {"pin_hole_on_lattice", R"({"id":"d","type":"difference","children":[
            {"id":"b","type":"box","size":[18,60,100],"transform":{"translate":[0,30,50]}},
            {"id":"h","type":"cylinder","radius":2.5,"height":13,"transform":{"translate":[3.5,30.5,50],"rotate":[0,90,0]}}]})",
         1.0, 18.0 * 60.0 * 100.0 - 3.14159265358979 * 6.25 * 12.0},
        // A square pommel on a turning of its width (the turned leg's top):
        // at each of the four tangent points the pommel's underside is a
        // sliver between two sharp edges that meet there. At 0.01 mm and
        // 0.5 mm cells, 79 triangles over (0.025 mm) before the stuck
        // triangles' disks were triangulated anew, 11 after (0.018 mm),
        // where the mesh lacks a vertex on one of the two edges.
        {"tangent_faces", R"({"id":"u","type":"union","children":[
            {"id":"p","type":"box","size":[30,30,20],"transform":{"translate":[0,0,20]}},
            {"id":"t","type":"cylinder","radius":15,"height":20,"transform":{"translate":[0,0,5]}}]})",
         0.5, 30.0 * 30.0 * 20.0 + 3.14159265358979 * 225.0 * 15.0, false},
    };
    // The plate with holes at the origin and 100 m away.
    const char* plate = R"({"id":"d","type":"difference","transform":{"translate":[%s]},"children":[
            {"id":"b","type":"box","size":[60,40,18]},
            {"id":"c","type":"cylinder","radius":4,"height":20,"transform":{"translate":[10,0,0]}}]})";
    for (const char* at : {"0,0,0", "100000,-100000,100000"}) {
        char buf[512];
        std::snprintf(buf, sizeof buf, plate, at);
        // 100 m away float32 steps by 7.8 um, most of the 0.01 mm
        // tolerance: STL's coordinates leave triangles over it (17; kerf
        // export refuses that tolerance for STL and names 3MF). As 3MF it
        // holds: the mesher keeps its vertices apart by the spacing of the
        // 3MF's coordinates, written next to the part (17 over before, when
        // it went by the world's).
        const bool far = at[0] != '0';
        cases.push_back(
            {far ? "plate_far" : "plate", buf, 1.0, 60.0 * 40.0 * 18.0 - 3.14159265358979 * 16.0 * 18.0, !far, true});
    }
    return cases;
}

class ExportedFile : public ::testing::TestWithParam<FileCase> {};

INSTANTIATE_TEST_SUITE_P(Parts, ExportedFile, ::testing::ValuesIn(fileCases()),
                         [](const auto& test) { return std::string(test.param.name); });

TEST_P(ExportedFile, ReadsBackAsTheClosedSolidInEveryFormat)
{
    const FileCase& c = GetParam();
    const Document doc = parse(c.root);
    const Tape tape = compileTape(doc);
    constexpr double kTolerance = 0.01;
    MeshOptions plain;
    plain.featureSize = c.featureSize;
    const auto reference = meshPart(doc, plain); // the topology, from the marching cubes
    ASSERT_TRUE(reference);
    const MeshReport expected = checkMesh(*reference);
    ASSERT_TRUE(expected.watertight());

    // The export's lattice in every format; the lattice centred on the part
    // (latticeShift 0, where these parts' round coordinates fall on lattice
    // planes, lines and points: the exact zeros) as binary STL, held to
    // everything but the tolerance.
    struct Run {
        MeshFileFormat format;
        bool centred;
    };
    for (const Run run : {Run{MeshFileFormat::BinaryStl, false}, Run{MeshFileFormat::AsciiStl, false},
                          Run{MeshFileFormat::ThreeMf, false}, Run{MeshFileFormat::BinaryStl, true}}) {
        const MeshFileFormat format = run.format;
        MeshOptions o = plain;
        o.tolerance = kTolerance;
        if (run.centred) o.latticeShift = glm::dvec3(0.0);
        const std::string what = std::string(c.name) + " as " + describe(format) + (run.centred ? ", centred" : "");
        const auto file = scratch(std::string(c.name) + (format == MeshFileFormat::ThreeMf ? ".3mf" : ".stl"));
        const ExportedPart exported = exportPart(doc, o, file, format, c.name);
        const MeshFileReport& report = exported.report;
        const MeshStats& stats = exported.stats;
        ASSERT_TRUE(report.solid()) << what << ": " << describeDefects(report);
        // Where the simplified mesh was not a solid the plain one was written
        // (a known weakness, reported by kerf export).
        if (!exported.simplificationDefects.empty())
            std::printf("%s: simplified mesh had %s; plain mesh written\n", what.c_str(),
                        exported.simplificationDefects.c_str());
        const Mesh read = test::readMeshFile(file);
        const MeshReport r = checkMesh(read);
        // What the exporter says a reader gets is what the reader got.
        EXPECT_EQ(r.triangles, report.asRead.triangles) << what;
        EXPECT_EQ(r.vertices, report.asRead.vertices) << what;
        EXPECT_TRUE(r.watertight()) << what << ": open " << r.boundaryEdges << ", non-manifold " << r.nonManifoldEdges
                                    << ", misoriented " << r.misorientedEdges << ", pinched "
                                    << r.nonManifoldVertices << ", degenerate " << r.degenerateTriangles;
        EXPECT_EQ(findSelfIntersections(read, 0).pairs, 0u) << what;
        EXPECT_EQ(r.components, expected.components) << what;
        EXPECT_EQ(r.genus(), expected.genus()) << what;
        // Every triangle near the exact surface at its samples: the
        // tolerance, plus the file's coordinate step (100 m away, float32
        // steps by 7.8 um: more than the tolerance allows for, and said so
        // by kerf export). The distance is measured as the accuracy library
        // does (SurfaceDistance.hpp: a walk to a point of the surface, an
        // upper bound of the distance), not by |f|, which is only a lower
        // bound of it in a blend.
        std::vector<glm::dvec3> samples;
        for (const auto& t : read.triangles) {
            const glm::dvec3 a = read.vertices[t[0]], b = read.vertices[t[1]], d = read.vertices[t[2]];
            for (const glm::dvec3& w : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1),
                                        glm::dvec3(1, 1, 1) / 3.0, glm::dvec3(0.5, 0.5, 0), glm::dvec3(0, 0.5, 0.5),
                                        glm::dvec3(0.5, 0, 0.5), glm::dvec3(4, 1, 1) / 6.0,
                                        glm::dvec3(1, 4, 1) / 6.0, glm::dvec3(1, 1, 4) / 6.0,
                                        // the quarters of the edges: with the above, every point the
                                        // exporter samples (TriangleSamples.hpp)
                                        glm::dvec3(3, 1, 0) / 4.0, glm::dvec3(1, 3, 0) / 4.0,
                                        glm::dvec3(0, 3, 1) / 4.0, glm::dvec3(0, 1, 3) / 4.0,
                                        glm::dvec3(1, 0, 3) / 4.0, glm::dvec3(3, 0, 1) / 4.0})
                samples.push_back(w.x * a + w.y * b + w.z * d);
        }
        double worst = 0.0;
        for (const PointDistance& d : distancesToSurface(tape, samples)) {
            EXPECT_TRUE(d.resolved) << what;
            worst = std::max(worst, d.upper);
        }
        // Where the exporter says every triangle is within the tolerance, it
        // is (as read back, up to the file's coordinate step: 100 m away
        // float32 steps by 7.8 um, and kerf export warns about it).
        const bool claimed = exported.simplificationDefects.empty() && stats.trianglesOverTolerance == 0;
        if (claimed) {
            EXPECT_LE(worst, kTolerance + 2.0 * report.spacing) << what;
        } else {
            std::printf("%s: not held to the tolerance (%llu triangles over, as reported)\n", what.c_str(),
                        (unsigned long long)stats.trianglesOverTolerance);
        }
        // Only where a cell hides detail (the wall of one cell), or a sharp
        // edge lies on lattice lines (holdsTolerance), may the refinement
        // leave triangles over the tolerance. The worst the
        // exporter reports is in the file (sampled at every point the
        // exporter samples and more), not a figure of a mesh before its
        // last pass.
        if ((format == MeshFileFormat::ThreeMf ? c.holdsToleranceAs3mf : c.holdsTolerance) &&
            stats.hiddenDetailCells == 0 && !run.centred) {
            EXPECT_EQ(stats.trianglesOverTolerance, 0u) << what;
        }
        if (exported.simplificationDefects.empty()) {
            EXPECT_GE(worst + 2.0 * report.spacing, stats.worstSample) << what;
        }
        if (c.volume > 0.0 && claimed) {
            EXPECT_NEAR(r.volume, c.volume, kTolerance * r.area) << what;
        }
        std::printf("%s: %zu triangles (marching cubes %zu), worst sample %.4f mm, volume %.2f mm^3\n", what.c_str(),
                    r.triangles, stats.latticeTriangles, worst, r.volume);
    }
}

// Every bundled example's plain marching-cubes export (what kerf export
// writes where simplification fails) reads back as a closed solid without
// crossing triangles. The simplified exports of the examples take minutes
// on the bookshelf side (docs/benchmarks.md), too long for the suite.
class ExampleFile : public ::testing::TestWithParam<const char*> {};

INSTANTIATE_TEST_SUITE_P(Examples, ExampleFile,
                         ::testing::Values("side-chair", "stool", "table-top", "door-frame", "bookshelf-side"),
                         [](const auto& test) {
                             std::string n = test.param;
                             for (char& ch : n)
                                 if (ch == '-') ch = '_';
                             return n;
                         });

TEST_P(ExampleFile, ReadsBackClosed)
{
    const Document doc = Document::load(std::string(KERF_EXAMPLES_DIR) + "/" + GetParam() + ".kerf");
    MeshOptions o;
    o.featureSize = 4.0;
    o.tolerance = 0.0;
    const auto file = scratch(std::string(GetParam()) + ".stl");
    const ExportedPart exported = exportPart(doc, o, file, MeshFileFormat::BinaryStl, GetParam());
    ASSERT_TRUE(exported.report.solid()) << GetParam() << ": " << describeDefects(exported.report);
    std::printf("%s: %zu triangles, %s, %llu triangles over the tolerance\n", GetParam(),
                exported.report.asRead.triangles,
                exported.simplificationDefects.empty() ? "simplified"
                                                       : ("plain (" + exported.simplificationDefects + ")").c_str(),
                (unsigned long long)exported.stats.trianglesOverTolerance);
    const Mesh read = test::readMeshFile(file);
    const MeshReport r = checkMesh(read);
    EXPECT_TRUE(r.watertight()) << GetParam();
    EXPECT_EQ(findSelfIntersections(read, 0).pairs, 0u) << GetParam();
}

// The turned leg as `kerf export` makes it by default (its own 0.5 mm cells,
// 0.05 mm): the last simplification, which judges its collapses by a cheaper
// rule than the final judgement, left 6 triangles up to 0.092 mm off where
// the blends of the turning meet; the refinement now runs again where the
// final judgement finds any, and the file keeps to the tolerance.
TEST(ExportedFileSimplified, TheTurnedLegKeepsToTheDefaultTolerance)
{
    const Document doc = Document::load(std::string(KERF_EXAMPLES_DIR) + "/turned-leg.kerf");
    MeshOptions o;
    o.featureSize = 0.5;
    o.tolerance = 0.05;
    const auto file = scratch("turned-leg-default.stl");
    const ExportedPart exported = exportPart(doc, o, file, MeshFileFormat::BinaryStl, "turned leg");
    ASSERT_TRUE(exported.report.solid()) << describeDefects(exported.report);
    EXPECT_EQ(exported.stats.trianglesOverTolerance, 0u) << "up to " << exported.stats.worstSample << " mm";
    EXPECT_LE(exported.stats.worstSample, o.tolerance);
    EXPECT_TRUE(checkMesh(test::readMeshFile(file)).watertight());
}

// How many triangles of `mesh` face into the part: their normal more than
// 90 degrees from the field's gradient at their centroid (a fold).
std::size_t trianglesFacingIntoThePart(const Mesh& mesh, const Tape& tape)
{
    GradientEvaluator<double> field;
    std::size_t count = 0;
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        const glm::dvec3 p = (a + b + c) / 3.0 - tape.origin();
        const Dual<double> g = field.evaluate(tape, p.x, p.y, p.z);
        if (glm::dot(glm::cross(b - a, c - a), glm::dvec3(g.d[0], g.d[1], g.d[2])) < 0.0) ++count;
    }
    return count;
}

// Exports `doc` as binary STL and reads the file back with the suite's own
// reader (empty when the exporter found no solid to write, a failure).
struct ReadBack {
    ExportedPart exported;
    Mesh read;
};
ReadBack exportAndReadBack(const Document& doc, double featureSize, double tolerance, const std::string& name)
{
    MeshOptions o;
    o.featureSize = featureSize;
    o.tolerance = tolerance;
    const auto file = scratch(name + ".stl");
    ReadBack r{exportPart(doc, o, file, MeshFileFormat::BinaryStl, name), {}};
    EXPECT_TRUE(r.exported.report.solid()) << name << ": " << describeDefects(r.exported.report);
    if (r.exported.report.solid()) r.read = test::readMeshFile(file);
    return r;
}

// Exports `doc` (binary STL), reads the file back and measures it with the
// accuracy library's walk (which counts a point only where the field
// changes sign): closed, nothing reported over the tolerance, and nothing
// over it as read.
void expectKeepsToTheToleranceAsRead(const Document& doc, double featureSize, double tolerance, const std::string& name)
{
    const auto [exported, read] = exportAndReadBack(doc, featureSize, tolerance, name);
    EXPECT_TRUE(checkMesh(read).watertight());
    EXPECT_EQ(exported.stats.trianglesOverTolerance, 0u) << "up to " << exported.stats.worstSample << " mm";
    const SurfaceDistance measured = measureSurfaceDistance(read, compileTape(doc));
    EXPECT_EQ(measured.unresolved, 0u);
    EXPECT_LE(measured.max, tolerance + 2.0 * exported.report.spacing)
        << "at " << measured.maxAt.x << ", " << measured.maxAt.y << ", " << measured.maxAt.z;
}

// The turned leg moved by (0.37, -0.21, 0.13) mm, exported at 0.01 mm: the
// cells fall otherwise on the pommel, whose square sides touch the
// turning's cylinder at a tangent, and beside the four tangent points the
// pommel's underside is a sliver narrower than a cell between two sharp
// edges. The refinement's splits put their vertices beside those edges,
// never on them: 20 triangles were left up to 0.024 mm off. A second
// refinement that also splits onto the edges a third sheet makes with an
// edge's ends (RefineSettings::splitsOnThirdSheet) keeps to the tolerance.
// Read back and measured by the accuracy library's walk.
TEST(ExportedFileSimplified, TheTurnedLegMovedOffItsCellsKeepsToAHundredthBesideItsPommelsTangentPoints)
{
    std::ifstream in(std::string(KERF_EXAMPLES_DIR) + "/turned-leg.kerf");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t root = text.find("\"root\":"), last = text.rfind('}');
    ASSERT_NE(root, std::string::npos);
    ASSERT_NE(last, std::string::npos);
    text.insert(last, "]}");
    text.insert(root + 7, R"({"id":"moved","type":"union","transform":{"translate":[0.37,-0.21,0.13]},"children":[)");
    expectKeepsToTheToleranceAsRead(Document::parse(text, "turned-leg-moved.kerf"), 0.5, 0.01, "turned-leg-moved");
}

// A kitchen drawer's front with a grooved side glued to its back face, as a
// newcomer built it, exported as it comes (0.5 mm cells, 0.05 mm): the
// field is 0 all over the glue line inside the part. The refinement once
// put split vertices there and dug a pit 0.35 mm into the corner where
// front, side and bottom face meet, round after round: 33 triangles up to
// 0.15 mm off, and the export said the file did not match the part. Read
// back and measured by the accuracy library's walk, which counts a point
// only where the field changes sign, the file keeps to the tolerance.
TEST(ExportedFileSimplified, TheGlueLineOfADrawerCornerIsNotDugInto)
{
    const Document doc = parse(R"({"id":"u","type":"union","children":[
        {"id":"front","type":"box","size":[600,18,160],"transform":{"translate":[0,9,80]}},
        {"id":"d","type":"difference","children":[
            {"id":"side","type":"box","size":[12,432,160],"transform":{"translate":[-294,234,80]}},
            {"id":"groove","type":"box","size":[7,434,6],"transform":{"translate":[-290.5,234,13]}}]}]})");
    expectKeepsToTheToleranceAsRead(doc, 0.5, 0.05, "drawer-corner");
}

// Three boards glued together, a 10 mm dowel hole drilled 13 mm into the
// 12 mm bottom board from its top face: it ends flush with the underside,
// where the field is 0 across its mouth (the tool's end on the board's
// face: a film). Samples of triangles there read |f| = 0, and a triangle
// cutting the hole's rim by 0.08 mm was reported 0.049 mm off at 0.5 mm
// cells (found by ExportedJoinery). The final judgement now trusts |f|
// only where the field changes sign across the sample; the file, read back
// and measured by the accuracy library's walk, keeps to the tolerance.
TEST(ExportedFileSimplified, AHoleEndingFlushWithAFaceIsNotCutAcrossItsRim)
{
    const Document doc = parse(R"({"id":"cut","type":"difference","children":[
        {"id":"glued","type":"union","children":[
            {"id":"board0","type":"box","size":[60,30,12],"transform":{"translate":[30,15,6]}},
            {"id":"board1","type":"box","size":[12,30,40],"transform":{"translate":[-6,15,20]}},
            {"id":"board2","type":"box","size":[50,20,40],"transform":{"translate":[25,-10,20]}}]},
        {"id":"hole0","type":"cylinder","radius":2.5,"height":10,"transform":{"translate":[39.5,25,8]}},
        {"id":"hole1","type":"cylinder","radius":5,"height":13,"transform":{"translate":[21.5,24,6.5]}},
        {"id":"hole2","type":"cylinder","radius":2.5,"height":10,"transform":{"translate":[24,22,4]}}]})");
    expectKeepsToTheToleranceAsRead(doc, 0.5, 0.05, "flush-hole");
}

// A board with rounded edges and two square pockets through its underside
// (the table top's mortises, small): at 4 mm cells and 0.1 mm the
// simplification once left a sliver at a pocket's corner touching a face
// triangle of the underside, apart in double and crossing it once the
// coordinates were float32, and the export fell back to the plain mesh.
// New triangles now keep a clearance (TriangleClearance.hpp): the
// simplified mesh itself is written, and reads back as a solid.
TEST(ExportedFileSimplified, PocketCornersStayClearOfTheFacesAroundThem)
{
    const Document doc = parse(R"({"id":"d","type":"difference","children":[
        {"id":"b","type":"box","size":[300,200,28],"round":8,"transform":{"translate":[0,0,14]}},
        {"id":"m","type":"mirror","normal":[1,0,0],"offset":0,"children":[
            {"id":"p","type":"box","size":[40,40,19],"transform":{"translate":[110,60,8.5]}}]}]})");
    const auto [exported, read] = exportAndReadBack(doc, 4.0, 0.1, "pockets");
    EXPECT_EQ(exported.simplificationDefects, "");
    EXPECT_TRUE(checkMesh(read).watertight());
    EXPECT_EQ(findSelfIntersections(read, 0).pairs, 0u);
    EXPECT_LT(read.triangles.size(), exported.stats.latticeTriangles / 3);
}

// A board is two triangles a face, at any cell size: every vertex of a flat
// face has a free collapse until none is left (a refused first proposal
// has others; it once stopped at 98 triangles at 1 mm cells, 468 at 0.1).
TEST(ExportedFileSimplified, ABoardIsItsTwelveTriangles)
{
    const Document doc = parse(R"({"id":"b","type":"box","size":[18,100,100],"transform":{"translate":[0,50,50]}})");
    const Mesh read = exportAndReadBack(doc, 1.0, 0.01, "board").read;
    EXPECT_TRUE(checkMesh(read).watertight());
    EXPECT_EQ(read.triangles.size(), 12u);
}

// The other way round from the samples over the triangles: the part's own
// edges and corners, sampled along the exact box, lie within the tolerance
// of the file as read back. A newcomer's apron (a plain 360 x 20 x 80 box)
// came out in 450 triangles with its top front edge cut off 0.058 mm at
// 0.05 mm, and a board at its default cells with a corner slid 0.06 mm down
// its edge, while every sample of every triangle was within 0.049 mm: the
// lattice's crease point was sampled from the polygon's centre, 0.87 mm from
// one face and 0.88 from the other, and projected onto the same face from
// both sides; and the collapses, which measure the triangles against the
// surface, moved corners the triangles stayed near.
TEST(ExportedFileSimplified, ABoxsEdgesAndCornersLieWithinTheToleranceOfTheFile)
{
    std::mt19937 random(20261129);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double tolerance = 0.05;
    for (int i = 0; i < 16; ++i) {
        const glm::dvec3 size(5.0 + 395.0 * unit(random), 5.0 + 95.0 * unit(random), 5.0 + 95.0 * unit(random));
        const glm::dvec3 at(400.0 * unit(random) - 200.0, 400.0 * unit(random) - 200.0, 100.0 * unit(random));
        const bool turned = i % 2 == 1;
        const glm::dvec3 degrees = turned ? glm::dvec3(90.0 * unit(random), 90.0 * unit(random), 90.0 * unit(random))
                                          : glm::dvec3(0.0);
        const double cells = std::array{0.5, 1.0, 2.0}[std::size_t(i) % 3];
        char root[512];
        std::snprintf(root, sizeof root,
                      R"({"id":"b","type":"box","size":[%.17g,%.17g,%.17g],)"
                      R"("transform":{"translate":[%.17g,%.17g,%.17g],"rotate":[%.17g,%.17g,%.17g]}})",
                      size.x, size.y, size.z, at.x, at.y, at.z, degrees.x, degrees.y, degrees.z);
        const Document doc = parse(root);
        SCOPED_TRACE(root);
        const auto [exported, read] = exportAndReadBack(doc, cells, tolerance, "box-" + std::to_string(i));
        ASSERT_FALSE(read.triangles.empty());
        // The box's corners where the document puts them (its own frame to the world).
        const Node& box = doc.root;
        std::vector<glm::dvec3> corners;
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 local((c & 1 ? 0.5 : -0.5) * size.x, (c & 2 ? 0.5 : -0.5) * size.y,
                                   (c & 4 ? 0.5 : -0.5) * size.z);
            corners.push_back(Affine::fromTransform(box.transform).apply(local));
        }
        double worst = 0.0;
        glm::dvec3 worstAt(0.0);
        for (int c = 0; c < 8; ++c)
            for (int axis = 0; axis < 3; ++axis) {
                if (c & (1 << axis)) continue; // each edge once, from its lower corner
                const glm::dvec3 from = corners[std::size_t(c)], to = corners[std::size_t(c | (1 << axis))];
                for (int k = 0; k <= 64; ++k) {
                    const glm::dvec3 p = from + (to - from) * (double(k) / 64.0);
                    double nearest = std::numeric_limits<double>::infinity();
                    for (const auto& t : read.triangles) {
                        const glm::dvec3 u = read.vertices[t[0]], v = read.vertices[t[1]], w = read.vertices[t[2]];
                        nearest = std::min(nearest, mesher::pointTriangleDistance(p, u, v, w));
                    }
                    if (nearest > worst) {
                        worst = nearest;
                        worstAt = p;
                    }
                }
            }
        // (float32 coordinates: a few units in the last place of the part's size)
        EXPECT_LE(worst, tolerance + 1e-6 * glm::length(at + size))
            << read.triangles.size() << " triangles at " << cells << " mm cells; worst at " << worstAt.x << ", "
            << worstAt.y << ", " << worstAt.z;
        if (!turned) {
            EXPECT_EQ(read.triangles.size(), 12u) << cells << " mm cells";
        }
        // The export's own measure of the part's side (SurfaceCoverage)
        // says the same: every point the cells found within the tolerance.
        EXPECT_GT(exported.stats.partSamples, 0u);
        EXPECT_EQ(exported.stats.partSamplesBeyond, 0u) << "the furthest " << exported.stats.worstPartSample << " mm";
    }
}

// The other way round for curved edges and blends: the part's surface,
// sampled by another mesh of it (every vertex of the plain marching cubes at
// half the cells, roots of the exact field and points of its sharp edges,
// as written to its own file), lies within the tolerance of the simplified
// file as read back. A dowel's rims came out as chords up to 3 mm long,
// the rim bowing 0.073 mm out of the flat end between the chord's ends,
// while every sample of every triangle (those on the chord lie on the end
// face) was within 0.05 mm; a raised panel's blend rose 0.061 mm under its
// large flat triangles between their samples. The refinement now splits
// the edge nearest to each point of the part the mesh misses.
TEST(ExportedFileSimplified, ThePartsRimsAndBlendsLieWithinTheToleranceOfTheFile)
{
    const double tolerance = 0.05;
    const std::pair<const char*, const char*> parts[] = {
        {"dowel", R"({"id":"dowel","type":"cylinder","radius":18,"height":60})"},
        {"raised-panel", R"({"id":"panel","type":"union","blend":8,"children":[)"
                         R"({"id":"tongue","type":"box","size":[96,96,5]},)"
                         R"({"id":"field","type":"offset","distance":5,"transform":{"translate":[0,0,1]},)"
                         R"("children":[{"id":"core","type":"box","size":[40,40,2]}]}]})"},
    };
    for (const auto& [name, root] : parts) {
        SCOPED_TRACE(name);
        const Document doc = parse(root);
        const auto [exported, read] = exportAndReadBack(doc, 0.5, tolerance, name);
        ASSERT_FALSE(read.triangles.empty());
        const auto [plain, points] = exportAndReadBack(doc, 0.25, 0.0, std::string(name) + "-plain");
        ASSERT_FALSE(points.vertices.empty());
        double worst = 0.0;
        glm::dvec3 worstAt(0.0);
        for (const glm::dvec3& p : points.vertices) {
            double nearest = std::numeric_limits<double>::infinity();
            for (const auto& t : read.triangles)
                nearest = std::min(nearest, mesher::pointTriangleDistance(p, read.vertices[t[0]], read.vertices[t[1]],
                                                                         read.vertices[t[2]]));
            if (nearest > worst) {
                worst = nearest;
                worstAt = p;
            }
        }
        // The export holds the part to the tolerance at its own points, a
        // cell (h = 0.5 mm) apart: between two of them, where the distance
        // to the mesh peaks, a surface of radius R can lie up to about
        // (h/2)^2 / (2R) further (the blend's 8 mm: 0.004 mm; found 0.0014).
        // And the float32 coordinates of both files.
        const double between = 0.25 * 0.25 / (2.0 * 8.0);
        EXPECT_LE(worst, tolerance + between + 2.0 * (exported.report.spacing + plain.report.spacing))
            << read.triangles.size() << " triangles; worst at " << worstAt.x << ", " << worstAt.y << ", "
            << worstAt.z;
        EXPECT_EQ(exported.stats.partSamplesBeyond, 0u) << "the furthest " << exported.stats.worstPartSample << " mm";
        EXPECT_EQ(exported.stats.trianglesOverTolerance, 0u);
    }
}

// A board with 1 mm rounds at 1 mm cells, as the bookshelf side is: where
// three rounds meet (a corner of radius 1 in cells of 1), the collapses
// left a fin, two thin triangles facing apart whose shared edge cut the
// corner 0.24 mm deep (5 triangles over the default 0.05 mm; in the file,
// 3 facing into the part). The refinement now flips a triangle that faces
// into the part where the flip turns it the surface's way. At 0.01 mm, 4
// triangles then stayed over (0.048 mm), the splits stuck beside triangles
// leaning across the surface: the last refinement flips those upright too.
// The file, read back: within the tolerance at the exact surface, and no
// triangle facing into the part.
TEST(ExportedFileSimplified, ARoundedCornerInCellsOfItsRadiusHasNoFold)
{
    const Document doc =
        parse(R"({"id":"b","type":"box","size":[18,30,40],"round":1,"transform":{"translate":[0,15,20]}})");
    const Tape tape = compileTape(doc);
    for (const double tolerance : {0.05, 0.01}) {
        SCOPED_TRACE(tolerance);
        const auto [exported, read] = exportAndReadBack(doc, 1.0, tolerance, "rounded-corner");
        EXPECT_EQ(exported.simplificationDefects, "");
        EXPECT_EQ(exported.stats.trianglesOverTolerance, 0u) << "up to " << exported.stats.worstSample << " mm";
        EXPECT_EQ(exported.stats.foldedTriangles, 0u);
        const MeshReport r = checkMesh(read);
        EXPECT_TRUE(r.watertight());
        EXPECT_EQ(r.genus(), 0);
        EXPECT_EQ(trianglesFacingIntoThePart(read, tape), 0u);
        const SurfaceDistance d = measureSurfaceDistance(read, tape);
        EXPECT_LE(d.max, tolerance + 2.0 * exported.report.spacing)
            << "at " << d.maxAt.x << ", " << d.maxAt.y << ", " << d.maxAt.z;
    }
}

// Twelve shelf-pin holes (5 mm, 12 deep) in a panel at 1 mm cells and
// 0.01 mm: a hole takes about what its rims need (35 segments hold 0.01 mm
// on a 5 mm circle), not the marching cubes' density. Its wall once kept
// 300 triangles, held by feature vertices that the marching cubes fit on
// the tightly curved wall (no edge there) and by rims whose evenly spaced
// vertices no half-edge collapse could thin; the plain panel of
// bench/data (94 holes) then took 39 k triangles, now 20 k
// (docs/benchmarks.md). The file is read back: a closed solid of the
// part's genus, within the tolerance. (At these holes' places against the
// lattice, cells cut across the rims, and 33 to 39 triangles stayed up to
// 0.026 to 0.048 mm off, where no split could mend them, until the
// refinement flipped the triangles there that faced into the part.)
// An 18 mm panel with two rows of six 5 mm shelf-pin holes, 13 deep.
constexpr int kShelfPinHoles = 12;
Document shelfPinPanel()
{
    std::string holes;
    int count = 0;
    for (const double y : {23.0, 37.0})
        for (int k = 0; k < kShelfPinHoles / 2; ++k) {
            holes += R"(,{"id":"h)" + std::to_string(count++) +
                     R"(","type":"cylinder","radius":2.5,"height":13,"transform":{"translate":[3.5,)" +
                     std::to_string(y) + "," + std::to_string(20 + 32 * k) + R"(],"rotate":[0,90,0]}})";
        }
    return parse(
        R"({"id":"d","type":"difference","children":[{"id":"b","type":"box","size":[18,60,200],"transform":{"translate":[0,30,100]}})" +
        holes + "]}");
}

TEST(ExportedFileSimplified, ShelfPinHolesTakeTheTrianglesTheirRimsNeed)
{
    const Document doc = shelfPinPanel();
    const int count = kShelfPinHoles;
    const Tape tape = compileTape(doc);
    constexpr double kTolerance = 0.01;
    const auto [exported, read] = exportAndReadBack(doc, 1.0, kTolerance, "shelf-pin-holes");
    EXPECT_EQ(exported.simplificationDefects, "");
    const MeshReport r = checkMesh(read);
    EXPECT_TRUE(r.watertight());
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.genus(), 0);
    EXPECT_EQ(findSelfIntersections(read, 0).pairs, 0u);
    PointEvaluator<double> eval;
    double worst = 0.0;
    for (const auto& t : read.triangles)
        for (const glm::dvec3& w : {glm::dvec3(1, 1, 1) / 3.0, glm::dvec3(0.5, 0.5, 0), glm::dvec3(0, 0.5, 0.5),
                                    glm::dvec3(0.5, 0, 0.5)}) {
            const glm::dvec3 p =
                w.x * read.vertices[t[0]] + w.y * read.vertices[t[1]] + w.z * read.vertices[t[2]] - tape.origin();
            worst = std::max(worst, std::abs(eval.evaluate(tape, p.x, p.y, p.z)));
        }
    // The report does not understate the file (it samples more points than these).
    EXPECT_LE(worst, std::max(kTolerance, exported.stats.worstSample) + 2.0 * exported.report.spacing);
    EXPECT_EQ(exported.stats.trianglesOverTolerance, 0u) << "up to " << exported.stats.worstSample << " mm";
    EXPECT_LE(worst, kTolerance + 2.0 * exported.report.spacing);
    // The panel's faces need a few hundred; each hole about 200 (its two
    // rims' 35 to 60 vertices: the strip of its wall, the fans to the face
    // and the bottom).
    std::printf("%zu triangles for %d holes (marching cubes %zu), worst sample %.4f mm\n", read.triangles.size(),
                count, exported.stats.latticeTriangles, worst);
    EXPECT_LE(read.triangles.size(), std::size_t(count) * 230 + 300);
}

// Cells coarser than the holes (10 mm cells, 5 mm holes) miss them or put
// them through a face; no split mends that. The refinement once went on
// splitting towards the holes' walls for its 40 rounds and three more
// refinements after it, growing the mesh tenfold (the door frame at 8 mm
// cells took a minute for 250 k triangles). It now gives up once the
// triangles over the tolerance stop becoming fewer, and the file, still a
// closed solid, is reported as missing the part.
TEST(ExportedFileSimplified, CellsCoarserThanTheHolesAreNotDugAt)
{
    const auto [exported, read] = exportAndReadBack(shelfPinPanel(), 10.0, 0.05, "shelf-pin-holes-coarse");
    EXPECT_TRUE(checkMesh(read).watertight());
    EXPECT_GT(exported.stats.trianglesOverTolerance, 0u) << "the scenario needs cells that miss the holes";
    EXPECT_NE(describeVisibleMiss(exported.stats, 0.05, 1.0), "");
    std::printf("%zu triangles from %zu of the lattice, %llu splits\n", read.triangles.size(),
                exported.stats.latticeTriangles, static_cast<unsigned long long>(exported.stats.splits));
    EXPECT_LE(exported.stats.splits, 4 * exported.stats.latticeTriangles);
    EXPECT_LE(read.triangles.size(), 4 * exported.stats.latticeTriangles);
}

// The sentences that tell a person the file is not the part. A newcomer
// exported a shelf side at 10 mm cells: pin holes came out through its show
// face, 3.4 mm off, and the dialog called it "a closed solid all the same".
TEST(ExportMessages, AFileFarFromThePartSaysSoAndNamesTheFeatureSizeToUse)
{
    MeshStats stats;
    stats.cellSize = 10.0;
    stats.trianglesOverTolerance = 300;
    stats.worstSample = 3.4;
    const std::string miss = describeVisibleMiss(stats, 0.05, 1.0);
    EXPECT_NE(miss.find("the file does not match the part: in places it is up to 3.4 mm from the exact surface"),
              std::string::npos)
        << miss;
    EXPECT_NE(miss.find("export it at a feature size of 1 mm (the part's own)"), std::string::npos) << miss;
    // Without a finer size of the part's own: half the cell.
    EXPECT_NE(describeVisibleMiss(stats, 0.05, 0.0).find("feature size of 5 mm"), std::string::npos);
    // Within what a router or a printer reproduces, or twice the tolerance: nothing.
    stats.worstSample = 0.09;
    EXPECT_EQ(describeVisibleMiss(stats, 0.05, 1.0), "");
    stats.worstSample = 0.3;
    EXPECT_EQ(describeVisibleMiss(stats, 0.2, 1.0), "");
    stats.trianglesOverTolerance = 0;
    stats.worstSample = 3.4;
    EXPECT_EQ(describeVisibleMiss(stats, 0.05, 1.0), "");
}

// A 10 mm ball 10 km from the origin: STL's float32 steps by 1 mm there,
// which the ball's size passes (ten steps across) but its 0.25 mm cells do
// not: their vertices round onto each other. The export is refused, and the
// user was told "internal error"; now what makes it fail and what holds it.
// As 3MF (round its own middle) the same export is a closed solid.
TEST(ExportMessages, CellsFinerThanTheFilesStepAreBlamedOnTheFile)
{
    const Document doc = parse(R"({"id":"ball","type":"sphere","radius":5,"transform":{"translate":[1e7,0,0]}})");
    MeshOptions o;
    o.featureSize = 0.25;
    o.tolerance = 0.0;
    const auto stl = scratch("far-ball.stl");
    const ExportedPart refused = exportPart(doc, o, stl, MeshFileFormat::BinaryStl, "ball");
    ASSERT_FALSE(refused.report.solid());
    EXPECT_FALSE(std::filesystem::exists(stl));
    const std::string why = describeNotWritten(refused, MeshFileFormat::BinaryStl);
    EXPECT_EQ(why.rfind("a reader of the file would not get a closed solid (", 0), 0u) << why;
    EXPECT_NE(why.find("the file's coordinates step by 1 mm where the part reaches, too coarse for cells of 0.25 mm"),
              std::string::npos)
        << why;
    EXPECT_NE(why.find("a .3mf file keeps the detail"), std::string::npos) << why;
    EXPECT_EQ(why.find("internal error"), std::string::npos) << why;

    const auto threeMf = scratch("far-ball.3mf");
    const ExportedPart written = exportPart(doc, o, threeMf, MeshFileFormat::ThreeMf, "ball");
    EXPECT_TRUE(written.report.solid()) << describeDefects(written.report);
    EXPECT_TRUE(test::readMeshFile(threeMf).triangles.size() > 1000u);

    // Where the step is far below the cells, a mesh that does not read back
    // as a solid is the mesher's fault, and says so.
    ExportedPart broken = refused;
    broken.report.spacing = 1e-6;
    EXPECT_EQ(describeNotWritten(broken, MeshFileFormat::BinaryStl).rfind("internal error: a reader", 0), 0u);
}

// A 3MF export is reproducible: lib3mf drew new UUIDs for the object, the
// build item and the build on every export, so the same part never gave
// the same bytes (a file under version control, a CAM program's cache keyed
// by the file, all changed with nothing changed). Now they come from what
// the file holds: the same part, the same file; another part, other UUIDs;
// every one a well-formed version 8 UUID as lib3mf reads it back.
TEST(ExportedThreeMf, TheSamePartIsTheSameFileByteForByte)
{
    auto exported = [&](const std::string& radius, const std::string& name) {
        const Document doc = parse(R"({"id":"d","type":"difference","children":[{"id":"b","type":"box","size":[60,40,18]},)"
                                   R"({"id":"c","type":"cylinder","transform":{"translate":[5.3,2.1,4]},"radius":)" +
                                   radius + R"(,"height":20}]})");
        MeshOptions o;
        o.featureSize = 1.0;
        const auto file = scratch(name);
        const ExportedPart part = exportPart(doc, o, file, MeshFileFormat::ThreeMf, "holed board");
        EXPECT_TRUE(part.report.solid()) << describeDefects(part.report);
        return file;
    };
    auto bytes = [](const std::filesystem::path& file) {
        std::ifstream in(file, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const auto first = exported("4", "same-1.3mf");
    const auto second = exported("4", "same-2.3mf");
    const auto other = exported("4.5", "other.3mf");
    ASSERT_FALSE(bytes(first).empty());
    EXPECT_TRUE(bytes(first) == bytes(second));

    const std::vector<std::string> uuids = test::readThreeMfUuids(first);
    ASSERT_EQ(uuids.size(), 3u); // the build, its one item, the item's object
    for (const std::string& uuid : uuids) {
        ASSERT_EQ(uuid.size(), 36u) << uuid;
        for (std::size_t i = 0; i < uuid.size(); ++i) {
            if (i == 8 || i == 13 || i == 18 || i == 23)
                EXPECT_EQ(uuid[i], '-') << uuid;
            else // the production extension's ST_UUID: [a-f0-9] only
                EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(uuid[i])) || (uuid[i] >= 'a' && uuid[i] <= 'f'))
                    << uuid;
        }
        EXPECT_EQ(uuid[14], '8') << uuid;                                  // version 8
        EXPECT_NE(std::string("89ab").find(uuid[19]), std::string::npos) << uuid; // RFC 9562 variant
    }
    EXPECT_NE(uuids[0], uuids[1]);
    EXPECT_NE(uuids[1], uuids[2]);
    EXPECT_NE(uuids[0], uuids[2]);
    const std::vector<std::string> others = test::readThreeMfUuids(other);
    ASSERT_EQ(others.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i)
        EXPECT_NE(others[i], uuids[i]);
}

// A report names one feature size to try. The door frame at 8 mm cells
// said "a gap 0.5 mm wide … a feature size of 0.2 mm resolves it" and then
// "export it at a feature size of 0.5 mm (the part's own)": both true (half
// the gap for certain; a gap as wide as a cell holds a lattice plane), and a
// newcomer did not know which to use. The part's own, where it is no
// coarser than the hidden detail is thin; else the finer size, everywhere.
TEST(ExportMessages, TheReportAdvisesOneFeatureSize)
{
    MeshStats stats;
    stats.cellSize = 8.0;
    stats.trianglesOverTolerance = 4250;
    stats.worstSample = 3.05;
    stats.hiddenDetailCells = 398;
    stats.hiddenDetailThickness = 0.5;
    auto advised = [&](double own) {
        return std::vector<std::string>{describeHiddenDetail(stats, own), describeTrianglesOverTolerance(stats, 0.05, own),
                                        describeVisibleMiss(stats, 0.05, own)};
    };
    for (const std::string& said : advised(0.5)) {
        EXPECT_NE(said.find("a feature size of 0.5 mm (the part's own)"), std::string::npos) << said;
        EXPECT_EQ(said.find("0.2 mm"), std::string::npos) << said;
    }
    // A part whose own size is coarser than the gap: the size that resolves it.
    for (const std::string& said : advised(1.0)) {
        EXPECT_NE(said.find("a feature size of 0.2 mm"), std::string::npos) << said;
        EXPECT_EQ(said.find("part's own"), std::string::npos) << said;
    }
    EXPECT_EQ(advisedFeatureSize(stats, 0.5), 0.5);
    EXPECT_EQ(advisedFeatureSize(stats, 1.0), 0.2);
    EXPECT_EQ(advisedFeatureSize(stats, 0.0), 0.2);  // own unknown
    EXPECT_EQ(advisedFeatureSize(stats, 10.0), 0.2); // own coarser than the cells asked for
}

// A few triangles left just over a fine tolerance, with no hidden detail,
// were answered "a feature size of 0.25 mm often leaves fewer": on the
// bundled examples at 0.01 mm it left as many or more (the turned leg's
// tangent of pommel and turning 21 -> 32). The sentence says what holds and
// names no feature size; a miss a woodworker would see still gets one.
TEST(ExportMessages, TrianglesJustOverTheToleranceAreNotSentToFinerCells)
{
    MeshStats stats;
    stats.cellSize = 0.5;
    stats.trianglesOverTolerance = 21;
    stats.areaOverTolerance = 0.0477;
    stats.worstSample = 0.0207;
    const std::string said = describeTrianglesOverTolerance(stats, 0.01, 0.5);
    EXPECT_NE(said.find("stay up to 0.0207 mm"), std::string::npos) << said;
    EXPECT_NE(said.find("every other triangle keeps to the tolerance, and finer cells are no sure cure"),
              std::string::npos) << said;
    EXPECT_EQ(said.find("feature size of"), std::string::npos) << said;
    EXPECT_FALSE(missesVisibly(stats, 0.01));
    EXPECT_EQ(describeVisibleMiss(stats, 0.01, 0.5), "");
    // Far over: the file misses the part, and the feature size to try is named.
    stats.cellSize = 8.0;
    stats.worstSample = 1.3;
    EXPECT_TRUE(missesVisibly(stats, 0.05));
    EXPECT_NE(describeVisibleMiss(stats, 0.05, 1.0).find("a feature size of 1 mm (the part's own)"), std::string::npos);
    // ... and the sentence on the triangles does not call finer cells no cure beside it.
    const std::string far = describeTrianglesOverTolerance(stats, 0.05, 1.0);
    EXPECT_NE(far.find("every other triangle keeps to the tolerance"), std::string::npos) << far;
    EXPECT_EQ(far.find("no sure cure"), std::string::npos) << far;
}

TEST(ExportMessages, ATolerancePastTheFeatureSizeIsWarnedOf)
{
    MeshStats stats;
    stats.cellSize = 1.0;
    EXPECT_NE(describeCoarseTolerance(stats, 5.0).find("a tolerance of 5 mm is coarser than the feature size of 1 mm"),
              std::string::npos);
    EXPECT_EQ(describeCoarseTolerance(stats, 0.5), "");  // finer than the cells
    EXPECT_EQ(describeCoarseTolerance(stats, 0.05), ""); // the default
    stats.cellSize = 0.02;                               // a tiny part's own cells
    EXPECT_EQ(describeCoarseTolerance(stats, 0.05), "");  // within what nobody sees
}

// Where triangles stay over the tolerance, the report gives their area: a
// woodworker judges "a few hundredths of a square millimetre" where a count
// of triangles says nothing (and led to halving the feature size again and
// again). Two boards touching along an edge leave such triangles at 1 mm
// cells and 0.1 mm (exportDialogNamesWhatTheToleranceMissed). Read back,
// the triangles with a sample beyond the tolerance have at most that area
// (the exporter samples more points than these), and some do.
TEST(ExportedFileSimplified, TheAreaLeftOverTheToleranceIsReported)
{
    const Document doc = parse(R"({"id":"u","type":"union","children":[
        {"id":"a","type":"box","size":[20,20,18],"transform":{"translate":[-10,-10,0]}},
        {"id":"b","type":"box","size":[20,20,18],"transform":{"translate":[10,10,0]}}]})");
    const Tape tape = compileTape(doc);
    constexpr double kTolerance = 0.1;
    const auto [exported, read] = exportAndReadBack(doc, 1.0, kTolerance, "touching-boards");
    ASSERT_GT(exported.stats.trianglesOverTolerance, 0u) << "the scenario needs a part that misses";
    PointEvaluator<double> eval;
    double overArea = 0.0, totalArea = 0.0;
    for (const auto& t : read.triangles) {
        const glm::dvec3 a = read.vertices[t[0]], b = read.vertices[t[1]], c = read.vertices[t[2]];
        const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
        totalArea += area;
        double worst = 0.0;
        for (const glm::dvec3& w : {glm::dvec3(1, 1, 1) / 3.0, glm::dvec3(0.5, 0.5, 0), glm::dvec3(0, 0.5, 0.5),
                                    glm::dvec3(0.5, 0, 0.5)}) {
            const glm::dvec3 p = w.x * a + w.y * b + w.z * c - tape.origin();
            worst = std::max(worst, std::abs(eval.evaluate(tape, p.x, p.y, p.z)));
        }
        if (worst > kTolerance + 2.0 * exported.report.spacing) overArea += area;
    }
    std::printf("over the tolerance: %llu triangles, %.4f mm^2 reported, %.4f mm^2 found here, of %.1f mm^2\n",
                (unsigned long long)exported.stats.trianglesOverTolerance, exported.stats.areaOverTolerance, overArea,
                totalArea);
    EXPECT_GT(overArea, 0.0);
    EXPECT_LE(overArea, exported.stats.areaOverTolerance * (1.0 + 1e-6));
    EXPECT_LT(exported.stats.areaOverTolerance, 0.01 * totalArea);
    const std::string said = describeTrianglesOverTolerance(exported.stats, kTolerance);
    EXPECT_NE(said.find(" mm^2 in all) stay up to "), std::string::npos) << said;
}

} // namespace
} // namespace kerf

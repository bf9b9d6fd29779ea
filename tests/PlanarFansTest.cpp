// Flat blocks of the lattice made fans before the simplification
// (mesher/src/PlanarFans.hpp): the mesh stays closed, oriented, of the same
// genus, without crossings, every vertex on the exact surface, the volume
// the same to rounding; only blocks that are one flat disk change.

#include "PlanarFans.hpp"

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/mesher/SelfIntersections.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>

namespace kerf::mesher {
namespace {

struct Lattice {
    Tape tape;
    glm::dvec3 origin{0.0}; // a lattice point
    Mesh mesh;
    std::vector<glm::dvec3> normals; // the field's unit gradient at each vertex
};

// The marching-cubes mesh of a part (no tolerance: the lattice as it is)
// and its vertices' normals from the exact field.
Lattice latticeOf(const std::string& root, double cell)
{
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf");
    Lattice l{compileTape(doc), glm::dvec3(0.0), {}, {}};
    MeshOptions o;
    o.featureSize = cell;
    MeshStats stats;
    auto mesh = meshTape(l.tape, o, {}, &stats);
    EXPECT_TRUE(mesh.has_value());
    l.origin = stats.latticeOrigin;
    l.mesh = std::move(*mesh);
    GradientEvaluator<double> gradients;
    for (const glm::dvec3& v : l.mesh.vertices) {
        const glm::dvec3 q = v - l.tape.origin();
        const Dual<double> d = gradients.evaluate(l.tape, q.x, q.y, q.z);
        const glm::dvec3 g(d.d[0], d.d[1], d.d[2]);
        l.normals.push_back(glm::length(g) > 0.0 ? glm::normalize(g) : glm::dvec3(0.0));
    }
    return l;
}

double worstField(const Tape& tape, const Mesh& mesh)
{
    PointEvaluator<double> eval;
    double worst = 0.0;
    for (const glm::dvec3& v : mesh.vertices) {
        const glm::dvec3 q = v - tape.origin();
        worst = std::max(worst, std::abs(eval.evaluate(tape, q.x, q.y, q.z)));
    }
    return worst;
}

// As the exporter allows at its default tolerance (1e-3 of 0.05 mm).
constexpr double kFlatness = 5e-5;

// Fans the lattice (blocks from `origin`) and checks it is the same solid;
// returns the blocks fanned.
PlanarFanStats expectSameSolid(Lattice& l, double cell, const glm::dvec3& origin, const char* what)
{
    const MeshReport before = checkMesh(l.mesh);
    EXPECT_TRUE(before.watertight()) << what;
    const double rootsWithin = worstField(l.tape, l.mesh); // the lattice's own vertices' |f|
    tbb::task_arena arena(2);
    const PlanarFanStats fans = fanPlanarBlocks(l.mesh, l.normals, origin, cell, 16, 4, kFlatness, arena);
    const MeshReport after = checkMesh(l.mesh);
    EXPECT_TRUE(after.watertight()) << what;
    EXPECT_EQ(after.components, before.components) << what;
    EXPECT_EQ(after.genus(), before.genus()) << what;
    // The same up to rounding, and to the vertices dropped from straight
    // seams between fans: each lies within the flatness of the run that
    // replaces it, whose triangles stand on about two cells of it.
    const double seams = kFlatness * 2.0 * cell * double(fans.seamVertices);
    EXPECT_NEAR(after.volume, before.volume, 1e-9 * before.volume + kFlatness * seams) << what;
    EXPECT_NEAR(after.area, before.area, 1e-9 * before.area + seams) << what;
    EXPECT_EQ(after.triangles + fans.removed, before.triangles) << what;
    EXPECT_EQ(l.normals.size(), l.mesh.vertices.size()) << what;
    EXPECT_EQ(findSelfIntersections(l.mesh).pairs, 0u) << what;
    EXPECT_EQ(after.unusedVertices, 0u) << what;
    // A fan's centre is on its plane, to the flatness allowed.
    EXPECT_LE(worstField(l.tape, l.mesh), rootsWithin + kFlatness) << what;
    return fans;
}

TEST(PlanarFans, ABoardsFacesBecomeFansAndTheSolidStaysTheSame)
{
    const double cell = 0.5;
    Lattice l = latticeOf(R"({"id":"b","type":"box","size":[60,40,18]})", cell);
    const std::size_t before = l.mesh.triangles.size();
    const PlanarFanStats fans = expectSameSolid(l, cell, l.origin, "board");
    EXPECT_GT(fans.blocks, 0u);
    EXPECT_LT(l.mesh.triangles.size(), before / 3) << "most of a board is flat";
}

// Blocks that cut through cells (not the mesher's own): their triangles,
// taken by centroid, have ragged borders, and fewer of them make a fan that
// passes the checks; what is made is still right.
TEST(PlanarFans, BlocksAcrossTheCellsStillLeaveTheSameSolid)
{
    const double cell = 0.5;
    Lattice l = latticeOf(R"({"id":"b","type":"box","size":[60,40,18],"transform":{"rotate":[0,0,20]}})", cell);
    const std::size_t before = l.mesh.triangles.size();
    expectSameSolid(l, cell, l.origin + glm::dvec3(0.31, 0.17, 0.23), "board, blocks across the cells");
    EXPECT_LT(l.mesh.triangles.size(), before);
}

TEST(PlanarFans, ATurnedBoardWithHolesKeepsItsHolesAndGenus)
{
    const double cell = 0.5;
    Lattice l = latticeOf(R"({"id":"d","type":"difference","transform":{"rotate":[17,31,5]},"children":[
        {"id":"board","type":"box","size":[60,40,18],"round":2},
        {"id":"holes","type":"array","count":[3,1,1],"step":[18,0,0],"transform":{"translate":[-18,0,0]},
         "children":[{"id":"hole","type":"cylinder","radius":5,"height":30}]}]})",
                          cell);
    const std::size_t before = l.mesh.triangles.size();
    const PlanarFanStats fans = expectSameSolid(l, cell, l.origin, "turned board with holes");
    EXPECT_EQ(checkMesh(l.mesh).genus(), 3);
    EXPECT_GT(fans.blocks, 0u);
    EXPECT_LT(l.mesh.triangles.size(), before);
}

// Two boards touching with their tops 0.2 mm apart, less than a cell: a
// block over the step holds two parallel sheets of the same normal.
TEST(PlanarFans, AStepThinnerThanACellIsNotFlattened)
{
    const double cell = 0.5;
    Lattice l = latticeOf(R"({"id":"u","type":"union","children":[
        {"id":"a","type":"box","size":[20,20,10],"transform":{"translate":[-10,0,0]}},
        {"id":"b","type":"box","size":[20,20,10.4],"transform":{"translate":[10,0,0]}}]})",
                          cell);
    expectSameSolid(l, cell, l.origin, "step");
}

TEST(PlanarFans, NothingOnACurvedSurfaceChanges)
{
    const double cell = 0.5;
    Lattice l = latticeOf(R"({"id":"s","type":"sphere","radius":10})", cell);
    const Mesh before = l.mesh;
    const PlanarFanStats fans = expectSameSolid(l, cell, l.origin, "sphere");
    EXPECT_EQ(fans.blocks, 0u);
    EXPECT_EQ(l.mesh.triangles, before.triangles);
    EXPECT_EQ(l.mesh.vertices, before.vertices);
}

} // namespace
} // namespace kerf::mesher

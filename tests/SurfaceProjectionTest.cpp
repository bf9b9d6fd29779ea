// Points put onto the surface by the export's refinement and crease snap
// (mesher/src/CreaseSnap.hpp: projectOntoSurface): on the part's surface,
// never on a zero of the field that is no surface.

#include "CreaseSnap.hpp"

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

namespace kerf::mesher {
namespace {

Tape tapeOf(const std::string& root)
{
    return compileTape(Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf"));
}

std::optional<SurfacePoint> project(const Tape& tape, const glm::dvec3& p, const glm::dvec3& expected)
{
    GradientEvaluator<double> gradients;
    return projectOntoSurface(tape, gradients, p, 1.0, 1e-6, expected);
}

// A drawer's front and side glued face to face (the side's end on the
// front's back face, y = 18): the field is 0 all over the glue line, and
// negative on both sides of it. A point near it inside the part once
// settled there, and the refinement dug a pit 0.35 mm into the part along
// the glue line where both boards meet the bottom face, round after round
// (the drawer's default export, 0.15 mm off the exact surface).
TEST(SurfaceProjection, AGlueLineInsideThePartIsNoSurface)
{
    const Tape tape = tapeOf(R"({"id":"u","type":"union","children":[
        {"id":"front","type":"box","size":[600,18,160],"transform":{"translate":[0,9,80]}},
        {"id":"side","type":"box","size":[12,432,160],"transform":{"translate":[-294,234,80]}}]})");
    // Inside both boards' reach, 0.1 mm from the glue line, 0.2 mm in from the outer face.
    EXPECT_FALSE(project(tape, {-299.8, 18.1, 50.0}, {0, 1, 0}));
    EXPECT_FALSE(project(tape, {-299.8, 18.0, 50.0}, {0, 1, 0})) << "starting on it";
    // Beside it, the outer face is found: the start is nearer to it.
    const auto outer = project(tape, {-300.05, 18.01, 50.0}, {-1, 0, 0});
    ASSERT_TRUE(outer);
    EXPECT_NEAR(outer->p.x, -300.0, 1e-6);
    EXPECT_NEAR(glm::dot(outer->n, glm::dvec3(-1, 0, 0)), 1.0, 1e-9);
}

// The other kind of zero that is no surface: two bodies intersected where
// they only touch face to face. The field is 0 on the contact and positive
// on both sides of it: no solid there.
TEST(SurfaceProjection, AFilmOutsideThePartIsNoSurface)
{
    const Tape tape = tapeOf(R"({"id":"i","type":"intersection","children":[
        {"id":"a","type":"box","size":[40,40,18],"transform":{"translate":[0,0,9]}},
        {"id":"b","type":"box","size":[40,40,18],"transform":{"translate":[0,0,27]}}]})");
    EXPECT_FALSE(project(tape, {3.0, 1.0, 18.05}, {0, 0, 1}));
    EXPECT_FALSE(project(tape, {3.0, 1.0, 18.0}, {0, 0, 1})) << "starting on it";
}

// Points exactly on a sharp edge stay: one side of the step is then on the
// other sheet's face, where the field is 0, not past it.
TEST(SurfaceProjection, APointOnASharpEdgeIsOnTheSurface)
{
    const Tape tape = tapeOf(R"({"id":"b","type":"box","size":[20,20,20]})");
    EXPECT_TRUE(project(tape, {10.0, 10.0, 3.0}, {1, 0, 0}));
    // A concave edge: an L of two boards.
    const Tape l = tapeOf(R"({"id":"u","type":"union","children":[
        {"id":"a","type":"box","size":[20,18,100],"transform":{"translate":[10,9,0]}},
        {"id":"b","type":"box","size":[18,60,100],"transform":{"translate":[9,30,0]}}]})");
    EXPECT_TRUE(project(l, {18.0, 18.0, 3.0}, {0, 1, 0}));
}

} // namespace
} // namespace kerf::mesher

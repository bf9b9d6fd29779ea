// The export (issue 13): meshes sized by a tolerance, square edges, and
// files that a slicer reads as one closed solid.

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>

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

class ToleranceCases : public ::testing::TestWithParam<Case> {};

INSTANTIATE_TEST_SUITE_P(
    Parts, ToleranceCases,
    ::testing::Values(
        Case{"sphere", R"({"id":"s","type":"sphere","radius":10})", 1.0},
        Case{"box", R"({"id":"b","type":"box","transform":{"translate":[0.3,0.2,0.1],"rotate":[10,20,30]},"size":[40,30,18]})", 2.0},
        Case{"cylinder", R"({"id":"c","type":"cylinder","transform":{"rotate":[0,90,0]},"radius":7,"height":60})", 2.0},
        Case{"foot", R"({"id":"i","type":"intersection","children":[{"id":"c","type":"cone","transform":{"translate":[0.3,0.2,10]},"radius_bottom":14,"radius_top":20,"height":40},{"id":"h","type":"halfspace","normal":[0,0,-1],"offset":0}]})", 2.0},
        Case{"holed", R"({"id":"d","type":"difference","children":[{"id":"b","type":"box","size":[60,40,18]},{"id":"c","type":"cylinder","transform":{"translate":[5.3,2.1,4]},"radius":4,"height":20}]})", 1.0}),
    [](const auto& info) { return std::string(info.param.name); });

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

} // namespace
} // namespace kerf

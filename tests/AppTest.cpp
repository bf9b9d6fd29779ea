// kerf bench's measuring code, below the command line: the choice of the
// typical edit, and a whole run on a small part with the CPU tracer, whose
// figures must behave as the trade says (finer voxels: more memory, less
// error).

#include "kerf/app/Commands.hpp"
#include "kerf/app/TradeBench.hpp"
#include "kerf/app/TypicalEdit.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <unistd.h>

namespace kerf {
namespace {

Document doc(const std::string& root)
{
    return Document::parse(R"({"format":"kerf","version":1,"root":)" + root + "}", "test.kerf");
}

TEST(Commands, AnOutputThatIsTheDocumentIsRefusedAndTheDocumentKept)
{
    // A hostile tester exported a document onto itself through a link
    // named .stl, and a document named .stl onto itself: both replaced the
    // document with the mesh.
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("kerf-overwrite-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string text = R"({"format":"kerf","version":1,"root":{"id":"b","type":"box","size":[20,20,20]}})";
    std::ofstream(dir / "part.kerf") << text;
    std::ofstream(dir / "part.stl") << text;
    fs::create_symlink("part.kerf", dir / "link.stl");
    fs::create_hard_link(dir / "part.kerf", dir / "hard.png");
    const std::string doc = (dir / "part.kerf").string();
    const std::vector<std::vector<std::string>> exports = {
        {doc, "-o", (dir / "link.stl").string(), "--feature-size", "2"},
        {(dir / "part.stl").string(), "-o", (dir / "part.stl").string()},
        {doc, "-o", (dir / "." / "part.kerf").string()}};
    for (const auto& args : exports) {
        std::ostringstream out, err;
        EXPECT_EQ(runExport(args, out, err), 2) << args[2];
        EXPECT_NE(err.str().find("is the document being read"), std::string::npos) << err.str();
    }
    std::ostringstream out, err;
    EXPECT_EQ(runRender({doc, "-o", (dir / "hard.png").string(), "--cpu"}, out, err), 2);
    EXPECT_NE(err.str().find("is the document being read"), std::string::npos) << err.str();
    std::ostringstream benchOut, benchErr;
    EXPECT_EQ(runBench({doc, "--json", (dir / "same").string(), "--plot", (dir / "same").string()}, benchOut, benchErr,
                       [](const TradeReport&, const std::string&, const std::filesystem::path&) {}),
              2);
    EXPECT_NE(benchErr.str().find("is the --json file"), std::string::npos) << benchErr.str();
    for (const char* name : {"part.kerf", "part.stl"}) {
        std::ifstream in(dir / name);
        EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), text) << name;
    }
    EXPECT_FALSE(fs::exists(dir / "same"));
    fs::remove_all(dir);
}

// kerf check names each field it does not know on stderr, and lists them
// in its JSON with the field each is probably a misspelling of.
TEST(Commands, CheckNamesMisspeltFields)
{
    const std::string file = std::string(KERF_CLI_DATA_DIR) + "/misspelt-fields.kerf";
    std::ostringstream out, err;
    ASSERT_EQ(runCheck({file, "--json"}, out, err), 0) << err.str();
    const auto j = nlohmann::json::parse(out.str());
    const auto& unknown = j.at("unknown_fields");
    ASSERT_EQ(unknown.size(), 4u) << unknown.dump();
    EXPECT_EQ(unknown[0].at("owner"), "document");
    EXPECT_EQ(unknown[0].at("field"), "settings.featuresize");
    EXPECT_EQ(unknown[0].at("did_you_mean"), "feature_size");
    EXPECT_EQ(unknown[1].at("id"), "top");
    EXPECT_EQ(unknown[1].at("did_you_mean"), "blend");
    EXPECT_EQ(unknown[2].at("field"), "Round");
    EXPECT_EQ(unknown[3].at("owner"), "feature");
    EXPECT_EQ(unknown[3].at("id"), "leg");
    EXPECT_EQ(unknown[3].at("field"), "transfom");
    EXPECT_EQ(unknown[3].at("did_you_mean"), "transform");
    EXPECT_NE(err.str().find("kerf check: warning: feature 'leg': field 'transfom' is not one Kerf knows"),
              std::string::npos)
        << err.str();

    EXPECT_TRUE(j.at("tools_cutting_nothing").empty());

    // A hole moved clear of its board, in the JSON too.
    std::ostringstream holeOut, holeErr;
    ASSERT_EQ(runCheck({std::string(KERF_CLI_DATA_DIR) + "/hole-off-its-board.kerf", "--json"}, holeOut, holeErr), 0);
    EXPECT_EQ(nlohmann::json::parse(holeOut.str()).at("tools_cutting_nothing"), nlohmann::json::array({"hole"}));
    EXPECT_NE(holeErr.str().find("kerf check: warning: the cylinder 'hole' cuts nothing"), std::string::npos)
        << holeErr.str();

    // A bundled example has none, and no warning.
    std::ostringstream exampleOut, exampleErr;
    ASSERT_EQ(runCheck({std::string(KERF_EXAMPLES_DIR) + "/stool.kerf", "--json"}, exampleOut, exampleErr), 0);
    EXPECT_TRUE(nlohmann::json::parse(exampleOut.str()).at("unknown_fields").empty());
    EXPECT_EQ(exampleErr.str().find("warning"), std::string::npos) << exampleErr.str();
}

TEST(TypicalEdit, TheChairMovesADowelHole)
{
    const Document chair = Document::load(KERF_EXAMPLES_DIR "/side-chair.kerf");
    const auto edit = chooseTypicalEdit(chair);
    ASSERT_TRUE(edit);
    EXPECT_EQ(edit->nodeId, "dowel-hole-r");
    EXPECT_EQ(edit->type, NodeType::Cylinder);
    EXPECT_EQ(edit->instances, 2u); // under a mirror
}

TEST(TypicalEdit, TheTableTopMovesAPilotHoleWithItsCopies)
{
    const auto edit = chooseTypicalEdit(Document::load(KERF_EXAMPLES_DIR "/table-top.kerf"));
    ASSERT_TRUE(edit);
    EXPECT_EQ(edit->nodeId, "pilot-hole");
    EXPECT_EQ(edit->instances, 10u); // an array of 5 under a mirror
}

TEST(TypicalEdit, SmallestVisibleBoundedPrimitiveFirstInTheDocumentOnTies)
{
    const Document d = doc(R"({"id":"i","type":"intersection","children":[
        {"id":"u","type":"union","children":[
            {"id":"big","type":"box","size":[50,50,50]},
            {"id":"hidden-tiny","type":"sphere","radius":0.1,"visible":false},
            {"id":"first-small","type":"sphere","radius":2},
            {"id":"second-small","type":"sphere","radius":2},
            {"id":"off","type":"union","visible":false,"children":[{"id":"tiny-under-hidden","type":"sphere","radius":0.2}]}]},
        {"id":"floor","type":"halfspace","normal":[0,0,-1],"offset":0}]})");
    const auto edit = chooseTypicalEdit(d);
    ASSERT_TRUE(edit);
    EXPECT_EQ(edit->nodeId, "first-small");
    EXPECT_NEAR(edit->diagonalMm, 4.0 * std::sqrt(3.0), 1e-9);

    const Document moved = applyTypicalEdit(d, *edit, kTypicalEditMm);
    EXPECT_EQ(moved.root.find("first-small")->transform.translate.x, kTypicalEditMm);
    EXPECT_EQ(moved.root.find("second-small")->transform.translate.x, 0.0);
}

// A halfspace clipped by settings.bounds: a bounded part with nothing to move.
Document clippedHalfspace()
{
    return Document::parse(R"({"format":"kerf","version":1,"settings":{"bounds":[[-10,-10,-10],[10,10,10]]},
        "root":{"id":"h","type":"halfspace","normal":[0,0,1],"offset":0}})",
                           "test.kerf");
}

TEST(TypicalEdit, OnlyAHalfspaceGivesNoEdit) { EXPECT_FALSE(chooseTypicalEdit(clippedHalfspace())); }

TEST(TradeBench, FinerFeatureSizesCostMoreAndErrLess)
{
    // A plate with a rounded edge and a hole: flat, curved and sharp surfaces.
    const Document part = doc(R"({"id":"d","type":"difference","children":[
        {"id":"plate","type":"box","size":[60,40,12],"round":3},
        {"id":"hole","type":"cylinder","radius":6,"height":20}]})");
    TradeBenchOptions options;
    options.featureSizes = {4.0, 2.0, 1.0};
    options.width = 96;
    options.height = 72;
    options.frames = 1;
    options.cpu = true;
    const TradeReport r = runTradeBench(part, options);
    EXPECT_FALSE(r.vulkan);
    EXPECT_NE(r.device.find("CPU reference tracer"), std::string::npos);
    ASSERT_TRUE(r.edit);
    EXPECT_EQ(r.edit->nodeId, "hole");
    ASSERT_EQ(r.rows.size(), 3u);
    ASSERT_TRUE(r.volumeReference);
    EXPECT_EQ(r.volumeReference->cellSize, 1.0);
    // The plate's volume in closed form: the rounded box less the hole.
    // Each edge loses (1 - pi/4) r^2 per unit of its straight length, each
    // corner (1 - pi/6) r^3.
    const double rr = 3.0, box = 60.0 * 40.0 * 12.0 - (4.0 - std::numbers::pi) * rr * rr * (54.0 + 34.0 + 6.0) -
                                 (8.0 - 4.0 / 3.0 * std::numbers::pi) * rr * rr * rr;
    const double exact = box - std::numbers::pi * 36.0 * 12.0;
    EXPECT_NEAR(r.volumeReference->volume, exact, r.volumeReference->uncertainty);

    for (std::size_t i = 0; i < r.rows.size(); ++i) {
        SCOPED_TRACE(i);
        const TradeRow& row = r.rows[i];
        EXPECT_EQ(row.voxelSize, options.featureSizes[i]);
        EXPECT_GT(row.gpuBytes, 0u);
        EXPECT_GT(row.picture.bothHit, 1000u);
        ASSERT_TRUE(row.revoxelize);
        EXPECT_GT(row.revoxelize->dirtyTiles, 0u);
        EXPECT_LE(row.revoxelize->dirtyTiles, row.revoxelize->tiles);
        ASSERT_TRUE(row.exported);
        EXPECT_TRUE(row.exported->watertight);
        EXPECT_EQ(row.exported->distance.unresolved, 0u);
        EXPECT_EQ(row.exported->stlBytes, 84u + 50u * row.exported->triangles);
        if (i == 0) continue;
        const TradeRow& coarser = r.rows[i - 1];
        EXPECT_GT(row.gpuBytes, 2 * coarser.gpuBytes);
        EXPECT_GT(row.exported->triangles, 2 * coarser.exported->triangles);
        EXPECT_LT(row.picture.depthMm.mean, coarser.picture.depthMm.mean);
        EXPECT_LT(row.picture.normalDegrees.mean, coarser.picture.normalDegrees.mean);
        EXPECT_LT(row.exported->distance.mean, coarser.exported->distance.mean);
        EXPECT_LT(row.exported->distance.max, coarser.exported->distance.max);
        EXPECT_LT(std::abs(row.exported->volume - exact), std::abs(coarser.exported->volume - exact));
    }

    for (const TradeRow& row : r.rows)
        EXPECT_FALSE(row.exactEdges); // not asked for

    const auto j = tradeReportJson(r);
    EXPECT_EQ(j["results"].size(), 3u);
    EXPECT_EQ(j["edit"]["node"], "hole");
    EXPECT_TRUE(j["results"][2]["mesh"].contains("volume_error_mm3"));
    EXPECT_TRUE(j["results"][2]["picture"]["depth_error_mm"].contains("p99"));
}

TEST(TradeBench, TraceOnlyLeavesTheExportOut)
{
    TradeBenchOptions options;
    options.featureSizes = {2.0};
    options.width = 32;
    options.height = 24;
    options.frames = 1;
    options.cpu = true;
    options.traceOnly = true;
    const TradeReport r = runTradeBench(doc(R"({"id":"s","type":"sphere","radius":10})"), options);
    ASSERT_EQ(r.rows.size(), 1u);
    EXPECT_FALSE(r.rows[0].exported);
    EXPECT_FALSE(r.volumeReference);
    // A part with nothing to move is still measured, without re-voxelization.
    const TradeReport h = runTradeBench(clippedHalfspace(), options);
    EXPECT_FALSE(h.edit);
    ASSERT_EQ(h.rows.size(), 1u);
    EXPECT_FALSE(h.rows[0].revoxelize);
    EXPECT_GT(h.rows[0].picture.bothHit, 100u);
}

TEST(TradeBench, ExactEdgesSharpenTheSamePicture)
{
    // Two boxes meeting at a crease, less a tilted cylinder: edges the voxels
    // round off at a coarse feature size and the exact field keeps.
    const Document part = doc(R"({"id":"d","type":"difference","children":[
        {"id":"u","type":"union","children":[
            {"id":"a","type":"box","size":[40,30,20]},
            {"id":"b","type":"box","size":[30,30,30],"transform":{"translate":[15,0,5],"rotate":[0,35,0]}}]},
        {"id":"hole","type":"cylinder","radius":5,"height":80,"transform":{"rotate":[20,0,10]}}]})");
    TradeBenchOptions options;
    options.featureSizes = {4.0, 2.0};
    options.width = 120;
    options.height = 90;
    options.frames = 1;
    options.cpu = true;
    options.traceOnly = true;
    options.exactEdges = true;
    const TradeReport r = runTradeBench(part, options);
    ASSERT_EQ(r.rows.size(), 2u);
    for (const TradeRow& row : r.rows) {
        SCOPED_TRACE(row.featureSize);
        ASSERT_TRUE(row.exactEdges);
        const ImageError& voxels = row.picture;
        const ImageError& exact = row.exactEdges->picture;
        EXPECT_GT(row.exactEdges->traceMs, 0.0);
        // Same voxels, refined: the picture is several times closer to the
        // exact part in depth and normal, and the silhouette agrees better.
        EXPECT_LT(exact.depthMm.p99, voxels.depthMm.p99 / 4.0);
        EXPECT_LT(exact.depthMm.mean, voxels.depthMm.mean / 4.0);
        EXPECT_LT(exact.normalDegrees.mean, voxels.normalDegrees.mean / 4.0);
        EXPECT_LE(exact.mismatchFraction(), voxels.mismatchFraction());
        // And within a fraction of a voxel everywhere but a few pixels.
        EXPECT_LT(exact.depthMm.p99, 0.05 * row.voxelSize);
    }
    const auto j = tradeReportJson(r);
    EXPECT_TRUE(j["results"][0]["exact_edges"]["picture"]["depth_error_mm"].contains("p99"));
    EXPECT_GT(j["results"][0]["exact_edges"]["trace_ms"].get<double>(), 0.0);
}

} // namespace
} // namespace kerf

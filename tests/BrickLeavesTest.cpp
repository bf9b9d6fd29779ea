// Brick leaves (BrickLeaves.hpp) hold exactly the contree's voxels: every
// populated voxel's corners in its brick with the contree's codes, and every
// other sample on the side of the surface the exact field puts it.
#include "kerf/voxelizer/BrickLeaves.hpp"

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/VoxelFormat.hpp"
#include "kerf/voxelizer/VoxelQuery.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <map>
#include <string>
#include <tuple>

using namespace kerf;

namespace {

struct BrickCase {
    const char* example;
    double featureSize;
};

class BrickLeavesOfEveryExample : public ::testing::TestWithParam<BrickCase> {};

TEST_P(BrickLeavesOfEveryExample, HoldTheContreesVoxelsAndTheFieldsSigns)
{
    const BrickCase c = GetParam();
    const Document doc = Document::load(std::string(KERF_EXAMPLES_DIR) + "/" + c.example);
    const Tape tape = compileTape(doc);
    const GridLayout layout = GridLayout::choose(tape.bounds(), c.featureSize);
    const VoxelSnapshot snap = voxelize(tape, layout);
    const BrickLeaves bricks = BrickLeaves::fromVoxels(FlatVoxelBuffers::flatten(snap));
    ASSERT_FALSE(bricks.bricks.empty());
    ASSERT_EQ(bricks.distance.size(), bricks.bricks.size() * std::size_t(kBrickSampleCount));

    // Where each brick is: (tile, brick position in the tile) -> index.
    std::map<std::tuple<std::uint32_t, int, int, int>, std::size_t> where;
    for (std::size_t b = 0; b < bricks.bricks.size(); ++b) {
        const Brick& brick = bricks.bricks[b];
        const glm::dvec3 tileMin = layout.origin + layout.tileSize * glm::dvec3(layout.tileCoord(long(brick.tile)));
        const glm::ivec3 at(glm::round((brick.min - tileMin) / (brick.voxelMm * brick.cells)));
        EXPECT_TRUE(where.emplace(std::tuple(brick.tile, at.x, at.y, at.z), b).second) << "two bricks at one place";
    }

    // Every populated voxel (read by the contree's own reader): its brick
    // exists and holds its eight corners' codes and features.
    std::size_t voxels = 0, cornersOff = 0, missing = 0;
    std::vector<std::uint8_t> cornerOfAVoxel(bricks.distance.size(), 0);
    for (std::size_t t = 0; t < snap.tiles.size(); ++t) {
        const auto& tile = snap.tiles[t];
        if (!tile || tile->state != TileState::Surface) continue;
        const int finest = 1 << (2 * tile->levels);
        const int cells = std::min(kBrickCells, finest);
        const float voxelMm = float(layout.tileSize / finest);
        forEachVoxel(*tile, voxelMm, [&](const glm::ivec3& v, const VoxelCorners& corners) {
            ++voxels;
            const glm::ivec3 at = v / cells, local = v % cells;
            const auto it = where.find(std::tuple(std::uint32_t(t), at.x, at.y, at.z));
            if (it == where.end()) {
                ++missing;
                return;
            }
            for (int q = 0; q < 8; ++q) {
                const glm::ivec3 s = local + glm::ivec3(q & 1, (q >> 1) & 1, q >> 2);
                const std::size_t i = BrickLeaves::sampleIndex(it->second, s.x, s.y, s.z);
                cornerOfAVoxel[i] = 1;
                const std::uint32_t code = voxel::encodeDistanceFeature(corners.distance[q], voxelMm, 0) & 0xFFFF;
                cornersOff += std::int16_t(code) != bricks.distance[i] || corners.feature[q] != bricks.feature[i];
            }
        });
    }
    EXPECT_GT(voxels, 0u);
    EXPECT_EQ(missing, 0u) << "populated voxels without a brick, of " << voxels;
    EXPECT_EQ(cornersOff, 0u) << "corner samples that are not the contree's code, of " << voxels << " voxels";

    // The other samples: at the end of the range, with the sign of the exact
    // field there (a sample within a hundredth of a voxel of the surface may
    // take either).
    PointEvaluator<double> exact;
    std::size_t filled = 0, wrongSide = 0, notAtTheEnd = 0;
    for (std::size_t b = 0; b < bricks.bricks.size(); ++b) {
        const Brick& brick = bricks.bricks[b];
        for (int z = 0; z <= brick.cells; ++z)
            for (int y = 0; y <= brick.cells; ++y)
                for (int x = 0; x <= brick.cells; ++x) {
                    const std::size_t i = BrickLeaves::sampleIndex(b, x, y, z);
                    if (cornerOfAVoxel[i]) continue;
                    ++filled;
                    notAtTheEnd += std::abs(int(bricks.distance[i])) != 32767 || bricks.normal[i] != 0;
                    const glm::dvec3 p = brick.min + brick.voxelMm * glm::dvec3(x, y, z);
                    const double f = exact.evaluate(tape, p.x, p.y, p.z);
                    if (std::abs(f) > 0.01 * brick.voxelMm) wrongSide += (f > 0.0) != (bricks.distance[i] >= 0);
                }
    }
    EXPECT_GT(filled, 0u);
    EXPECT_EQ(notAtTheEnd, 0u);
    EXPECT_EQ(wrongSide, 0u) << "filled samples on the wrong side of the surface, of " << filled;
    // What a brick costs against the contree's leaves: stated in the test's
    // output (the benchmark has the figures).
    std::printf("%s at %.2f mm: %zu bricks, %zu populated voxels, %.1f MB of bricks against %.1f MB of contree\n",
                c.example, c.featureSize, bricks.bricks.size(), voxels, double(bricks.deviceBytes()) / 1e6,
                double(snap.bytes()) / 1e6);
}

INSTANTIATE_TEST_SUITE_P(Examples, BrickLeavesOfEveryExample,
                         ::testing::Values(BrickCase{"side-chair.kerf", 4.0}, BrickCase{"stool.kerf", 2.0},
                                           BrickCase{"table-top.kerf", 4.0}, BrickCase{"door-frame.kerf", 2.0},
                                           BrickCase{"bookshelf-side.kerf", 2.0}, BrickCase{"turned-leg.kerf", 1.0}),
                         [](const ::testing::TestParamInfo<BrickCase>& param) {
                             std::string name = param.param.example;
                             name = name.substr(0, name.find('.'));
                             for (char& ch : name)
                                 if (ch == '-') ch = '_';
                             return name;
                         });

} // namespace

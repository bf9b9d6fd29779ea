#include "kerf/voxelizer/BrickLeaves.hpp"

#include "kerf/voxelizer/VoxelFormat.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <unordered_map>

#include <tbb/parallel_for.h>

namespace kerf {

namespace {

std::uint32_t childRank(const voxel::Node& n, int c)
{
    const std::uint64_t below = c == 0 ? 0 : n.mask() & ((std::uint64_t(1) << c) - 1);
    return std::uint32_t(std::popcount(below));
}

std::uint32_t packSnorm8(const glm::vec3& n)
{
    auto byte = [](float v) { return std::uint32_t(std::uint8_t(std::int8_t(std::lround(glm::clamp(v, -1.0f, 1.0f) * 127.0f)))); };
    return byte(n.x) | byte(n.y) << 8 | byte(n.z) << 16;
}

// Samples no populated voxel of the brick has as a corner lie only on cells
// without a sign change: each takes the sign of a neighbour along a lattice
// edge (whose cells all have that sign), breadth first from the known ones,
// and its feature. Zero counts as outside, as in the contree. (A ray that
// enters a brick through a face already on the surface stops there, and its
// feature is the nearest sample's: on a face sample that only the
// neighbouring brick's voxels use, the feature next to it.)
void fillUnknown(BrickLeaves& out, std::size_t brick, std::vector<std::uint8_t>& known, std::vector<int>& queue)
{
    queue.clear();
    for (int s = 0; s < kBrickSampleCount; ++s)
        if (known[std::size_t(s)]) queue.push_back(s);
    const std::size_t base = brick * kBrickSampleCount;
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const int s = queue[head];
        const int x = s % kBrickSamples, y = (s / kBrickSamples) % kBrickSamples, z = s / (kBrickSamples * kBrickSamples);
        const std::int16_t end = out.distance[base + std::size_t(s)] >= 0 ? std::int16_t(32767) : std::int16_t(-32767);
        const int steps[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (const auto& d : steps) {
            const int nx = x + d[0], ny = y + d[1], nz = z + d[2];
            if (nx < 0 || ny < 0 || nz < 0 || nx >= kBrickSamples || ny >= kBrickSamples || nz >= kBrickSamples) continue;
            const int n = nx + kBrickSamples * (ny + kBrickSamples * nz);
            if (known[std::size_t(n)]) continue;
            known[std::size_t(n)] = 1;
            out.distance[base + std::size_t(n)] = end;
            out.feature[base + std::size_t(n)] = out.feature[base + std::size_t(s)];
            queue.push_back(n);
        }
    }
}

// One surface tile's bricks, in the order its voxels first reach them.
BrickLeaves tileBricks(const FlatVoxelBuffers& v, std::size_t t)
{
    BrickLeaves out;
    const GridLayout& grid = v.layout;
    const TileEntry& entry = v.entries[v.tiles[t]];
    const int levels = int(entry.levels);
    if (levels < 1) return out;
    const int finest = 1 << (2 * levels); // voxels along a tile edge
    const int cells = std::min(kBrickCells, finest);
    const double voxelMm = grid.tileSize / double(finest);
    const glm::dvec3 tileMin = grid.origin + grid.tileSize * glm::dvec3(grid.tileCoord(long(t)));
    std::unordered_map<std::uint64_t, std::uint32_t> brickOf; // the tile's bricks by position
    std::vector<std::vector<std::uint8_t>> known;               // their known samples
    struct Visit {
        std::uint32_t node;
        int depth;
        glm::ivec3 origin; // finest cells in the tile
    };
    std::vector<Visit> stack(1, {entry.node, 0, glm::ivec3(0)});
    while (!stack.empty()) {
        const Visit at = stack.back();
        stack.pop_back();
        const voxel::Node nd = v.nodes[at.node];
        const int childEdge = 1 << (2 * (levels - 1 - at.depth)); // finest cells per child
        for (int c = 0; c < 64; ++c) {
            if (!((nd.mask() >> c) & 1)) continue;
            const glm::ivec3 child = at.origin + childEdge * glm::ivec3(c & 3, (c >> 2) & 3, c >> 4);
            if (!nd.isLeaf()) {
                stack.push_back({entry.node + nd.pointer() + childRank(nd, c), at.depth + 1, child});
                continue;
            }
            // A populated voxel: its corners into its brick.
            const voxel::LeafIndirection li = v.leafIndirections[entry.leafIndirection + nd.pointer()];
            const voxel::LeafData ld = v.leafData[entry.leafData + li.leafData + childRank(nd, c)];
            const glm::ivec3 brick = child / cells, local = child % cells;
            const std::uint64_t key =
                std::uint64_t(brick.x) | std::uint64_t(brick.y) << 21 | std::uint64_t(brick.z) << 42;
            auto [it, inserted] = brickOf.try_emplace(key, std::uint32_t(out.bricks.size()));
            if (inserted) {
                out.bricks.push_back({tileMin + voxelMm * glm::dvec3(brick * cells), voxelMm, cells, std::uint32_t(t)});
                out.distance.resize(out.distance.size() + kBrickSampleCount, 0);
                out.normal.resize(out.normal.size() + kBrickSampleCount, 0);
                out.feature.resize(out.feature.size() + kBrickSampleCount, 0);
                known.emplace_back(std::size_t(kBrickSampleCount), std::uint8_t(0));
            }
            const std::uint32_t b = it->second;
            for (int q = 0; q < 8; ++q) {
                const glm::ivec3 s = local + glm::ivec3(q & 1, (q >> 1) & 1, q >> 2);
                const voxel::Vertex vx = v.vertices[entry.vertex + li.vertex + ld.corner[std::size_t(q)]];
                const std::size_t i = BrickLeaves::sampleIndex(b, s.x, s.y, s.z);
                out.distance[i] = std::int16_t(vx.distanceFeature & 0xFFFF);
                out.normal[i] = packSnorm8(voxel::decodeNormal(vx.normal));
                out.feature[i] = std::uint16_t(vx.distanceFeature >> 16);
                known[b][std::size_t(s.x + kBrickSamples * (s.y + kBrickSamples * s.z))] = 1;
            }
        }
    }
    std::vector<int> queue;
    for (std::size_t b = 0; b < out.bricks.size(); ++b)
        fillUnknown(out, b, known[b], queue);
    return out;
}

} // namespace

BrickLeaves BrickLeaves::fromVoxels(const FlatVoxelBuffers& v)
{
    // Tile by tile on every core, then joined in the tiles' order (the same
    // bricks in the same order whatever the threads).
    std::vector<std::size_t> surface;
    for (std::size_t t = 0; t < v.tiles.size(); ++t)
        if (v.tiles[t] != voxel::kEmptyTile && v.tiles[t] != voxel::kFullTile) surface.push_back(t);
    std::vector<BrickLeaves> parts(surface.size());
    tbb::parallel_for(std::size_t(0), surface.size(), [&](std::size_t i) { parts[i] = tileBricks(v, surface[i]); });
    BrickLeaves out;
    std::size_t bricks = 0;
    for (const BrickLeaves& p : parts)
        bricks += p.bricks.size();
    out.bricks.reserve(bricks);
    out.distance.reserve(bricks * kBrickSampleCount);
    out.normal.reserve(bricks * kBrickSampleCount);
    out.feature.reserve(bricks * kBrickSampleCount);
    for (BrickLeaves& p : parts) {
        out.bricks.insert(out.bricks.end(), p.bricks.begin(), p.bricks.end());
        out.distance.insert(out.distance.end(), p.distance.begin(), p.distance.end());
        out.normal.insert(out.normal.end(), p.normal.begin(), p.normal.end());
        out.feature.insert(out.feature.end(), p.feature.begin(), p.feature.end());
        p = BrickLeaves{};
    }
    return out;
}

} // namespace kerf

#include "kerf/voxelizer/TileBuilder.hpp"

#include "kerf/voxelizer/TileTape.hpp"

#include <glm/glm.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <array>
#include <bit>
#include <deque>
#include <limits>

namespace kerf {

namespace {

struct Cancelled {};

// Tiles at least this deep build their 64 children in parallel when a
// helper scratch is given (shallower ones are too small to pay for tasks).
constexpr int kParallelFromLevels = 3;

// A node of the contree while it is built; serialized afterwards so that
// children end up contiguous (breadth-first).
struct BuildNode {
    std::uint64_t mask = 0;
    bool leaf = false;
    std::vector<BuildNode> children;        // inner: one per set bit, in mask order
    std::vector<voxel::LeafData> voxels;    // leaf: one per set bit, in mask order
    std::vector<voxel::Vertex> vertices;    // leaf: the corners they use
};

class Builder {
public:
    Builder(TileBuildScratch& s, int levels, double tileSize, const Progress& work)
        : s_(s), levels_(levels), tileSize_(tileSize), work_(work)
    {
        if (s_.levelTapes.size() < std::size_t(levels + 1)) s_.levelTapes.resize(std::size_t(levels + 1));
    }

    // Builds the node whose cube starts at `lo` (tile-relative, mm) with the
    // tape s_.levelTapes[level]. Returns false when nothing is populated.
    bool build(const glm::dvec3& lo, int level, BuildNode& out)
    {
        const double size = tileSize_ / std::pow(4.0, level);
        const double child = size / 4.0;
        if (level == levels_ - 1) return buildLeaf(lo, child, level, out);
        if (work_.cancelled()) throw Cancelled{};
        if (level == 0 && levels_ >= kParallelFromLevels && s_.helper && !s_.quietVoxels)
            return buildChildrenInParallel(out);
        const Tape& tape = s_.levelTapes[std::size_t(level)];
        Tape& childTape = s_.levelTapes[std::size_t(level + 1)];
        for (int c = 0; c < 64; ++c) {
            const glm::dvec3 clo = lo + child * glm::dvec3(c & 3, (c >> 2) & 3, c >> 4);
            // Grown by a hair: the leaves sample float-rounded points (kIntervalBoxHair).
            const double hair = tileSize_ * kIntervalBoxHair;
            const Interval iv = s_.intervals.simplify(tape, Aabb{clo - hair, clo + glm::dvec3(child + hair)}, childTape);
            if (iv.lo > 0.0 || iv.hi < 0.0) continue; // provably empty or full
            BuildNode node;
            if (!build(clo, level + 1, node)) continue;
            out.mask |= std::uint64_t(1) << c;
            out.children.push_back(std::move(node));
        }
        return out.mask != 0;
    }

private:
    // A tile's children from different threads: each subtree is independent
    // (its tape simplified from the tile's, its records its own), and the
    // children are put back in mask order, so the tile is the serial one.
    bool buildChildrenInParallel(BuildNode& out)
    {
        const Tape tileTape = s_.levelTapes[0]; // a copy: helpers write their own level tapes
        const double child = tileSize_ / 4.0;
        std::array<BuildNode, 64> children;
        std::array<bool, 64> populated{};
        tbb::this_task_arena::isolate([&] {
            tbb::parallel_for(0, 64, [&](int c) {
                TileBuildScratch& h = s_.helper();
                Builder sub(h, levels_, tileSize_, work_);
                const glm::dvec3 clo = child * glm::dvec3(c & 3, (c >> 2) & 3, c >> 4);
                const double hair = tileSize_ * kIntervalBoxHair;
                const Interval iv =
                    h.intervals.simplify(tileTape, Aabb{clo - hair, clo + glm::dvec3(child + hair)}, h.levelTapes[1]);
                if (iv.lo > 0.0 || iv.hi < 0.0) return; // provably empty or full
                populated[std::size_t(c)] = sub.build(clo, 1, children[std::size_t(c)]);
            });
        });
        for (int c = 0; c < 64; ++c) {
            if (!populated[std::size_t(c)]) continue;
            out.mask |= std::uint64_t(1) << c;
            out.children.push_back(std::move(children[std::size_t(c)]));
        }
        return out.mask != 0;
    }

    // Keeps voxel c of the leaf at `lo` as a QuietVoxel if a corner lies
    // within its half-diagonal of the surface (with room for float rounding).
    void noteQuiet(const glm::dvec3& lo, double voxel, int c, const std::array<int, 8>& corner,
                   const std::array<float, 125>& d, bool inside)
    {
        float nearest = std::numeric_limits<float>::infinity();
        for (const int l : corner)
            nearest = std::min(nearest, std::abs(d[std::size_t(l)]));
        if (!(double(nearest) < 0.875 * voxel)) return;
        const glm::ivec3 base(glm::round(lo / voxel));
        s_.quietVoxels->push_back({base + glm::ivec3(c & 3, (c >> 2) & 3, c >> 4), inside});
    }

    bool buildLeaf(const glm::dvec3& lo, double voxel, int level, BuildNode& out)
    {
        const Tape& tape = s_.levelTapes[std::size_t(level)];
        std::array<float, 125> x, y, z, d;
        for (int k = 0; k < 5; ++k)
            for (int j = 0; j < 5; ++j)
                for (int i = 0; i < 5; ++i) {
                    const int l = voxel::latticeIndex(i, j, k);
                    x[l] = float(lo.x + voxel * i);
                    y[l] = float(lo.y + voxel * j);
                    z[l] = float(lo.z + voxel * k);
                }
        s_.points.evaluate(tape, x.data(), y.data(), z.data(), 125, d.data());

        std::array<std::int16_t, 125> vertexOf;
        vertexOf.fill(-1);
        std::array<float, 125> ux, uy, uz;
        std::array<std::uint8_t, 125> latticeOf; // the lattice point of each used vertex
        int used = 0;
        for (int c = 0; c < 64; ++c) {
            const int ci = c & 3, cj = (c >> 2) & 3, ck = c >> 4;
            int inside = 0;
            std::array<int, 8> corner;
            for (int q = 0; q < 8; ++q) {
                corner[std::size_t(q)] = voxel::latticeIndex(ci + (q & 1), cj + ((q >> 1) & 1), ck + (q >> 2));
                inside += d[std::size_t(corner[std::size_t(q)])] < 0.0f;
            }
            if (inside == 0 || inside == 8) { // no sign change: no surface crossing
                if (s_.quietVoxels) noteQuiet(lo, voxel, c, corner, d, inside == 8);
                continue;
            }
            out.mask |= std::uint64_t(1) << c;
            voxel::LeafData ld;
            for (int q = 0; q < 8; ++q) {
                const int l = corner[std::size_t(q)];
                if (vertexOf[std::size_t(l)] < 0) {
                    vertexOf[std::size_t(l)] = std::int16_t(used);
                    ux[std::size_t(used)] = x[std::size_t(l)];
                    uy[std::size_t(used)] = y[std::size_t(l)];
                    uz[std::size_t(used)] = z[std::size_t(l)];
                    latticeOf[std::size_t(used)] = std::uint8_t(l);
                    ++used;
                }
                ld.corner[std::size_t(q)] = std::uint8_t(vertexOf[std::size_t(l)]);
            }
            out.voxels.push_back(ld);
        }
        if (out.mask == 0) return false;
        out.leaf = true;
        std::array<float, 125> dist, gx, gy, gz;
        std::array<std::uint32_t, 125> feature;
        s_.gradients.evaluate(tape, ux.data(), uy.data(), uz.data(), std::size_t(used), dist.data(), gx.data(),
                              gy.data(), gz.data(), feature.data());
        out.vertices.resize(std::size_t(used));
        const float v = float(voxel);
        for (int u = 0; u < used; ++u) {
            const std::size_t k = std::size_t(u);
            glm::vec3 n(gx[k], gy[k], gz[k]);
            const float len = glm::length(n);
            n = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0, 0, 1);
            out.vertices[k].normal = voxel::encodeNormal(n);
            // The distance stored is the very value whose sign populated the
            // voxel (not the gradient pass's, which may round differently),
            // and its encoding keeps the sign: a populated voxel always
            // reads back with corners on both sides of the surface, whatever
            // the compiler made of the arithmetic.
            out.vertices[k].distanceFeature =
                voxel::encodeDistanceFeature(d[std::size_t(latticeOf[k])], v, feature[k]);
        }
        return true;
    }

    TileBuildScratch& s_;
    int levels_;
    double tileSize_;
    const Progress& work_;
};

TileData serialize(BuildNode& root, int levels)
{
    TileData t;
    t.state = TileState::Surface;
    t.levels = levels;
    std::deque<std::pair<BuildNode*, std::size_t>> queue;
    t.nodes.push_back({0, std::uint32_t(root.mask), std::uint32_t(root.mask >> 32)});
    queue.emplace_back(&root, 0);
    while (!queue.empty()) {
        auto [node, index] = queue.front();
        queue.pop_front();
        if (node->leaf) {
            t.nodes[index].header = voxel::kLeafFlag | std::uint32_t(t.leafIndirections.size());
            t.leafIndirections.push_back({std::uint32_t(t.leafData.size()), std::uint32_t(t.vertices.size())});
            t.leafData.insert(t.leafData.end(), node->voxels.begin(), node->voxels.end());
            t.vertices.insert(t.vertices.end(), node->vertices.begin(), node->vertices.end());
            continue;
        }
        t.nodes[index].header = std::uint32_t(t.nodes.size());
        for (auto& c : node->children) {
            queue.emplace_back(&c, t.nodes.size());
            t.nodes.push_back({0, std::uint32_t(c.mask), std::uint32_t(c.mask >> 32)});
        }
    }
    return t;
}

} // namespace

std::optional<TileData> buildTile(const Tape& tape, const GridLayout& layout, const glm::ivec3& tile, int levels,
                                  TileBuildScratch& scratch, const Progress& work)
{
    levels = std::clamp(levels, 1, voxel::kMaxLevels);
    const Aabb box = layout.tileBox(tile).grown(layout.tileSize * kIntervalBoxHair);
    TileData empty;
    empty.levels = levels;
    if (scratch.levelTapes.size() < std::size_t(levels + 1)) scratch.levelTapes.resize(std::size_t(levels + 1));
    Tape& tileTape = scratch.levelTapes[0];
    const Interval iv = scratch.intervals.simplify(tape, box, tileTape);
    if (iv.lo > 0.0) return empty;
    if (iv.hi < 0.0) {
        empty.state = TileState::Full;
        return empty;
    }
    // From here on, coordinates are relative to the tile's corner: float
    // keeps its precision however far the part is from the world origin.
    tileTape = tileTape.rebased(layout.tileBox(tile).min);
    BuildNode root;
    try {
        Builder builder(scratch, levels, layout.tileSize, work);
        if (!builder.build(glm::dvec3(0.0), 0, root)) {
            // Ambiguous to intervals but no sign change: report which side it
            // is on, at this depth (a deeper one may find a sign change).
            empty.unresolved = true;
            const double c = 0.5 * layout.tileSize;
            if (scratch.points.evaluate(scratch.levelTapes[0], float(c), float(c), float(c)) < 0.0f)
                empty.state = TileState::Full;
            return empty;
        }
    } catch (const Cancelled&) {
        return std::nullopt;
    }
    TileData built = serialize(root, levels);
    // The tape the tile was built from, for the tracer's exact refinement.
    built.tape = voxel::encodeTileTape(scratch.levelTapes[0]);
    return built;
}

} // namespace kerf

#include "kerf/voxelizer/RefinementPlan.hpp"

#include "kerf/voxelizer/OcclusionMap.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace kerf {

namespace {

constexpr double kBytesGrowthPerLevel = 16.0;

double estimate(const TileData& t, int levels)
{
    return double(t.bytes()) * std::pow(kBytesGrowthPerLevel, double(levels - t.levels));
}

} // namespace

double ViewRequirement::pixelSizeAt(double depth) const
{
    const double imageHeightMm = orthographic ? 2.0 * halfHeight : 2.0 * halfHeight * std::max(depth, 0.0);
    return imageHeightMm / double(std::max(imageHeight, 1));
}

double ViewRequirement::depthOf(const Aabb& box) const
{
    double nearest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                           c & 4 ? box.max.z : box.min.z);
        nearest = std::min(nearest, glm::dot(p - eye, forward));
    }
    return std::max(nearest, 0.0);
}

bool ViewRequirement::sees(const Aabb& box) const
{
    // A plane separates the box from the frustum when all 8 corners are
    // outside it. Planes: behind the eye's plane (perspective), and the four
    // sides. Side planes of a perspective frustum pass through the eye.
    glm::dvec3 corners[8];
    for (int c = 0; c < 8; ++c)
        corners[c] = glm::dvec3(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                                c & 4 ? box.max.z : box.min.z) -
                     eye;
    auto allOutside = [&](auto outside) {
        for (const auto& p : corners)
            if (!outside(p)) return false;
        return true;
    };
    const double halfW = halfHeight * aspect;
    if (orthographic) {
        if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, right) > halfW; })) return false;
        if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, right) < -halfW; })) return false;
        if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, up) > halfHeight; })) return false;
        if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, up) < -halfHeight; })) return false;
        return true;
    }
    if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, forward) < 0.0; })) return false;
    if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, right) > halfW * glm::dot(p, forward); })) return false;
    if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, right) < -halfW * glm::dot(p, forward); })) return false;
    if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, up) > halfHeight * glm::dot(p, forward); })) return false;
    if (allOutside([&](const glm::dvec3& p) { return glm::dot(p, up) < -halfHeight * glm::dot(p, forward); })) return false;
    return true;
}

RefinementPlan planRefinement(const GridLayout& layout, const std::vector<std::shared_ptr<const TileData>>& tiles,
                              const RefinementOptions& options)
{
    RefinementPlan plan;
    const std::size_t n = tiles.size();
    plan.levels.assign(n, 0);
    const int coarse = std::clamp(options.coarseLevels, 1, std::max(layout.levels, 1));
    std::vector<double> distance(n, 0.0);
    std::vector<std::int8_t> needed(n, 0);
    double total = 0.0;
    // The picture may show a surface as coarse as the coarsest tile: a finer
    // one may lie up to that voxel's diagonal behind it.
    const OcclusionMap* occlusion =
        options.view && options.occlusion && options.occlusion->view == *options.view ? options.occlusion.get() : nullptr;
    double occlusionMargin = 0.0;
    if (occlusion) {
        int shallowest = layout.levels;
        for (const auto& t : tiles)
            if (t && t->state == TileState::Surface) shallowest = std::min(shallowest, int(t->levels));
        occlusionMargin = layout.voxelSizeAt(std::max(shallowest, 1)) * std::sqrt(3.0);
        plan.occlusionMargin = occlusionMargin;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const auto& t = tiles[i];
        if (!t || !t->mayRefine()) continue;
        const Aabb box = layout.tileBox(layout.tileCoord(long(i)));
        int level = layout.levels;
        if (options.view) {
            const ViewRequirement& v = *options.view;
            if (!v.sees(box)) {
                level = coarse;
                distance[i] = std::numeric_limits<double>::infinity();
                ++plan.outsideView;
            } else if (occlusion && occlusion->hides(box, occlusionMargin)) {
                level = coarse;
                distance[i] = std::numeric_limits<double>::infinity();
                ++plan.hidden;
                plan.hiddenTiles.push_back(long(i));
            } else {
                const double allowed = v.pixelSizeAt(v.depthOf(box)) * v.pixelsPerVoxel;
                level = coarse;
                while (level < layout.levels && layout.voxelSizeAt(level) > allowed) ++level;
                distance[i] = glm::length(box.center() - v.eye);
            }
        } else {
            distance[i] = glm::length(box.center() - options.focus);
        }
        needed[i] = std::int8_t(level);
        plan.levels[i] = std::int8_t(level);
        total += estimate(*t, level);
    }
    // Over the budget: the farthest tiles give up a level at a time.
    if (options.memoryBudgetBytes > 0 && total > double(options.memoryBudgetBytes)) {
        std::priority_queue<std::pair<double, std::size_t>> farthest;
        for (std::size_t i = 0; i < n; ++i)
            if (plan.levels[i] > 1) farthest.emplace(distance[i], i);
        while (total > double(options.memoryBudgetBytes) && !farthest.empty()) {
            const std::size_t i = farthest.top().second;
            farthest.pop();
            const int level = plan.levels[i];
            total -= estimate(*tiles[i], level) - estimate(*tiles[i], level - 1);
            plan.levels[i] = std::int8_t(level - 1);
            if (level - 1 > 1) farthest.emplace(distance[i], i);
        }
        for (std::size_t i = 0; i < n; ++i) plan.coarsenedForBudget += plan.levels[i] < needed[i];
    }
    plan.estimatedBytes = std::size_t(std::max(total, 0.0));
    return plan;
}

} // namespace kerf

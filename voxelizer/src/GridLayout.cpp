#include "kerf/voxelizer/GridLayout.hpp"

#include "kerf/document/Limits.hpp"

#include "kerf/voxelizer/VoxelFormat.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <sstream>

namespace kerf {

double defaultFeatureSize(const Aabb& bounds)
{
    if (bounds.isEmpty() || !bounds.isBounded()) return 1.0;
    const glm::dvec3 e = bounds.size();
    const double target = std::max({e.x, e.y, e.z}) / 1000.0;
    if (!(target > 0.0)) return 1.0;
    // Within the feature sizes a document may set: a sphere of 1e-300 mm
    // got 2e-303 mm (check said "0 populated voxels of 2e-303 mm").
    if (target <= limits::kMinFeatureSize) return limits::kMinFeatureSize;
    if (target >= limits::kMaxFeatureSize) return limits::kMaxFeatureSize;
    const double decade = std::pow(10.0, std::floor(std::log10(target)));
    for (double m : {5.0, 2.0, 1.0})
        if (m * decade <= target) return m * decade;
    return decade;
}

double GridLayout::voxelSizeAt(int lv) const { return tileSize / std::pow(4.0, lv); }

GridLayout GridLayout::choose(const Aabb& partBounds, double featureSize, const GridLimits& limits)
{
    GridLayout g;
    if (partBounds.isEmpty() || !partBounds.isBounded() || !(featureSize > 0.0)) return g;
    const int maxLevels = std::clamp(limits.maxLevels, 1, voxel::kMaxLevels);
    // One voxel of margin on every side keeps the surface off the grid's
    // boundary, so every surface voxel has all its neighbours in the grid.
    // In double: a 200 km part at 1e-6 mm is 1e13 tiles a side, which an
    // int held as INT_MIN (a negative count that "fit", and a crash after).
    auto dimsFor = [&](double tile, double voxel) {
        const glm::dvec3 e = partBounds.size() + glm::dvec3(2.0 * voxel);
        return glm::max(glm::dvec3(1.0), glm::ceil(e / tile));
    };
    double voxel = featureSize;
    int levels = std::clamp(limits.minLevels, 1, maxLevels);
    for (;; ++levels) {
        const glm::dvec3 d = dimsFor(voxel * std::pow(4.0, levels), voxel);
        if (d.x * d.y * d.z <= double(limits.maxTiles) || levels == maxLevels) break;
    }
    glm::dvec3 dims = dimsFor(voxel * std::pow(4.0, levels), voxel);
    if (dims.x * dims.y * dims.z > double(limits.maxTiles)) {
        // Too fine for the addressing: coarsen the voxels until the grid fits.
        const double requested = voxel;
        while (dims.x * dims.y * dims.z > double(limits.maxTiles)) {
            voxel *= 1.25;
            dims = dimsFor(voxel * std::pow(4.0, levels), voxel);
        }
        std::ostringstream s;
        s << "feature size " << requested << " mm needs more than " << maxLevels
          << " contree levels; voxels are " << voxel << " mm instead";
        g.note = s.str();
    }
    g.levels = levels;
    g.voxelSize = voxel;
    g.tileSize = voxel * std::pow(4.0, levels);
    g.dims = glm::ivec3(dims); // at most maxTiles in all: within int
    g.origin = partBounds.center() - 0.5 * glm::dvec3(dims) * g.tileSize;
    return g;
}

} // namespace kerf

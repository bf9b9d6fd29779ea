#pragma once
// How deep each tile should be built: only as fine as the view needs, and
// within a memory budget.
//
// - A tile the camera sees is built to the coarsest depth whose voxels still
//   project to at most about a pixel (ViewRequirement::pixelsPerVoxel) at the
//   tile's nearest point, and never finer than the grid's full depth (the
//   feature size). A tile outside the picture stays at the coarse depth the
//   background pass builds; it refines when the view turns to it.
// - Without a view (headless work, tests) every tile goes to full depth.
// - When the estimated bytes exceed the budget, the farthest tiles (outside
//   the view first) lose a level at a time until the estimate fits or
//   nothing can coarsen further; the plan says how many were coarsened.
//
// - A tile inside the picture that the last picture of the same view shows
//   hidden (OcclusionMap.hpp: every ray that could reach it met the part
//   sooner, by more than the coarsest voxels' diagonal) stays at the coarse
//   depth too; the next picture refines it if it comes into sight.
//
// Estimates: a surface tile's bytes grow 16x per level (its surface is
// sampled 4x finer along two dimensions), from the tile's data as it is.

#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/TileData.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace kerf {

struct OcclusionMap;

/// What the viewer needs, from the camera: its frame and how large a pixel is.
struct ViewRequirement {
    glm::dvec3 eye{0.0};
    glm::dvec3 forward{0.0, 1.0, 0.0}, right{1.0, 0.0, 0.0}, up{0.0, 0.0, 1.0}; // unit, orthonormal
    bool orthographic = false;
    /// tan(fovY / 2) for a perspective camera, half the image height in mm
    /// for an orthographic one.
    double halfHeight = 0.2679;
    double aspect = 1.0;      // image width / height
    int imageHeight = 1080;   // pixels
    double pixelsPerVoxel = 1.0;

    /// The edge (mm) of a pixel at `depth` mm in front of the eye.
    double pixelSizeAt(double depth) const;
    /// Whether any part of the box can be in the picture (a conservative
    /// test against the view frustum's side planes and the eye's plane).
    bool sees(const Aabb& box) const;
    /// The nearest depth (along the view) of the box in front of the eye; 0
    /// when the eye's plane cuts the box.
    double depthOf(const Aabb& box) const;
    bool operator==(const ViewRequirement&) const = default;
};

struct RefinementOptions {
    std::optional<ViewRequirement> view;
    /// Estimated voxel bytes the plan may reach (0: no limit).
    std::size_t memoryBudgetBytes = 0;
    /// Depth of tiles outside the view (and the shallowest the budget may
    /// coarsen to), at least 1.
    int coarseLevels = 1;
    /// Where "far" is measured from without a view (the focus point).
    glm::dvec3 focus{0.0};
    /// The last picture of `view`, when there is one (a map of another view
    /// is not used).
    std::shared_ptr<const OcclusionMap> occlusion;
};

struct RefinementPlan {
    std::vector<std::int8_t> levels; // per tile: target depth (0 where there is no surface)
    std::size_t estimatedBytes = 0;  // of the tiles' records at their target depths
    std::size_t coarsenedForBudget = 0; // tiles planned below what the view needs
    std::size_t outsideView = 0;        // surface tiles the camera does not see
    std::size_t hidden = 0;             // surface tiles in the picture but behind the part
    std::vector<long> hiddenTiles;      // ... which they are
    double occlusionMargin = 0.0;       // mm: how much nearer the picture had to be to hide them
};

/// Plans every tile's depth. `tiles` holds the tiles' present data (null:
/// empty); a surface tile's estimate is scaled from its bytes at its depth.
RefinementPlan planRefinement(const GridLayout& layout, const std::vector<std::shared_ptr<const TileData>>& tiles,
                              const RefinementOptions& options);

} // namespace kerf

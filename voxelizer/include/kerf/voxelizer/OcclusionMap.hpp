#pragma once
// What the last picture of the part showed, coarsely: for each block of
// pixels, the farthest depth any of its rays reached before meeting the
// part. A tile is hidden when every ray that could reach it met the part
// sooner, by more than the surface may still move: the viewer cannot see it,
// so it need not be finer than the coarse pass (RefinementPlan.hpp).
//
// The picture comes from the viewport (it traces every pixel anyway), taken
// with one view; the map says nothing of any other view. It is sound for the
// surface it was traced from: every pixel counts (a gap of a single pixel
// keeps what is behind it visible), and a block where any ray saw nothing
// hides nothing. When the surface changes (finer voxels open a gap the
// coarse ones closed, an edit removes an occluder), the next picture shows
// it and the tiles behind refine: the map follows the pictures.
//
// Depths follow the tracer's convention (Camera.hpp): distance along the
// pixel's unit ray from the eye (perspective) or from the eye's plane
// (orthographic), +infinity where the ray hits nothing.

#include "kerf/document/Aabb.hpp"
#include "kerf/voxelizer/RefinementPlan.hpp"

#include <glm/vec2.hpp>

#include <span>
#include <vector>

namespace kerf {

struct OcclusionMap {
    ViewRequirement view; // the view the picture was traced with
    int width = 0, height = 0; // the picture, pixels
    int block = 8;             // pixels per block side
    int columns = 0, rows = 0; // blocks
    std::vector<float> farthest; // per block, row-major from the top; +inf where a ray saw nothing

    /// The map of a picture of `width` x `height` depths (row 0 at the top).
    /// NaN and non-positive depths count as rays that saw nothing.
    static OcclusionMap fromDepths(const ViewRequirement& view, int width, int height, std::span<const float> depths,
                                   int block = 8);

    /// Where `p` lands in the picture (pixels, (0, 0) the top-left corner);
    /// false when it is not in front of the eye's plane.
    bool project(const glm::dvec3& p, glm::dvec2& pixel) const;

    /// Whether every ray of the picture that could reach `box` met the part
    /// more than `margin` mm before it: true only when the box lies wholly in
    /// front of the eye's plane and inside the picture's blocks it covers.
    bool hides(const Aabb& box, double margin) const;
};

} // namespace kerf

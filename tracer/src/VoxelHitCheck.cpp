#include "kerf/tracer/VoxelHitCheck.hpp"

#include "kerf/tracer/ExactRefinement.h"
#include "kerf/voxelizer/TileTape.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>

// Written to be ported to GLSL (shaders/trace.comp, judgeVoxelHit): keep
// the two in step.

namespace kerf {

VoxelHitVerdict checkVoxelHit(const FlatVoxelBuffers& b, const glm::vec3& origin, const glm::vec3& dir,
                              const glm::vec4& plane, const RayHit& voxelHit, RayHit& refined)
{
    refined = voxelHit;
    // A refined ray searches around every populated voxel it meets: where
    // it passed close to the trilinear surface of one before its hit (or
    // without a hit), the exact surface, which departs from the trilinear
    // one at edges, may be there.
    if (voxelHit.passedClearance < 1.0f) return VoxelHitVerdict::Refine;
    if (!voxelHit.hit() || voxelHit.feature == kSectionCap) return VoxelHitVerdict::Keep;

    const float tileSize = float(b.layout.tileSize);
    const glm::ivec3 dims = b.layout.dims;
    const glm::vec3 p = origin + voxelHit.depth * dir;
    const glm::ivec3 tile = glm::clamp(glm::ivec3(glm::floor(p / tileSize)), glm::ivec3(0), dims - 1);
    const std::uint32_t value = b.tiles[std::size_t(tile.x + dims.x * (tile.y + dims.y * tile.z))];
    // The hit rounded into a tile without voxels: let the refinement decide.
    if (value == voxel::kEmptyTile || value == voxel::kFullTile) return VoxelHitVerdict::Refine;
    const TileEntry& entry = b.entries[value];
    if (entry.tape == voxel::kNoTape) return VoxelHitVerdict::Keep; // traced on its voxels either way
    const std::uint32_t* tape = b.tapes.data() + entry.tape;
    const float voxelEdge = tileSize / float(1 << (2 * int(entry.levels)));

    // One Newton step along the ray from the voxels' hit, with their
    // interpolated normal standing in for the gradient (a unit gradient: a
    // distance field; where a blend shortens it, the step falls short and
    // the second one finishes it).
    const glm::vec3 local = p - glm::vec3(tile) * tileSize;
    const float f0 = voxel::evaluateTileTape(tape, local);
    ++refined.evaluations;
    const float voxelSlope = glm::dot(voxelHit.normal, dir);
    if (!(voxelSlope < -float(KERF_EDGE_CHECK_FACING))) return VoxelHitVerdict::Refine;
    const float step = -f0 / voxelSlope;
    if (!(glm::abs(step) <= float(KERF_EDGE_CHECK_SHIFT) * voxelEdge)) return VoxelHitVerdict::Refine;
    const glm::vec3 landed = local + step * dir;
    if (glm::any(glm::lessThan(landed, glm::vec3(0.0f))) || glm::any(glm::greaterThan(landed, glm::vec3(tileSize))))
        return VoxelHitVerdict::Refine;
    // Where it lands: the field, its gradient (the normal) and the feature.
    std::uint32_t feature = kNoFeature;
    const glm::vec4 fg = voxel::evaluateTileTapeGradient(tape, landed, feature);
    ++refined.evaluations;
    const glm::vec3 g(fg.y, fg.z, fg.w);
    const float length = glm::length(g);
    const float slope = glm::dot(g, dir); // the field's derivative along the ray
    if (!(slope < -float(KERF_EDGE_CHECK_FACING) * length)) return VoxelHitVerdict::Refine;
    // The second Newton step, with the exact slope, must be short: its
    // error grows with the square of its length.
    const float finish = -fg.x / slope;
    if (!(glm::abs(finish) <= float(KERF_EDGE_CHECK_RESIDUAL) * voxelEdge)) return VoxelHitVerdict::Refine;
    // An edge between the voxels' hit and the exact surface: the exact
    // normal turned away from the voxels'.
    if (!(glm::dot(g, voxelHit.normal) >= std::cos(glm::radians(float(KERF_EDGE_CHECK_SMOOTH_ANGLE))) * length))
        return VoxelHitVerdict::Refine;

    // Where the second step lands must be on the surface, as the refinement's
    // crossings are: at an edge the exact slope of one face can carry it off
    // the other.
    const glm::vec3 finished = landed + finish * dir;
    if (glm::any(glm::lessThan(finished, glm::vec3(0.0f))) ||
        glm::any(glm::greaterThan(finished, glm::vec3(tileSize))))
        return VoxelHitVerdict::Refine;
    ++refined.evaluations;
    if (!(glm::abs(voxel::evaluateTileTape(tape, finished)) <= float(KERF_EDGE_CHECK_ON_SURFACE) * voxelEdge))
        return VoxelHitVerdict::Refine;

    const float depth = voxelHit.depth + step + finish;
    // Moved past a section plane: the refinement knows what is cut away.
    const glm::vec3 n(plane);
    if (n != glm::vec3(0.0f) && glm::dot(n, origin + depth * dir) > plane.w) return VoxelHitVerdict::Refine;
    refined.depth = depth;
    refined.normal = g / length;
    refined.feature = feature;
    return VoxelHitVerdict::Confirm;
}

} // namespace kerf

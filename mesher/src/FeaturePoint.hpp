#pragma once
// Where a sharp edge or corner passes through a marching-cubes cell: the
// point that best fits the tangent planes of the cell polygon's vertices
// (extended marching cubes: Kobbelt, Botsch, Schwanecke, Seidel 2001).
//
// Each vertex p_i with unit normal n_i gives the plane n_i . (x - p_i) = 0.
// The least-squares point of those planes is found around the vertices'
// mean m with a truncated pseudo-inverse of A = sum n_i n_i^T: directions
// whose singular value is below a tenth of the largest are left at m. A flat
// patch (one plane) moves m onto it; two planes give the point of their
// line nearest m (an edge); three independent ones their common point (a
// corner). Whether the point is on the part's surface is for the caller to
// check: on a smooth curved patch the tangent planes meet off the surface.

#include <glm/vec3.hpp>

#include <optional>

namespace kerf::mesher {

/// Vertices whose normals differ by more than this angle (cosine) in one
/// polygon mark a sharp feature inside the cell.
inline constexpr double kFeatureCosine = 0.9;

/// The smallest cosine between the normals of a polygon's vertices.
double smallestNormalCosine(const glm::dvec3* normals, int count);

/// The least-squares point of the tangent planes, and how many independent
/// directions constrained it (1 flat, 2 edge, 3 corner). For rank 2 and 3,
/// `edgePoint` and `edgeDirection` describe the line of the two strongest
/// directions alone (the crease): for rank 2 `point` lies on it.
struct FeatureFit {
    glm::dvec3 point{0.0};
    int rank = 0;
    glm::dvec3 edgePoint{0.0};
    glm::dvec3 edgeDirection{0.0};
};
FeatureFit fitTangentPlanes(const glm::dvec3* points, const glm::dvec3* normals, int count);

/// The point of the fit's crease line nearest its `point` among those
/// inside the box (lo, hi), or nothing when the line misses the box.
std::optional<glm::dvec3> edgePointInBox(const FeatureFit& fit, const glm::dvec3& lo, const glm::dvec3& hi);

} // namespace kerf::mesher

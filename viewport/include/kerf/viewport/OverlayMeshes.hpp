#pragma once
// Small meshes the viewport draws over the part (SceneRenderer's markers):
// measured points, dimension lines, the move gizmo's arrows and squares,
// a bounding box's edges. World coordinates in mm; sizes are chosen by the
// caller from the view (so they look the same at any zoom).

#include "kerf/document/Aabb.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"

#include <glm/vec3.hpp>

#include <array>

namespace kerf {

/// A small octahedron around `p`.
PlacedMesh markerMesh(const glm::dvec3& p, double radius, glm::vec3 color);

/// A round bar from `a` to `b` (open ends: it is always seen from the side
/// or joined to something).
PlacedMesh barMesh(const glm::dvec3& a, const glm::dvec3& b, double radius, glm::vec3 color);

/// An arrow: a bar from `from` along `axis` (unit) for `length`, its last
/// fifth a cone three times the bar's radius.
PlacedMesh arrowMesh(const glm::dvec3& from, const glm::dvec3& axis, double length, double radius, glm::vec3 color);

/// A flat quadrilateral, visible from both sides (corners in order).
PlacedMesh quadMesh(const std::array<glm::dvec3, 4>& corners, glm::vec3 color);

/// The twelve edges of a box as bars.
PlacedMesh boxEdgesMesh(const Aabb& box, double radius, glm::vec3 color);

} // namespace kerf

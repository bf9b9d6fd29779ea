#pragma once
// Triangulation of one cell polygon (a cycle of CellPolygons.hpp, 3 to 12
// vertices on distinct cell edges).
//
// Topological rule: a diagonal may not join two vertices that lie on a common
// cell face. Such a pair can also be joined in the neighbouring cell across
// that face, and the mesh edge would then have four triangles. With the rule,
// every added diagonal belongs to its cell alone.
//
// Geometric choice: among the triangulations the rule allows, the one whose
// worst triangle is best (dynamic programming over the polygon, O(n^3)).
// Quality is 4 sqrt(3) area / (sum of squared edge lengths), 1 for an
// equilateral triangle, signed by the triangle's normal against the
// polygon's (Newell) normal, so folded triangles lose to flat ones. Three
// vertices on three distinct edges of a cube are never collinear, so the
// triangles have non-zero area in exact arithmetic; the quality measure keeps
// them away from slivers where the polygon allows.

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace kerf {

inline constexpr int kMaxPolygon = 12;

/// Writes n - 2 triangles (indices into the polygon, in the polygon's
/// orientation) to `out` and returns their number; returns 0 when no
/// triangulation satisfies the face rule. `faceMasks[i]`: the cell faces
/// vertex i lies on (CellPolygons' edgeFaceMask). 3 <= n <= kMaxPolygon.
int triangulatePolygon(const glm::dvec3* points, const std::uint8_t* faceMasks, int n,
                       std::array<std::uint8_t, 3>* out);

/// Whether some triangulation satisfies the face rule (topology only).
bool hasAllowedTriangulation(const std::uint8_t* faceMasks, int n);

} // namespace kerf

#pragma once
// The second step of extended marching cubes (Kobbelt et al. 2001): a cell
// whose polygon has a feature vertex is a fan around it, and two fans in
// neighbouring cells meet along an edge (u, w) of the cell face between them,
// which cuts across the sharp edge of the part. Flipping that edge to join
// the two feature vertices puts the sharp edge into the mesh as a chain of
// mesh edges, and leaves each triangle on one side of it.

#include "kerf/mesher/Mesh.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace kerf::mesher {

/// Flips, in `mesh`, every edge whose two triangles have feature vertices
/// (normals[v] == 0) opposite it, unless the two are joined already or the
/// flip would fold a triangle over. Returns the number of flips.
std::uint64_t flipFeatureEdges(Mesh& mesh, const std::vector<glm::dvec3>& normals);

} // namespace kerf::mesher

#pragma once
// An indexed triangle mesh in world millimetres, as the mesher produces it.
//
// Vertices are in double: a part 100 m from the origin keeps its sub-micron
// detail (float would round to about 8 micrometres there). Triangles list
// their vertices counter-clockwise seen from outside the solid, so normals
// by the right-hand rule point outward.
//
// Why not an OpenMesh halfedge mesh: at the finest feature sizes a chair has
// a quarter of a billion triangles, and a halfedge structure costs about
// three times this layout (see docs/benchmarks.md). OpenMeshAdapter.hpp
// converts both ways, and the STL writer goes through OpenMesh's own writer
// straight from this layout.

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace kerf {

struct Mesh {
    std::vector<glm::dvec3> vertices;                    // mm, world coordinates
    std::vector<std::array<std::uint32_t, 3>> triangles; // indices into vertices, outward orientation

    bool empty() const { return triangles.empty(); }
    std::size_t bytes() const
    {
        return vertices.capacity() * sizeof(glm::dvec3) + triangles.capacity() * sizeof(triangles[0]);
    }
};

} // namespace kerf

#pragma once
// Checks that a triangle mesh bounds a solid: closed, 2-manifold,
// consistently oriented, no degenerate triangles; and measures it (Euler
// characteristic, components, genus, signed volume, area). Used by the tests
// and by `kerf export` to report closedness.
//
// Method: vertex -> triangle incidence (CSR), then at every vertex v the
// "link" of its triangles: each triangle (v, a, b), rotated so v comes first,
// contributes the link edge a -> b. The mesh is a closed, oriented 2-manifold
// at v iff every neighbour u appears exactly once as a link-edge start
// (triangle with edge v -> u) and once as an end (edge u -> v), and the link
// edges form one cycle (one disc of triangles around v). Memory: 4 bytes per
// vertex and 12 per triangle besides the mesh; threads: oneTBB over vertices.

#include "kerf/mesher/Mesh.hpp"

#include <cstddef>
#include <optional>

namespace kerf {

struct MeshReport {
    std::size_t vertices = 0; // used by at least one triangle
    std::size_t unusedVertices = 0;
    std::size_t triangles = 0;
    std::size_t edges = 0;
    std::size_t boundaryEdges = 0;       // in one triangle only
    std::size_t nonManifoldEdges = 0;    // in three or more triangles
    std::size_t misorientedEdges = 0;    // in two triangles that run along it the same way
    std::size_t nonManifoldVertices = 0; // whose triangles form more than one disc (edges being fine)
    std::size_t degenerateTriangles = 0; // a repeated vertex or zero area (in double)
    std::size_t components = 0;          // connected through edges
    long eulerCharacteristic = 0;        // V - E + F over used vertices
    double volume = 0.0;                 // mm^3, positive when triangles face outward
    double area = 0.0;                   // mm^2
    double smallestArea = 0.0;           // mm^2, of the smallest triangle

    bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0; }
    bool manifold() const { return nonManifoldEdges == 0 && nonManifoldVertices == 0; }
    bool oriented() const { return misorientedEdges == 0; }
    /// Closed, manifold, oriented, no degenerate triangles, outward.
    bool watertight() const { return closed() && manifold() && oriented() && degenerateTriangles == 0 && volume > 0.0; }
    /// Total genus (sum over components), for a closed oriented manifold.
    std::optional<long> genus() const
    {
        if (!closed() || !manifold() || !oriented()) return std::nullopt;
        return (2 * long(components) - eulerCharacteristic) / 2;
    }
};

MeshReport checkMesh(const Mesh& mesh);

} // namespace kerf

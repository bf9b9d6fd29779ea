#pragma once
// Kerf meshes as OpenMesh halfedge meshes and back, for code that wants
// OpenMesh's algorithms (and for the tests: OpenMesh refuses faces that
// would make an edge or a vertex non-manifold, an independent check of the
// mesher's topology). Points are double.

#include "kerf/mesher/Mesh.hpp"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstddef>

namespace kerf {

struct OpenMeshTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using OpenTriMesh = OpenMesh::TriMesh_ArrayKernelT<OpenMeshTraits>;

/// Builds the halfedge mesh. `refused` (optional) receives the number of
/// triangles OpenMesh refused to add (complex edge or vertex); a closed
/// 2-manifold has none.
OpenTriMesh toOpenMesh(const Mesh& mesh, std::size_t* refused = nullptr);

/// The triangles of an OpenMesh mesh (faces with more sides are fanned).
Mesh fromOpenMesh(const OpenTriMesh& mesh);

} // namespace kerf

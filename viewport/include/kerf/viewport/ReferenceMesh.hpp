#pragma once
// Reference triangle meshes (STL, OBJ, PLY, OFF) loaded with OpenMesh and
// placed in the world: the document's `meshes`, drawn beside the part and
// mixed with it by depth. Not part of the CSG, never exported.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Affine.hpp"
#include "kerf/document/Document.hpp"

#include <glm/vec3.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace kerf {

/// Triangles with one normal per corner (flat: each triangle has its own
/// three vertices), positions in mm in the mesh's own frame.
struct TriangleMesh {
    std::vector<glm::dvec3> positions;
    std::vector<glm::vec3> normals;
    Aabb bounds;
    std::size_t triangles() const { return positions.size() / 3; }
};

/// Loads a mesh file (format from the extension). Throws std::runtime_error
/// with one line naming the file and the reason (missing, unreadable, not a
/// mesh, no triangles).
TriangleMesh loadTriangleMesh(const std::filesystem::path& file);

struct PlacedMesh {
    std::string id;
    TriangleMesh mesh;
    Affine worldFromLocal;
    glm::vec3 color{0.63f, 0.63f, 0.63f}; // linear RGB
    float opacity = 1.0f; // below 1 only for ghosts (SceneRenderer::setGhosts)
    Aabb worldBounds() const { return worldFromLocal.apply(mesh.bounds); }
};

/// Loads the document's reference meshes (paths relative to
/// `documentFolder`). A mesh that cannot be loaded is left out and its
/// reason appended to `problems` ("mesh 'hinge': hinge.stl: no such file");
/// the others still load.
std::vector<PlacedMesh> loadReferenceMeshes(const Document& doc, const std::filesystem::path& documentFolder,
                                            std::vector<std::string>& problems);

} // namespace kerf

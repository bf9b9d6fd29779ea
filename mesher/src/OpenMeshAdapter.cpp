#include "kerf/mesher/OpenMeshAdapter.hpp"

#include <vector>

namespace kerf {

OpenTriMesh toOpenMesh(const Mesh& mesh, std::size_t* refused)
{
    OpenTriMesh out;
    out.reserve(mesh.vertices.size(), mesh.triangles.size() * 3 / 2, mesh.triangles.size());
    std::vector<OpenTriMesh::VertexHandle> handles;
    handles.reserve(mesh.vertices.size());
    for (const glm::dvec3& p : mesh.vertices)
        handles.push_back(out.add_vertex({p.x, p.y, p.z}));
    std::size_t failed = 0;
    for (const auto& t : mesh.triangles) {
        const auto f = out.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
        if (!f.is_valid()) ++failed;
    }
    if (refused) *refused = failed;
    return out;
}

Mesh fromOpenMesh(const OpenTriMesh& mesh)
{
    Mesh out;
    out.vertices.reserve(mesh.n_vertices());
    for (const auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        out.vertices.emplace_back(p[0], p[1], p[2]);
    }
    for (const auto f : mesh.faces()) {
        std::vector<std::uint32_t> ids;
        for (const auto v : mesh.fv_range(f))
            ids.push_back(std::uint32_t(v.idx()));
        for (std::size_t k = 1; k + 1 < ids.size(); ++k)
            out.triangles.push_back({ids[0], ids[k], ids[k + 1]});
    }
    return out;
}

} // namespace kerf

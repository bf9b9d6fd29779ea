#pragma once
// An OpenMesh exporter over kerf's Mesh layout: OpenMesh's writers read
// vertices and triangles straight from it, with no halfedge copy (which
// would triple the memory of a large export). Only what mesh writers need is
// real: points, faces (triangles), face normals (computed in double); every
// colour, texture coordinate, status and halfedge query returns a neutral
// value. Written against OpenMesh 9.0's BaseExporter (Debian 12).

#include "kerf/document/Progress.hpp"
#include "kerf/mesher/Mesh.hpp"

#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>

#include <glm/glm.hpp>

namespace kerf::mesher {

class MeshExporter : public OpenMesh::IO::BaseExporter {
public:
    /// Thrown from inside OpenMesh's writer when `work` is cancelled.
    struct Cancelled {};

    /// `work` hears how far the writer is through the triangles (OpenMesh's
    /// writers ask for each triangle's corners once, in order), and stops it
    /// by MeshExporter::Cancelled.
    explicit MeshExporter(const Mesh& mesh, const Progress& work = {}) : mesh_(mesh), work_(work) {}

    OpenMesh::Vec3f point(OpenMesh::VertexHandle v) const override
    {
        const glm::dvec3& p = mesh_.vertices[std::size_t(v.idx())];
        return {float(p.x), float(p.y), float(p.z)};
    }
    // The float32 value in double: binary STL stores float32, and ASCII STL
    // (printed with 9 significant digits) then holds exactly the same
    // coordinates, so that both read back as WrittenFormat::Float32 says.
    OpenMesh::Vec3d pointd(OpenMesh::VertexHandle v) const override
    {
        const OpenMesh::Vec3f p = point(v);
        return {double(p[0]), double(p[1]), double(p[2])};
    }
    bool is_point_double() const override { return true; }
    OpenMesh::Vec3f normal(OpenMesh::VertexHandle) const override { return {0.0f, 0.0f, 0.0f}; }
    OpenMesh::Vec3d normald(OpenMesh::VertexHandle) const override { return {0.0, 0.0, 0.0}; }
    bool is_normal_double() const override { return true; }
    OpenMesh::Vec3uc color(OpenMesh::VertexHandle) const override { return {0, 0, 0}; }
    OpenMesh::Vec4uc colorA(OpenMesh::VertexHandle) const override { return {0, 0, 0, 0}; }
    OpenMesh::Vec3ui colori(OpenMesh::VertexHandle) const override { return {0, 0, 0}; }
    OpenMesh::Vec4ui colorAi(OpenMesh::VertexHandle) const override { return {0, 0, 0, 0}; }
    OpenMesh::Vec3f colorf(OpenMesh::VertexHandle) const override { return {0.0f, 0.0f, 0.0f}; }
    OpenMesh::Vec4f colorAf(OpenMesh::VertexHandle) const override { return {0.0f, 0.0f, 0.0f, 0.0f}; }
    OpenMesh::Vec2f texcoord(OpenMesh::VertexHandle) const override { return {0.0f, 0.0f}; }
    OpenMesh::Vec2f texcoord(OpenMesh::HalfedgeHandle) const override { return {0.0f, 0.0f}; }
    OpenMesh::Attributes::StatusInfo status(OpenMesh::VertexHandle) const override { return {}; }

    unsigned int get_vhandles(OpenMesh::FaceHandle f, std::vector<OpenMesh::VertexHandle>& out) const override
    {
        // Every 65,536 triangles: a tenth of a second of writing.
        if ((f.idx() & 0xffff) == 0 && f.idx() > 0) {
            if (work_.cancelled()) throw Cancelled{};
            work_.report(double(f.idx()) / double(mesh_.triangles.size()));
        }
        const auto& t = mesh_.triangles[std::size_t(f.idx())];
        out.assign(
            {OpenMesh::VertexHandle(int(t[0])), OpenMesh::VertexHandle(int(t[1])), OpenMesh::VertexHandle(int(t[2]))});
        return 3;
    }
    OpenMesh::HalfedgeHandle getHeh(OpenMesh::FaceHandle, OpenMesh::VertexHandle) const override
    {
        return OpenMesh::HalfedgeHandle();
    }
    unsigned int get_face_texcoords(std::vector<OpenMesh::Vec2f>&) const override { return 0; }
    OpenMesh::Vec3f normal(OpenMesh::FaceHandle f) const override
    {
        const OpenMesh::Vec3d n = normald(f);
        return {float(n[0]), float(n[1]), float(n[2])};
    }
    OpenMesh::Vec3d normald(OpenMesh::FaceHandle f) const override
    {
        const auto& t = mesh_.triangles[std::size_t(f.idx())];
        const glm::dvec3 a = mesh_.vertices[t[0]];
        const glm::dvec3 n = glm::cross(mesh_.vertices[t[1]] - a, mesh_.vertices[t[2]] - a);
        const double len = glm::length(n);
        if (!(len > 0.0)) return {0.0, 0.0, 0.0};
        return {n.x / len, n.y / len, n.z / len};
    }
    OpenMesh::Vec3uc color(OpenMesh::FaceHandle) const override { return {0, 0, 0}; }
    OpenMesh::Vec4uc colorA(OpenMesh::FaceHandle) const override { return {0, 0, 0, 0}; }
    OpenMesh::Vec3ui colori(OpenMesh::FaceHandle) const override { return {0, 0, 0}; }
    OpenMesh::Vec4ui colorAi(OpenMesh::FaceHandle) const override { return {0, 0, 0, 0}; }
    OpenMesh::Vec3f colorf(OpenMesh::FaceHandle) const override { return {0.0f, 0.0f, 0.0f}; }
    OpenMesh::Vec4f colorAf(OpenMesh::FaceHandle) const override { return {0.0f, 0.0f, 0.0f, 0.0f}; }
    OpenMesh::Attributes::StatusInfo status(OpenMesh::FaceHandle) const override { return {}; }

    OpenMesh::Vec3uc color(OpenMesh::EdgeHandle) const override { return {0, 0, 0}; }
    OpenMesh::Vec4uc colorA(OpenMesh::EdgeHandle) const override { return {0, 0, 0, 0}; }
    OpenMesh::Vec3ui colori(OpenMesh::EdgeHandle) const override { return {0, 0, 0}; }
    OpenMesh::Vec4ui colorAi(OpenMesh::EdgeHandle) const override { return {0, 0, 0, 0}; }
    OpenMesh::Vec3f colorf(OpenMesh::EdgeHandle) const override { return {0.0f, 0.0f, 0.0f}; }
    OpenMesh::Vec4f colorAf(OpenMesh::EdgeHandle) const override { return {0.0f, 0.0f, 0.0f, 0.0f}; }
    OpenMesh::Attributes::StatusInfo status(OpenMesh::EdgeHandle) const override { return {}; }

    int get_halfedge_id(OpenMesh::VertexHandle) override { return -1; }
    int get_halfedge_id(OpenMesh::FaceHandle) override { return -1; }
    int get_next_halfedge_id(OpenMesh::HalfedgeHandle) override { return -1; }
    int get_to_vertex_id(OpenMesh::HalfedgeHandle) override { return -1; }
    int get_face_id(OpenMesh::HalfedgeHandle) override { return -1; }
    OpenMesh::Attributes::StatusInfo status(OpenMesh::HalfedgeHandle) const override { return {}; }

    size_t n_vertices() const override { return mesh_.vertices.size(); }
    size_t n_faces() const override { return mesh_.triangles.size(); }
    size_t n_edges() const override { return 3 * mesh_.triangles.size() / 2; } // closed triangle meshes

    bool is_triangle_mesh() const override { return true; }
    bool has_face_normals() const override { return true; }

private:
    const Mesh& mesh_;
    Progress work_;
};

} // namespace kerf::mesher

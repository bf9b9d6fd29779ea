#include "kerf/viewport/ReferenceMesh.hpp"

#include "kerf/document/FileKind.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <glm/glm.hpp>

#include <cmath>
#include <stdexcept>

#include <sys/stat.h>

namespace kerf {

namespace {
struct Traits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

float toLinear(std::uint8_t c)
{
    const float s = float(c) / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}
} // namespace

TriangleMesh loadTriangleMesh(const std::filesystem::path& file)
{
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) throw std::runtime_error(file.string() + ": no such file");
    // Only a regular file is read: a FIFO named hinge.stl blocked the
    // application in open() for ever, waiting for a writer.
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
        throw std::runtime_error(file.string() + ": is " + describeFileKind(st.st_mode) + ", not a mesh file");
    OMesh m;
    OpenMesh::IO::Options options;
    if (!OpenMesh::IO::read_mesh(m, file.string(), options))
        throw std::runtime_error(file.string() + ": cannot read it as a mesh (STL, OBJ, PLY or OFF)");
    TriangleMesh out;
    for (const auto& f : m.faces()) {
        glm::dvec3 p[3];
        int k = 0;
        for (const auto& v : f.vertices()) {
            if (k == 3) break;
            const auto& q = m.point(v);
            p[k++] = {q[0], q[1], q[2]};
        }
        if (k != 3) continue;
        bool finite = true;
        for (const auto& v : p) finite = finite && std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
        if (!finite) throw std::runtime_error(file.string() + ": has a non-finite coordinate");
        const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
        const double len = glm::length(n);
        if (!(len > 0.0)) continue; // a degenerate triangle draws nothing
        for (const auto& v : p) {
            out.positions.push_back(v);
            out.normals.push_back(glm::vec3(n / len));
            out.bounds = out.bounds.merged(Aabb{v, v});
        }
    }
    if (out.positions.empty()) throw std::runtime_error(file.string() + ": has no triangles");
    return out;
}

std::vector<PlacedMesh> loadReferenceMeshes(const Document& doc, const std::filesystem::path& documentFolder,
                                            std::vector<std::string>& problems)
{
    std::vector<PlacedMesh> out;
    for (const auto& ref : doc.meshes) {
        try {
            PlacedMesh pm;
            pm.id = ref.id;
            pm.mesh = loadTriangleMesh(documentFolder / ref.path);
            pm.worldFromLocal = Affine::fromTransform(ref.transform);
            if (ref.color) pm.color = {toLinear(ref.color->r), toLinear(ref.color->g), toLinear(ref.color->b)};
            out.push_back(std::move(pm));
        } catch (const std::exception& e) {
            problems.push_back("mesh '" + ref.id + "': " + e.what());
        }
    }
    return out;
}

} // namespace kerf

#include "kerf/mesher/ThreeMfWriter.hpp"

#include "kerf/document/AtomicFile.hpp"

#include <Model/COM/NMR_DLLInterfaces.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace kerf {

namespace {

// Releases a lib3mf instance when it goes out of scope.
class Released {
public:
    explicit Released(NMR::PLib3MFBase* p = nullptr) : p_(p) {}
    ~Released()
    {
        if (p_) NMR::lib3mf_release(p_);
    }
    Released(const Released&) = delete;
    Released& operator=(const Released&) = delete;

private:
    NMR::PLib3MFBase* p_;
};

void check(LIB3MFRESULT result, const std::filesystem::path& file, const char* what)
{
    if (result != LIB3MF_OK) throw std::runtime_error(file.string() + ": lib3mf could not " + what);
}

} // namespace

void writeThreeMf(const Mesh& mesh, const std::filesystem::path& file, const std::string& partName,
                  const glm::dvec3& offset)
{
    // 3MF counts in 32 bits (lib3mf's DWORD).
    if (mesh.vertices.size() > std::numeric_limits<std::uint32_t>::max() ||
        mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
        throw std::runtime_error(file.string() + ": too many triangles for a 3MF file");
    std::vector<NMR::MODELMESHVERTEX> vertices(mesh.vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i)
        for (int a = 0; a < 3; ++a)
            vertices[i].m_fPosition[a] = float(mesh.vertices[i][a] - offset[a]);
    std::vector<NMR::MODELMESHTRIANGLE> triangles(mesh.triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i)
        for (int k = 0; k < 3; ++k)
            triangles[i].m_nIndices[k] = mesh.triangles[i][std::size_t(k)];

    NMR::PLib3MFModel* model = nullptr;
    check(NMR::lib3mf_createmodel(&model), file, "create a model");
    const Released releaseModel(model);
    check(NMR::lib3mf_model_setunit(model, NMR::MODELUNIT_MILLIMETER), file, "set the unit");
    NMR::PLib3MFModelMeshObject* object = nullptr;
    check(NMR::lib3mf_model_addmeshobject(model, &object), file, "add a mesh object");
    const Released releaseObject(object);
    check(NMR::lib3mf_object_setnameutf8(object, partName.c_str()), file, "name the part");
    check(NMR::lib3mf_meshobject_setgeometry(object, vertices.data(), DWORD(vertices.size()), triangles.data(),
                                             DWORD(triangles.size())),
          file, "take the mesh");
    NMR::MODELTRANSFORM transform{};
    for (int r = 0; r < 3; ++r)
        transform.m_fFields[r][r] = 1.0f;
    for (int a = 0; a < 3; ++a)
        transform.m_fFields[a][3] = float(offset[a]);
    NMR::PLib3MFModelBuildItem* item = nullptr;
    check(NMR::lib3mf_model_addbuilditem(model, object, &transform, &item), file, "add the build item");
    const Released releaseItem(item);
    check(NMR::lib3mf_model_addmetadatautf8(model, "Application", "Kerf"), file, "add metadata");

    NMR::PLib3MFModelWriter* writer = nullptr;
    check(NMR::lib3mf_model_querywriter(model, "3mf", &writer), file, "make a writer");
    const Released releaseWriter(writer);
    ULONG64 size = 0;
    check(NMR::lib3mf_writer_getstreamsize(writer, &size), file, "size the file");
    std::string bytes(std::size_t(size), '\0');
    check(NMR::lib3mf_writer_writetobuffer(writer, reinterpret_cast<BYTE*>(bytes.data()), size), file,
          "write the file");
    writeFileAtomically(file, bytes);
}

} // namespace kerf

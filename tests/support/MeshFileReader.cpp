#include "MeshFileReader.hpp"

#include <Model/COM/NMR_DLLInterfaces.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace kerf::test {

namespace {

// Welds corners by their float32 coordinates, as slicers do.
class Welder {
public:
    std::uint32_t add(float x, float y, float z)
    {
        const auto key = std::make_tuple(x, y, z);
        const auto [it, inserted] = index_.try_emplace(key, std::uint32_t(mesh.vertices.size()));
        if (inserted) mesh.vertices.emplace_back(double(x), double(y), double(z));
        return it->second;
    }
    Mesh mesh;

private:
    std::map<std::tuple<float, float, float>, std::uint32_t> index_;
};

Mesh readBinaryStl(const std::string& bytes, const std::filesystem::path& file)
{
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() != 84 + 50 * std::uint64_t(count)) throw std::runtime_error(file.string() + ": bad binary STL size");
    Welder w;
    for (std::uint32_t t = 0; t < count; ++t) {
        const char* at = bytes.data() + 84 + 50 * std::size_t(t) + 12; // past the normal
        std::array<std::uint32_t, 3> tri{};
        for (int k = 0; k < 3; ++k) {
            float v[3];
            std::memcpy(v, at + 12 * k, 12);
            tri[std::size_t(k)] = w.add(v[0], v[1], v[2]);
        }
        w.mesh.triangles.push_back(tri);
    }
    return std::move(w.mesh);
}

Mesh readAsciiStl(const std::string& text, const std::filesystem::path& file)
{
    std::istringstream in(text);
    Welder w;
    std::string word;
    std::array<std::uint32_t, 3> tri{};
    int corner = 0;
    while (in >> word) {
        if (word != "vertex") continue;
        std::string xs, ys, zs;
        in >> xs >> ys >> zs;
        if (!in) throw std::runtime_error(file.string() + ": truncated vertex");
        tri[std::size_t(corner++)] =
            w.add(std::strtof(xs.c_str(), nullptr), std::strtof(ys.c_str(), nullptr), std::strtof(zs.c_str(), nullptr));
        if (corner == 3) {
            w.mesh.triangles.push_back(tri);
            corner = 0;
        }
    }
    if (corner != 0) throw std::runtime_error(file.string() + ": a facet without three vertices");
    return std::move(w.mesh);
}

} // namespace

Mesh readStl(const std::filesystem::path& file)
{
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error(file.string() + ": cannot open");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < 84) throw std::runtime_error(file.string() + ": too short for STL");
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    const bool binary = bytes.size() == 84 + 50 * std::uint64_t(count);
    return binary ? readBinaryStl(bytes, file) : readAsciiStl(bytes, file);
}

namespace {

struct Released {
    NMR::PLib3MFBase* p;
    ~Released()
    {
        if (p) NMR::lib3mf_release(p);
    }
};

std::runtime_error threeMfFailure(const std::filesystem::path& file, const char* what)
{
    return std::runtime_error(file.string() + ": lib3mf: " + what);
}

// Reads the file into a model and calls `withItem(item, object)` for each
// build item, in order.
template <typename WithModel, typename WithItem>
void readThreeMfItems(const std::filesystem::path& file, WithModel withModel, WithItem withItem)
{
    auto fail = [&](const char* what) { return threeMfFailure(file, what); };
    NMR::PLib3MFModel* model = nullptr;
    if (NMR::lib3mf_createmodel(&model) != LIB3MF_OK) throw fail("createmodel");
    const Released releaseModel{model};
    NMR::PLib3MFModelReader* reader = nullptr;
    if (NMR::lib3mf_model_queryreader(model, "3mf", &reader) != LIB3MF_OK) throw fail("queryreader");
    const Released releaseReader{reader};
    if (NMR::lib3mf_reader_readfromfileutf8(reader, file.string().c_str()) != LIB3MF_OK) throw fail("read");
    withModel(model);
    NMR::PLib3MFModelBuildItemIterator* items = nullptr;
    if (NMR::lib3mf_model_getbuilditems(model, &items) != LIB3MF_OK) throw fail("getbuilditems");
    const Released releaseItems{items};
    BOOL more = false;
    while (NMR::lib3mf_builditemiterator_movenext(items, &more) == LIB3MF_OK && more) {
        NMR::PLib3MFModelBuildItem* item = nullptr;
        if (NMR::lib3mf_builditemiterator_getcurrent(items, &item) != LIB3MF_OK) throw fail("getcurrent");
        const Released releaseItem{item};
        NMR::PLib3MFModelObjectResource* object = nullptr;
        if (NMR::lib3mf_builditem_getobjectresource(item, &object) != LIB3MF_OK) throw fail("getobjectresource");
        const Released releaseObject{object};
        withItem(item, object);
    }
}

} // namespace

Mesh readThreeMf(const std::filesystem::path& file)
{
    auto fail = [&](const char* what) { return threeMfFailure(file, what); };
    Mesh out;
    readThreeMfItems(file, [](NMR::PLib3MFModel*) {}, [&](NMR::PLib3MFModelBuildItem* item, NMR::PLib3MFModelObjectResource* object) {
        NMR::MODELTRANSFORM transform{};
        for (int r = 0; r < 3; ++r)
            transform.m_fFields[r][r] = 1.0f;
        BOOL transformed = false;
        if (NMR::lib3mf_builditem_hasobjecttransform(item, &transformed) != LIB3MF_OK) throw fail("hasobjecttransform");
        if (transformed && NMR::lib3mf_builditem_getobjecttransform(item, &transform) != LIB3MF_OK)
            throw fail("getobjecttransform");
        DWORD vertexCount = 0, triangleCount = 0;
        if (NMR::lib3mf_meshobject_getvertexcount(object, &vertexCount) != LIB3MF_OK ||
            NMR::lib3mf_meshobject_gettrianglecount(object, &triangleCount) != LIB3MF_OK)
            throw fail("counts");
        std::vector<NMR::MODELMESHVERTEX> vertices(vertexCount);
        std::vector<NMR::MODELMESHTRIANGLE> triangles(triangleCount);
        if (NMR::lib3mf_meshobject_getvertices(object, vertices.data(), vertexCount, nullptr) != LIB3MF_OK ||
            NMR::lib3mf_meshobject_gettriangleindices(object, triangles.data(), triangleCount, nullptr) != LIB3MF_OK)
            throw fail("geometry");
        const auto first = std::uint32_t(out.vertices.size());
        for (const auto& v : vertices) {
            glm::dvec3 p(0.0);
            for (int r = 0; r < 3; ++r)
                p[r] = double(transform.m_fFields[r][0]) * v.m_fPosition[0] +
                       double(transform.m_fFields[r][1]) * v.m_fPosition[1] +
                       double(transform.m_fFields[r][2]) * v.m_fPosition[2] + double(transform.m_fFields[r][3]);
            out.vertices.push_back(p);
        }
        for (const auto& t : triangles)
            out.triangles.push_back({first + t.m_nIndices[0], first + t.m_nIndices[1], first + t.m_nIndices[2]});
    });
    return out;
}

std::vector<std::string> readThreeMfUuids(const std::filesystem::path& file)
{
    auto fail = [&](const char* what) { return threeMfFailure(file, what); };
    std::vector<std::string> uuids;
    // lib3mf's form: 36 characters and the terminator.
    auto take = [&](BOOL has, const char* text) { uuids.push_back(has ? std::string(text) : std::string()); };
    readThreeMfItems(
        file,
        [&](NMR::PLib3MFModel* model) {
            BOOL has = false;
            char text[64] = {};
            if (NMR::lib3mf_model_getbuilduuidutf8(model, &has, text) != LIB3MF_OK) throw fail("getbuilduuid");
            take(has, text);
        },
        [&](NMR::PLib3MFModelBuildItem* item, NMR::PLib3MFModelObjectResource* object) {
            BOOL has = false;
            char text[64] = {};
            if (NMR::lib3mf_builditem_getuuidutf8(item, &has, text) != LIB3MF_OK) throw fail("builditem uuid");
            take(has, text);
            if (NMR::lib3mf_object_getuuidutf8(object, &has, text) != LIB3MF_OK) throw fail("object uuid");
            take(has, text);
        });
    return uuids;
}

Mesh readMeshFile(const std::filesystem::path& file)
{
    return file.extension() == ".3mf" ? readThreeMf(file) : readStl(file);
}

} // namespace kerf::test

#include "kerf/mesher/ThreeMfWriter.hpp"

#include "kerf/document/AtomicFile.hpp"

#include <Model/COM/NMR_DLLInterfaces.h>

// Header-only (Debian's libxxhash-dev): nothing to link, nothing for the
// package to depend on.
#define XXH_INLINE_ALL
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <limits>
#include <new>
#include <ostream>
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

// What the file holds, hashed: the coordinates and triangles as written, the
// part's name and where the build item puts it.
XXH128_hash_t hashContent(const std::vector<NMR::MODELMESHVERTEX>& vertices,
                          const std::vector<NMR::MODELMESHTRIANGLE>& triangles, const std::string& partName,
                          const NMR::MODELTRANSFORM& transform)
{
    XXH3_state_t* state = XXH3_createState();
    if (!state) throw std::bad_alloc();
    XXH3_128bits_reset(state);
    XXH3_128bits_update(state, vertices.data(), vertices.size() * sizeof(NMR::MODELMESHVERTEX));
    XXH3_128bits_update(state, triangles.data(), triangles.size() * sizeof(NMR::MODELMESHTRIANGLE));
    XXH3_128bits_update(state, partName.data(), partName.size());
    XXH3_128bits_update(state, &transform, sizeof transform);
    const XXH128_hash_t hash = XXH3_128bits_digest(state);
    XXH3_freeState(state);
    return hash;
}

// A UUID drawn from the content instead of at random (lib3mf's default), so
// that the same part exported twice is the same file byte for byte, and a
// different part a different UUID. RFC 9562's version 8 (its bits are the
// application's), in lowercase hex as the production extension's schema
// (ST_UUID) asks; `role` tells the object, the build item and the build
// apart.
std::string contentUuid(const XXH128_hash_t& content, const char* role)
{
    const XXH128_hash_t h = XXH3_128bits_withSeed(&content, sizeof content, XXH64(role, std::strlen(role), 0));
    std::array<unsigned char, 16> bytes{};
    for (int i = 0; i < 8; ++i) {
        bytes[std::size_t(i)] = static_cast<unsigned char>(h.high64 >> (56 - 8 * i));
        bytes[std::size_t(8 + i)] = static_cast<unsigned char>(h.low64 >> (56 - 8 * i));
    }
    bytes[6] = static_cast<unsigned char>((bytes[6] & 0x0f) | 0x80); // version 8
    bytes[8] = static_cast<unsigned char>((bytes[8] & 0x3f) | 0x80); // RFC variant
    std::string text;
    char digits[3];
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        if (i == 4 || i == 6 || i == 8 || i == 10) text += '-';
        std::snprintf(digits, sizeof digits, "%02x", bytes[i]);
        text += digits;
    }
    return text;
}

// lib3mf's stream callbacks (NMR_ExportStream_Callback.h): 0 for done.
std::uint32_t writeChunk(unsigned char* data, std::uint32_t bytes, void* out)
{
    auto& stream = *static_cast<std::ostream*>(out);
    stream.write(reinterpret_cast<const char*>(data), std::streamsize(bytes));
    return stream ? 0 : 1;
}

std::uint32_t seekTo(std::uint64_t position, void* out)
{
    auto& stream = *static_cast<std::ostream*>(out);
    stream.seekp(std::streamoff(position));
    return stream ? 0 : 1;
}

// How far lib3mf is through the file. It reports percentages only between
// its steps (1%, then 52% once every vertex and triangle is written), but
// asks whether to go on every 100,000 vertices and every 100,000 triangles
// as it writes them (lib3mf 1.8, measured), each costing about the same
// (0.4 and 0.5 us on the side chair's 1.2 M vertices and 2.4 M triangles),
// and they are nearly all the writing's time.
struct WriterProgress {
    const Progress& work;
    double items = 1.0; // vertices and triangles
    std::size_t asked = 0;

    static constexpr double kItemsPerQuestion = 100000.0;

    static bool onProgress(int percent, NMR::ProgressIdentifier step, void* self)
    {
        auto& p = *static_cast<WriterProgress*>(self);
        if (percent < 0 && (step == NMR::PROGRESS_WRITENODES || step == NMR::PROGRESS_WRITETRIANGLES))
            p.work.report(std::min(1.0, double(++p.asked) * kItemsPerQuestion / p.items));
        return !p.work.cancelled();
    }
};

struct Cancelled {};

} // namespace

bool writeThreeMf(const Mesh& mesh, const std::filesystem::path& file, const std::string& partName,
                  const glm::dvec3& offset, const Progress& work)
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
    const XXH128_hash_t content = hashContent(vertices, triangles, partName, transform);
    check(NMR::lib3mf_object_setuuidutf8(object, contentUuid(content, "object").c_str()), file, "set the object's UUID");
    check(NMR::lib3mf_builditem_setuuidutf8(item, contentUuid(content, "build item").c_str()), file,
          "set the build item's UUID");
    check(NMR::lib3mf_model_setbuilduuidutf8(model, contentUuid(content, "build").c_str()), file,
          "set the build's UUID");
    check(NMR::lib3mf_model_addmetadatautf8(model, "Application", "Kerf"), file, "add metadata");

    NMR::PLib3MFModelWriter* writer = nullptr;
    check(NMR::lib3mf_model_querywriter(model, "3mf", &writer), file, "make a writer");
    const Released releaseWriter(writer);
    WriterProgress progress{work, double(vertices.size() + triangles.size())};
    check(NMR::lib3mf_writer_setprogresscallback(writer, &WriterProgress::onProgress, &progress), file,
          "report progress");
    // Streamed into the file in one pass (the ZIP's headers patched by
    // seeking): sizing a buffer first (lib3mf_writer_getstreamsize) printed
    // and compressed the whole model twice.
    try {
        writeFileAtomically(file, [&](std::ostream& out) {
            const LIB3MFRESULT result = NMR::lib3mf_writer_writetocallback(
                writer, reinterpret_cast<void*>(&writeChunk), reinterpret_cast<void*>(&seekTo), &out);
            if (work.cancelled()) throw Cancelled{};
            check(result, file, "write the file");
        });
    } catch (const Cancelled&) {
        return false; // nothing written: the temporary file is gone
    }
    return true;
}

} // namespace kerf

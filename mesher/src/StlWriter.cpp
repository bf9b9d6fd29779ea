#include "kerf/mesher/StlWriter.hpp"

#include "MeshExporter.hpp"

#include "kerf/document/AtomicFile.hpp"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <limits>
#include <mutex>
#include <stdexcept>

namespace kerf {

bool writeStl(const Mesh& mesh, const std::filesystem::path& file, StlFormat format, const Progress& work)
{
    // OpenMesh's writers log "[STLWriter] : write binary file" to std::clog;
    // kerf's stderr carries one-line errors and progress only.
    static std::once_flag quiet;
    std::call_once(quiet, [] { omlog().disable(); });
    // The binary format counts triangles in 32 bits (OpenMesh in an int).
    if (mesh.triangles.size() > std::size_t(std::numeric_limits<int>::max()))
        throw std::runtime_error(file.string() + ": too many triangles for an STL file");
    OpenMesh::IO::Options options;
    if (format == StlFormat::Binary) options += OpenMesh::IO::Options::Binary;
    try {
        writeFileAtomically(file, [&](std::ostream& out) {
            mesher::MeshExporter exporter(mesh, work);
            // 9 significant digits print every float32 so that it reads back exactly.
            if (!OpenMesh::IO::IOManager().write(out, ".stl", exporter, options, 9))
                throw std::runtime_error(file.string() + ": OpenMesh could not write the STL");
        });
    } catch (const mesher::MeshExporter::Cancelled&) {
        return false; // nothing written: the temporary file is gone
    }
    return true;
}

} // namespace kerf

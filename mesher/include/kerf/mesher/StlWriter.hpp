#pragma once
// Writes a mesh as STL through OpenMesh's STL writer, straight from the
// Mesh layout (an OpenMesh exporter over it; no halfedge copy), whole or not
// at all: the bytes go to a temporary file beside the target, which replaces
// the target by rename(2) (kerf::writeFileAtomically).
//
// Binary STL by default: an 80-byte header, a 32-bit triangle count, then
// 50 bytes per triangle (normal and three vertices as float32, 2 attribute
// bytes). Normals are computed in double from the mesh (OpenMesh would
// compute them in float from rounded vertices). STL stores float32: a part
// far from the origin loses precision in the file (about 8 micrometres at
// 100 m), not in the mesh.

#include "kerf/document/Progress.hpp"
#include "kerf/mesher/Mesh.hpp"

#include <cstdint>
#include <filesystem>

namespace kerf {

enum class StlFormat { Binary, Ascii };

/// Writes `mesh` to `file`, reporting to `work` as it goes. Returns false,
/// with nothing written, when `work` is cancelled. Throws std::runtime_error
/// naming the file on any failure (the target is then untouched and no
/// temporary file remains).
bool writeStl(const Mesh& mesh, const std::filesystem::path& file, StlFormat format = StlFormat::Binary,
              const Progress& work = {});

/// Size in bytes of the binary STL of `mesh`.
inline std::uint64_t binaryStlBytes(const Mesh& mesh) { return 84 + 50 * std::uint64_t(mesh.triangles.size()); }

} // namespace kerf

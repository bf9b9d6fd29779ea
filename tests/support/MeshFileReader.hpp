#pragma once
// The test suite's own reader of exported files, as a slicer reads them:
// nothing from the mesher, only the bytes of the file.
//
// STL (binary or ASCII): every triangle's corners as float32 values (ASCII
// parsed with strtof), vertices welded when their float32 coordinates are
// identical, bit for bit. 3MF: through lib3mf's reader, the vertices and
// triangles by index, placed by the build item's transform.

#include "kerf/mesher/Mesh.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace kerf::test {

/// Throws std::runtime_error when the file cannot be read or is malformed.
Mesh readStl(const std::filesystem::path& file);
Mesh readThreeMf(const std::filesystem::path& file);

/// A 3MF file's UUIDs (the production extension's p:UUID) as lib3mf reads
/// them: the build's, then each build item's and its object's, in order.
/// Empty where the file has none.
std::vector<std::string> readThreeMfUuids(const std::filesystem::path& file);

/// By extension (.stl, .3mf).
Mesh readMeshFile(const std::filesystem::path& file);

} // namespace kerf::test

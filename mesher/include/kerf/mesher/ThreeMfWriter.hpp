#pragma once
// Writes a mesh as 3MF through lib3mf (Debian's lib3mf-dev, 1.8): one mesh
// object with the part's name, indexed triangles (no welding by position:
// a reader gets exactly the vertices and triangles written), millimetres,
// one build item. The object's, the build item's and the build's UUIDs
// (the production extension's p:UUID) are hashed from what the file holds,
// not drawn at random, so the same part gives the same file byte for byte.
// lib3mf prints coordinates as float32 with six decimals
// (WrittenFormat::Float32SixDecimals).
//
// `offset` is subtracted from every vertex and becomes the build item's
// translation: a part far from the origin keeps its detail in the file (a
// slicer places the item where it wants in any case). The offset must be a
// float32 value so that the translation is stored exactly.

#include "kerf/document/Progress.hpp"
#include "kerf/mesher/Mesh.hpp"

#include <glm/vec3.hpp>

#include <filesystem>
#include <string>

namespace kerf {

/// Writes whole or not at all (kerf::writeFileAtomically), reporting to
/// `work` as lib3mf goes. Returns false, with nothing written, when `work`
/// is cancelled. Throws std::runtime_error naming the file on any failure.
bool writeThreeMf(const Mesh& mesh, const std::filesystem::path& file, const std::string& partName,
                  const glm::dvec3& offset = glm::dvec3(0.0), const Progress& work = {});

} // namespace kerf

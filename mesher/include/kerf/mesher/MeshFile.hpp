#pragma once
// A mesh written as a file for slicers and CAM programs, and what they will
// read back from it. Both kerf export and the export dialog go through
// here, so that they write the same file and report the same figures.
//
// The format follows the file's extension: .stl (binary, or ASCII when
// asked) or .3mf. Before writing, the mesh is fitted to the file's
// coordinates (WrittenCoordinates.hpp): rounding to float32 or to 3MF's
// decimals may join vertices or flatten triangles, and a reader would see
// an open or pinched mesh. The report then describes the mesh as a reader
// gets it (STL welded by written position, 3MF by index), not the mesh in
// memory.

#include "kerf/document/Aabb.hpp"
#include "kerf/mesher/Mesh.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/mesher/WrittenCoordinates.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace kerf {

enum class MeshFileFormat { BinaryStl, AsciiStl, ThreeMf };

/// The format the file's extension asks for (case-insensitive): .stl gives
/// binary STL, or ASCII with `ascii`; .3mf gives 3MF. Nothing for any other.
std::optional<MeshFileFormat> meshFileFormatFor(const std::filesystem::path& file, bool ascii = false);

/// "binary STL", "ASCII STL", "3MF".
const char* describe(MeshFileFormat format);

WrittenFormat writtenFormatOf(MeshFileFormat format);

/// Where the file's coordinates start: zero for STL (it has no transform),
/// for 3MF a float32-exact point near the part once the part is so far from
/// the origin that float32 would lose more than `tolerance` / 10 there.
glm::dvec3 fileOffsetFor(const Mesh& mesh, MeshFileFormat format, double tolerance);
/// The same for a part within `box` (exportPart: from the part's bounds,
/// before it is meshed).
glm::dvec3 fileOffsetFor(const Aabb& box, MeshFileFormat format, double tolerance);

/// The finest tolerance a file of `format` can hold for a part within
/// `partBounds` (mm): twice the step of its written coordinates where the
/// part reaches (a vertex rounds by up to half a step on each axis). STL
/// steps by float32's spacing at the part's largest coordinate; 3MF, moved
/// next to the part, by float32's at its half extent or its sixth decimal.
double finestTolerance(const Aabb& partBounds, MeshFileFormat format);

/// Why `tolerance` cannot be asked of a file of `format` for this part, or
/// nothing when it can (0, no tolerance, always can). A tolerance finer than
/// the file holds would only make every triangle "over" it, after minutes.
std::optional<std::string> toleranceTheFileCannotHold(const Aabb& partBounds, MeshFileFormat format,
                                                      double tolerance);

/// Why a file of `format` cannot hold the part at all, or nothing when it
/// can: its coordinates step by more than a tenth of the part's smallest
/// extent where the part is (a 2 mm sphere 170 km from the origin in an STL
/// steps by 8 mm: every vertex rounds onto a few points and the triangles
/// cross). Says which format holds it.
std::optional<std::string> partTheFileCannotHold(const Aabb& partBounds, MeshFileFormat format);

/// A warning where the written coordinates, stepping by `spacing` from
/// `offset` (MeshFileReport::spacing, offset), leave less than ten steps to the tolerance
/// (none given: 0.01 mm), or nothing. It says where the step comes from and
/// only what would make it finer: a .3mf file (stored round its own
/// middle) or moving the part where the step is float32's at the part's
/// distance from the origin; a coarser tolerance where it is float32's at
/// the part's own size, which no placement changes (a 60 mm plate at
/// 0.00001 mm was told to move nearer the origin, on the origin).
std::string describeCoarseCoordinates(const Aabb& partBounds, MeshFileFormat format, double spacing,
                                      const glm::dvec3& offset, double tolerance);

/// The tolerance to mesh to when none was asked for: the default, or the
/// finest the file holds where that is coarser.
double defaultToleranceFor(const Aabb& partBounds, MeshFileFormat format);

struct MeshFileReport {
    WrittenFit fit;            // what fitting to the written coordinates changed
    MeshReport asRead;         // the mesh as a reader gets it
    std::size_t selfIntersections = 0; // triangle pairs that cross, as read
    double spacing = 0.0;      // mm: the coordinates' step at the part in the file
    glm::dvec3 offset{0.0};    // 3MF: the build item's translation
    std::uint64_t bytes = 0;
    bool cancelled = false;    // stopped on request before writing: nothing written

    /// A closed, oriented 2-manifold without degenerate or crossing triangles.
    bool solid() const { return asRead.watertight() && selfIntersections == 0; }
};

/// Fits `mesh` to the format's coordinates (it may change), checks it as a
/// reader will see it and writes it whole or not at all. `partName` names
/// the 3MF object. Throws std::runtime_error (or OutputFileError) naming the
/// file on failure; with `writeOnlyIfSolid` a mesh that a reader would not
/// see as a solid is not written, and the report says why. `work` hears
/// the steps (fitting, checking, the crossing search, writing); cancelled
/// (asked between them and during the crossing search) it stops before
/// anything is written. `offset`: where the file's coordinates start
/// (fileOffsetFor), where the mesh was made for it (MeshOptions::fileOffset);
/// else fileOffsetFor(mesh, ...).
MeshFileReport writeMeshFile(Mesh& mesh, const std::filesystem::path& file, MeshFileFormat format,
                             const std::string& partName, double tolerance, bool writeOnlyIfSolid = true,
                             const Progress& work = {}, const std::optional<glm::dvec3>& offset = std::nullopt);

/// The defects of a report in words ("12 open edges, 3 crossing triangle
/// pairs"), empty when it is a solid.
std::string describeDefects(const MeshFileReport& report);

struct ExportedPart {
    bool cancelled = false;
    bool empty = false;           // nothing to write (nothing written)
    MeshStats stats;              // of the mesh written
    MeshFileReport report;        // of the file written (or refused)
    std::string simplificationDefects; // non-empty: the simplified mesh had these, the plain one was written
};

/// Meshes the part to options.tolerance and writes it. Where the simplified
/// and refined mesh would not read back as a solid (a safety net: its
/// changes keep clear of rounding, TriangleClearance.hpp, and no bundled
/// example needs it), the plain marching-cubes mesh at the feature size is
/// written instead and simplificationDefects says why. The
/// file is written only when report.solid().
ExportedPart exportPart(const Document& doc, const MeshOptions& options, const std::filesystem::path& file,
                        MeshFileFormat format, const std::string& partName, const Progress& work = {});

/// Why an export that would not read back as a solid was not written, as
/// the user is told it: the defects, and where the file's coordinates step
/// too coarsely for the cells (a part far from the origin in STL's float32)
/// that cause and what holds the part; else "internal error: ...".
std::string describeNotWritten(const ExportedPart& exported, MeshFileFormat format);

} // namespace kerf

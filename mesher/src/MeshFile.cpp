#include "kerf/mesher/MeshFile.hpp"

#include "kerf/document/Limits.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include "kerf/mesher/FilePrecision.hpp"
#include "kerf/mesher/SelfIntersections.hpp"
#include "kerf/mesher/StlWriter.hpp"
#include "kerf/mesher/ThreeMfWriter.hpp"
#include "kerf/voxelizer/WorkerArena.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace kerf {

std::optional<MeshFileFormat> meshFileFormatFor(const std::filesystem::path& file, bool ascii)
{
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".stl") return ascii ? MeshFileFormat::AsciiStl : MeshFileFormat::BinaryStl;
    if (ext == ".3mf") return MeshFileFormat::ThreeMf;
    return std::nullopt;
}

const char* describe(MeshFileFormat format)
{
    switch (format) {
    case MeshFileFormat::BinaryStl: return "binary STL";
    case MeshFileFormat::AsciiStl: return "ASCII STL";
    case MeshFileFormat::ThreeMf: return "3MF";
    }
    return "?";
}

WrittenFormat writtenFormatOf(MeshFileFormat format)
{
    return format == MeshFileFormat::ThreeMf ? WrittenFormat::Float32SixDecimals : WrittenFormat::Float32;
}

namespace {

double largestCoordinate(const Mesh& mesh, const glm::dvec3& offset)
{
    double m = 0.0;
    for (const glm::dvec3& v : mesh.vertices)
        for (int a = 0; a < 3; ++a)
            m = std::max(m, std::abs(v[a] - offset[a]));
    return m;
}

// The step between written coordinates at magnitude x: float32's, and for
// 3MF at least the sixth decimal.
double spacingAt(double x, MeshFileFormat format)
{
    const double f = float32Spacing(x);
    return format == MeshFileFormat::ThreeMf ? std::max(f, 1e-6) : f;
}

} // namespace

glm::dvec3 fileOffsetFor(const Aabb& box, MeshFileFormat format, double tolerance)
{
    if (format != MeshFileFormat::ThreeMf || box.isEmpty() || !box.isBounded()) return glm::dvec3(0.0);
    double largest = 0.0;
    for (int a = 0; a < 3; ++a)
        largest = std::max({largest, std::abs(box.min[a]), std::abs(box.max[a])});
    if (spacingAt(largest, format) <= 0.1 * std::max(tolerance, 1e-4)) return glm::dvec3(0.0);
    // A whole number of millimetres: exact in float32 up to 16 km.
    glm::dvec3 centre = glm::round(box.center());
    for (int a = 0; a < 3; ++a)
        centre[a] = double(float(centre[a]));
    return centre;
}

glm::dvec3 fileOffsetFor(const Mesh& mesh, MeshFileFormat format, double tolerance)
{
    if (mesh.vertices.empty()) return glm::dvec3(0.0);
    Aabb box{mesh.vertices[0], mesh.vertices[0]};
    for (const glm::dvec3& v : mesh.vertices) {
        box.min = glm::min(box.min, v);
        box.max = glm::max(box.max, v);
    }
    return fileOffsetFor(box, format, tolerance);
}

namespace {

// How far the written coordinates reach for a part within `partBounds`: from
// the origin for STL, from the part's middle for 3MF (written next to it).
double writtenReach(const Aabb& partBounds, MeshFileFormat format)
{
    double reach = 0.0;
    for (int a = 0; a < 3; ++a)
        reach = std::max({reach,
                          format == MeshFileFormat::ThreeMf
                              ? 0.5 * (partBounds.max[a] - partBounds.min[a]) + 1.0 // the offset is whole millimetres
                              : std::max(std::abs(partBounds.min[a]), std::abs(partBounds.max[a]))});
    return reach;
}

} // namespace

double finestTolerance(const Aabb& partBounds, MeshFileFormat format)
{
    return 2.0 * spacingAt(writtenReach(partBounds, format), format);
}

std::optional<std::string> partTheFileCannotHold(const Aabb& partBounds, MeshFileFormat format)
{
    if (partBounds.isEmpty() || !partBounds.isBounded()) return std::nullopt;
    const glm::dvec3 size = partBounds.size();
    const double smallest = std::min({size.x, size.y, size.z});
    // A part thinner than any feature size is empty to the mesher, which says so.
    if (smallest < limits::kMinFeatureSize) return std::nullopt;
    const double step = 0.5 * finestTolerance(partBounds, format);
    if (!(step > 0.1 * smallest)) return std::nullopt;
    const bool stl = format != MeshFileFormat::ThreeMf;
    const bool threeMfHolds = stl && !(0.5 * finestTolerance(partBounds, MeshFileFormat::ThreeMf) > 0.1 * smallest);
    char text[640];
    std::snprintf(text, sizeof text,
                  "a %s file cannot hold this part: its coordinates step by %.2g mm where the part is, %.3g mm from "
                  "%s, and the part is %.3g mm across at its thinnest (every vertex would round onto a few points)%s",
                  describe(format), step, writtenReach(partBounds, format), stl ? "the origin" : "its middle",
                  smallest, threeMfHolds ? "; a .3mf file holds it (stored round its own middle)" : "");
    return std::string(text);
}

std::string describeCoarseCoordinates(const Aabb& partBounds, MeshFileFormat format, double spacing,
                                      const glm::dvec3& offset, double tolerance)
{
    const double asked = tolerance > 0.0 ? tolerance : 0.01;
    if (!(spacing > 0.1 * asked) || partBounds.isEmpty() || !partBounds.isBounded()) return {};
    const bool stl = format != MeshFileFormat::ThreeMf;
    // 3MF's step: float32's at the part's half extent, or the sixth decimal.
    const double ownStep = 0.5 * finestTolerance(partBounds, MeshFileFormat::ThreeMf);
    std::string advice;
    if (stl && !(ownStep > 0.1 * asked)) {
        advice = "a .3mf file keeps the detail, or move the part nearer the origin";
    } else {
        char coarser[160];
        std::snprintf(coarser, sizeof coarser,
                      "that is the step at the part's own size, wherever it lies: a tolerance of %.2g mm or coarser "
                      "leaves ten steps",
                      10.0 * std::max(spacing, ownStep));
        advice = coarser;
    }
    double reach = 0.0;
    for (int a = 0; a < 3; ++a)
        reach = std::max({reach, std::abs(partBounds.min[a] - offset[a]), std::abs(partBounds.max[a] - offset[a])});
    char measure[96];
    std::snprintf(measure, sizeof measure,
                  tolerance > 0.0 ? "the tolerance is %.2g mm" : "no tolerance asked: judged against %.2g mm", asked);
    char text[512];
    std::snprintf(text, sizeof text,
                  "the part reaches %.*f mm from %s, where the file's coordinates step by %.2g mm (%s); %s",
                  // The reach in plain digits ("100030", never "1e+05"), to a tenth below 100 mm.
                  reach < 100.0 ? 1 : 0, reach, offset == glm::dvec3(0.0) ? "the origin" : "its middle", spacing,
                  measure, advice.c_str());
    return std::string(text);
}

double defaultToleranceFor(const Aabb& partBounds, MeshFileFormat format)
{
    return partBounds.isEmpty() ? kDefaultExportTolerance
                                : std::max(kDefaultExportTolerance, finestTolerance(partBounds, format));
}

std::optional<std::string> toleranceTheFileCannotHold(const Aabb& partBounds, MeshFileFormat format,
                                                      double tolerance)
{
    if (!(tolerance > 0.0) || partBounds.isEmpty()) return std::nullopt;
    const double finest = finestTolerance(partBounds, format);
    if (tolerance >= finest) return std::nullopt;
    const bool stl = format != MeshFileFormat::ThreeMf;
    char text[640];
    std::snprintf(text, sizeof text,
                  "a tolerance of %.3g mm is finer than a %s file can hold for this part: its coordinates step by "
                  "%.2g mm where the part reaches, %.*f mm from %s; the finest tolerance it holds is %.2g mm (or "
                  "none: the marching-cubes mesh without simplification)%s",
                  // The reach in plain digits ("1600", never "1.6e+03"), to a tenth below 100 mm.
                  tolerance, describe(format), 0.5 * finest, writtenReach(partBounds, format) < 100.0 ? 1 : 0,
                  writtenReach(partBounds, format),
                  stl ? "the origin" : "its middle", finest,
                  stl && tolerance >= finestTolerance(partBounds, MeshFileFormat::ThreeMf)
                      ? "; a .3mf file holds it"
                      : "");
    return std::string(text);
}

MeshFileReport writeMeshFile(Mesh& mesh, const std::filesystem::path& file, MeshFileFormat format,
                             const std::string& partName, double tolerance, bool writeOnlyIfSolid, const Progress& work,
                             const std::optional<glm::dvec3>& offset)
{
    MeshFileReport report;
    auto stop = [&] { return report.cancelled = work.cancelled(); };
    const WrittenFormat written = writtenFormatOf(format);
    report.offset = offset ? *offset : fileOffsetFor(mesh, format, tolerance);
    report.spacing = spacingAt(largestCoordinate(mesh, report.offset), format);
    // The steps' shares of the time, from the side chair's raw 0.5 mm mesh
    // on two threads (docs/benchmarks.md): fit 0.8 s, read-back and check
    // 1.1 s, crossings 6 s, writing 2 to 3 s.
    report.fit = fitToWritten(mesh, written, report.offset);
    work.report(0.07);
    if (stop()) return report;
    // STL readers weld by position; 3MF readers keep the indices.
    const Mesh asRead = readBack(mesh, written, format != MeshFileFormat::ThreeMf, report.offset);
    report.asRead = checkMesh(asRead);
    work.report(0.17);
    if (stop()) return report;
    const SelfIntersections crossings = findSelfIntersections(asRead, 0, work.stage(0.17, 0.75));
    report.selfIntersections = crossings.pairs;
    if (crossings.stopped || stop()) {
        report.cancelled = true;
        return report;
    }
    if (writeOnlyIfSolid && !report.solid()) return report;
    const Progress writing = work.stage(0.75, 1.0);
    const bool finished =
        format == MeshFileFormat::ThreeMf
            ? writeThreeMf(mesh, file, partName, report.offset, writing)
            : writeStl(mesh, file, format == MeshFileFormat::AsciiStl ? StlFormat::Ascii : StlFormat::Binary, writing);
    if (!finished) {
        report.cancelled = true;
        return report;
    }
    std::error_code ec;
    report.bytes = std::filesystem::file_size(file, ec);
    work.report(1.0);
    return report;
}

std::string describeDefects(const MeshFileReport& report)
{
    std::string s;
    auto add = [&](std::size_t n, const std::string& what) {
        if (!n) return;
        if (!s.empty()) s += ", ";
        s += std::to_string(n) + " " + what;
    };
    const MeshReport& r = report.asRead;
    add(r.boundaryEdges, "open edges");
    add(r.nonManifoldEdges, "non-manifold edges");
    add(r.misorientedEdges, "misoriented edges");
    add(r.nonManifoldVertices, "non-manifold vertices");
    add(r.degenerateTriangles, "degenerate triangles");
    add(report.selfIntersections, "crossing triangle pairs");
    if (s.empty() && r.triangles > 0 && !(r.volume > 0.0)) s = "triangles face inward";
    return s;
}

ExportedPart exportPart(const Document& doc, const MeshOptions& options, const std::filesystem::path& file,
                        MeshFileFormat format, const std::string& partName, const Progress& work)
{
    // Meshing is most of the time of an export to a tolerance (the side
    // chair's: 17 s of 18); of a raw one (--tolerance 0), whose millions of
    // triangles the checks of the file read back, about a third (chair
    // at 0.5 mm: 5.5 s of 19; bookshelf side, stool: a quarter to a third).
    const double meshingShare = options.tolerance > 0.0 ? 0.95 : 0.3;
    const Progress meshing = work.stage(0.0, meshingShare), writing = work.stage(meshingShare, 1.0);
    ExportedPart out;
    // The file's offset from the part's bounds, before meshing: the mesher
    // keeps its vertices apart by the spacing of the coordinates written.
    const Tape tape = compileTape(doc);
    MeshOptions fitted = withDocumentFeatureSize(doc, options);
    fitted.fileOffset = fileOffsetFor(tape.bounds(), format, options.tolerance);
    std::optional<Mesh> mesh = meshTape(tape, fitted, meshing, &out.stats);
    if (!mesh) {
        out.cancelled = true;
        return out;
    }
    if (mesh->empty()) {
        out.empty = true;
        return out;
    }
    // The checks of the file as read back run on the export's threads too.
    tbb::task_arena arena = workerArena(options.threads);
    auto write = [&] {
        arena.execute([&] {
            out.report =
                writeMeshFile(*mesh, file, format, partName, options.tolerance, true, writing, fitted.fileOffset);
        });
    };
    write();
    if (out.report.cancelled) {
        out.cancelled = true;
        return out;
    }
    if (out.report.solid() || options.tolerance == 0.0) return out;
    out.simplificationDefects = describeDefects(out.report);
    MeshOptions plain = fitted;
    plain.tolerance = 0.0;
    out.stats = {};
    mesh = meshTape(tape, plain, meshing, &out.stats);
    if (!mesh) {
        out.cancelled = true;
        return out;
    }
    write();
    out.cancelled = out.report.cancelled;
    return out;
}

std::string describeNotWritten(const ExportedPart& exported, MeshFileFormat format)
{
    const MeshFileReport& report = exported.report;
    const std::string defects =
        "a reader of the file would not get a closed solid (" + describeDefects(report) + ")";
    // The cells keep their vertices eight coordinate steps from the lattice's
    // points, and so apart in the file, only in cells of 32 steps or more
    // (cellMeshing, MeshPart.cpp); in finer cells writing may join them.
    const double cell = exported.stats.cellSize;
    if (!(report.spacing > 0.0 && cell > 0.0 && cell < 32.0 * report.spacing)) return "internal error: " + defects;
    char text[400];
    std::snprintf(text, sizeof text,
                  ": the file's coordinates step by %.2g mm where the part reaches, too coarse for cells of %.2g mm; "
                  "%s",
                  report.spacing, cell,
                  format != MeshFileFormat::ThreeMf
                      ? "a .3mf file keeps the detail (stored round the part's own middle), or move the part nearer "
                        "the origin, or a coarser feature size"
                      : "a coarser feature size keeps the cells apart in it");
    return defects + text;
}

} // namespace kerf

#include "SimplifyToTolerance.hpp"

#include "EdgeCollapse.hpp"

#include "kerf/evaluator/PointEvaluator.hpp"


#include <glm/glm.hpp>

#include <algorithm>
#include <limits>
#include <utility>

namespace kerf::mesher {

namespace {

// Quadrics from the Hermite data: each vertex's tangent plane, weighted by
// the area around it (a third of its triangles'); a feature vertex takes
// the planes of its neighbours, which are the vertices of the cell polygon
// it was fitted to.
std::vector<Quadric> tangentQuadrics(const std::vector<glm::dvec3>& positions, const std::vector<Triangle>& triangles,
                                     const std::vector<glm::dvec3>& normals)
{
    std::vector<double> area(positions.size(), 0.0);
    for (const Triangle& t : triangles) {
        const double a =
            0.5 * glm::length(glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]));
        for (const std::uint32_t v : t)
            area[v] += a / 3.0;
    }
    std::vector<Quadric> quadrics(positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v)
        if (normals[v] != glm::dvec3(0.0)) quadrics[v] = Quadric::plane(normals[v], positions[v], area[v]);
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = t[std::size_t(k)];
            if (normals[v] != glm::dvec3(0.0)) continue;
            for (int j = 1; j < 3; ++j) {
                const std::uint32_t u = t[std::size_t(k + j) % 3];
                if (normals[u] != glm::dvec3(0.0))
                    quadrics[v] += Quadric::plane(normals[u], positions[u], 0.5 * area[u]);
            }
        }
    return quadrics;
}

// Feature vertices (no normal) where the surface has no edge: the marching
// cubes fit one wherever a cell's normals differ by more than the feature
// angle, which a tightly curved smooth sheet does too (the wall of a 5 mm
// hole at 1 mm cells). Held as a crease, such a vertex only ever collapses
// along it, and the walls of the shelf-pin panel's holes kept a column of
// them at every lattice plane. A vertex whose surface faces the same way
// (within 10 degrees) a little towards each of its neighbours is on one
// sheet: it gets that sheet's normal. A true edge or corner has neighbours
// on sheets that face apart.
void giveSmoothFeaturesTheirNormals(const std::vector<glm::dvec3>& positions, const std::vector<Triangle>& triangles,
                                    std::vector<glm::dvec3>& normals, SurfaceQueries& field)
{
    constexpr double kSameSheetCosine = 0.984807753012208; // 10 degrees
    // (feature vertex, neighbour) pairs, grouped by vertex: memory for the
    // feature vertices only, not a list per vertex of the mesh.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = t[std::size_t(k)];
            if (normals[v] != glm::dvec3(0.0)) continue;
            pairs.emplace_back(v, t[std::size_t(k + 1) % 3]);
            pairs.emplace_back(v, t[std::size_t(k + 2) % 3]);
        }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (std::size_t first = 0, last = 0; first < pairs.size(); first = last) {
        const std::uint32_t v = pairs[first].first;
        while (last < pairs.size() && pairs[last].first == v)
            ++last;
        double shortest = std::numeric_limits<double>::infinity();
        for (std::size_t i = first; i < last; ++i)
            shortest = std::min(shortest, glm::length(positions[pairs[i].second] - positions[v]));
        if (!(shortest > 0.0)) continue;
        const glm::dvec3 here = field.unitNormal(positions[v]);
        if (here == glm::dvec3(0.0)) continue;
        bool oneSheet = true;
        for (std::size_t i = first; i < last && oneSheet; ++i) {
            const glm::dvec3 n = field.unitNormal(positions[v] + 0.1 * shortest *
                                                                    glm::normalize(positions[pairs[i].second] - positions[v]));
            oneSheet = glm::dot(n, here) >= kSameSheetCosine;
        }
        if (oneSheet) normals[v] = here;
    }
}

// Whether any live triangle has an edge shorter than `length`: the micro
// passes walk the whole mesh (the sequential one about a third of a second
// on the chair at 4 mm), and a mesh without such edges can skip them.
bool hasEdgeShorterThan(const CollapseMesh& mesh, double length)
{
    for (const Triangle& t : mesh.triangles) {
        if (t[0] == kRemoved) continue;
        for (int k = 0; k < 3; ++k)
            if (glm::length(mesh.positions[t[std::size_t(k)]] - mesh.positions[t[std::size_t(k + 1) % 3]]) < length)
                return true;
    }
    return false;
}

} // namespace

std::uint64_t simplifyToTolerance(Mesh& mesh, std::vector<glm::dvec3>& normals, const Tape& tape,
                                  const SimplifySettings& settings, tbb::task_arena& arena,
                                  const Progress& progress, CrossingChecks* checks)
{
    if (mesh.triangles.empty()) return 0;
    // Work relative to the middle of the mesh: quadrics lose precision with
    // the square of the coordinates.
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& p : mesh.vertices) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const glm::dvec3 origin = 0.5 * (lo + hi);
    CollapseMesh work;
    work.positions.resize(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        work.positions[v] = mesh.vertices[v] - origin;
    // The input is replaced at the end (or dropped, if cancelled): its
    // arrays go now, not after the simplification's peak.
    std::vector<glm::dvec3>().swap(mesh.vertices);
    work.triangles = std::move(mesh.triangles);
    mesh.triangles = {};
    SurfaceQueries field(tape, origin, settings.placement, settings.regionSize);
    giveSmoothFeaturesTheirNormals(work.positions, work.triangles, normals, field);
    work.quadrics = tangentQuadrics(work.positions, work.triangles, normals);
    work.normals = std::move(normals);
    normals = {};
    work.held.assign(work.positions.size(), 0);
    work.removed.assign(work.positions.size(), 0);
    CollapseLimits limits;
    limits.maxMeanSquaredError = settings.rmsDistance * settings.rmsDistance;
    limits.minHeight = settings.minHeight;
    limits.placement = settings.placement;
    limits.tolerance = settings.tolerance;
    limits.clearance = settings.clearance;
    limits.checkAfterwards = !settings.guardEveryCollapse;

    // The micro collapses (edges shorter than settings.microLength, on
    // topology alone) come first in every cube of the two partitioned
    // passes, which cut the mesh into cubes once for both; one that
    // straddles the cubes of both (none on the examples) is left to a
    // sequential micro pass before the last.
    CollapseLimits micro;
    micro.maxMeanSquaredError = std::numeric_limits<double>::infinity();
    micro.maxEdgeLength = settings.microLength;
    micro.checkGeometry = false;
    const CollapseLimits* microFirst =
        settings.microLength > 0.0 && hasEdgeShorterThan(work, settings.microLength) ? &micro : nullptr;

    // The passes' shares of the progress, as they share the time on the
    // examples: the first partitioned pass over the whole marching-cubes
    // mesh is most of it.
    const Progress firstPass = progress.stage(0.0, 0.75), secondPass = progress.stage(0.75, 0.9),
                   lastPass = progress.stage(0.9, 1.0);
    std::uint64_t collapses =
        collapsePartitioned(work, limits, settings.cube, lo - origin, arena, field, firstPass, checks, microFirst);
    // Most of the marching-cubes mesh is gone by now (the side chair at
    // 0.5 mm: 9.5 M triangles to about 0.2 M): what follows walks and
    // indexes only what is left.
    work.dropRemoved();
    collapses += collapsePartitioned(work, limits, settings.cube, lo - origin + glm::dvec3(0.5 * settings.cube), arena,
                                     field, secondPass, checks, microFirst);
    if (microFirst && hasEdgeShorterThan(work, settings.microLength))
        collapses += collapseEdges(work, micro, field, lastPass);
    lastPass.report(0.0);
    collapses += limits.checkAfterwards ? collapseEdgesCheckedAfter(work, limits, field, lastPass, checks)
                                        : collapseEdges(work, limits, field, lastPass);
    if (progress.cancelled()) return 0;
    progress.report(1.0);

    // Keep the live triangles and the vertices they use, in their order.
    std::vector<std::uint32_t> index(work.positions.size(), std::numeric_limits<std::uint32_t>::max());
    Mesh out;
    std::vector<glm::dvec3> outNormals;
    for (const Triangle& t : work.triangles) {
        if (t[0] == kRemoved) continue;
        Triangle g;
        for (int k = 0; k < 3; ++k) {
            std::uint32_t& i = index[t[std::size_t(k)]];
            if (i == std::numeric_limits<std::uint32_t>::max()) {
                i = std::uint32_t(out.vertices.size());
                out.vertices.push_back(origin + work.positions[t[std::size_t(k)]]);
                outNormals.push_back(work.normals[t[std::size_t(k)]]);
            }
            g[std::size_t(k)] = i;
        }
        out.triangles.push_back(g);
    }
    mesh = std::move(out);
    normals = std::move(outNormals);
    return collapses;
}

} // namespace kerf::mesher

#include "SurfaceCoverage.hpp"

#include "SampleDistance.hpp"
#include "TriangleClearance.hpp"
#include "TriangleTree.hpp"

#include "kerf/evaluator/PointEvaluator.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_reduce.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace kerf::mesher {

namespace {

using Triangle = std::array<std::uint32_t, 3>;

struct Worst {
    double distance = 0.0;
    std::size_t sample = std::numeric_limits<std::size_t>::max();
    std::uint64_t beyond = 0;
};

// The later of two halves' worst samples only where it is further, so the
// first of the largest wins whatever the split.
Worst join(const Worst& a, const Worst& b)
{
    Worst w = b.distance > a.distance ? b : a;
    w.beyond = a.beyond + b.beyond;
    return w;
}

} // namespace

SurfaceSamples surfaceSamples(const Mesh& lattice, const std::vector<glm::dvec3>& normals, const Tape& tape,
                              double tolerance)
{
    SurfaceSamples samples;
    if (lattice.vertices.empty()) return samples;
    glm::dvec3 lo = lattice.vertices[0], hi = lo;
    for (const glm::dvec3& p : lattice.vertices) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    samples.origin = 0.5 * (lo + hi);
    // The feature vertices' distances, in blocks.
    std::vector<std::size_t> features;
    for (std::size_t v = 0; v < lattice.vertices.size(); ++v)
        if (normals[v] == glm::dvec3(0.0)) features.push_back(v);
    std::vector<std::uint8_t> onSurface(lattice.vertices.size(), 1);
    PointEvaluator<Dual<double>> evaluator;
    constexpr std::size_t kBlock = 256;
    std::vector<double> x, y, z;
    std::vector<Dual<double>> field;
    for (std::size_t first = 0; first < features.size(); first += kBlock) {
        const std::size_t n = std::min(kBlock, features.size() - first);
        x.resize(n);
        y.resize(n);
        z.resize(n);
        field.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            const glm::dvec3& p = lattice.vertices[features[first + k]];
            x[k] = p.x;
            y[k] = p.y;
            z[k] = p.z;
        }
        evaluator.evaluate(tape, x.data(), y.data(), z.data(), n, field.data());
        for (std::size_t k = 0; k < n; ++k)
            onSurface[features[first + k]] = firstOrderDistance(field[k]) <= 0.05 * tolerance;
    }
    samples.points.reserve(lattice.vertices.size());
    samples.onSharpEdge.reserve(lattice.vertices.size());
    for (std::size_t v = 0; v < lattice.vertices.size(); ++v)
        if (onSurface[v]) {
            samples.points.push_back(glm::vec3(lattice.vertices[v] - samples.origin));
            samples.onSharpEdge.push_back(normals[v] == glm::dvec3(0.0));
        }
    return samples;
}

CoverageCheck measureCoverage(const SurfaceSamples& samples, const Mesh& mesh, double tolerance,
                              tbb::task_arena& arena, std::vector<std::pair<double, std::uint32_t>>* beyond,
                              const std::vector<std::uint32_t>* only)
{
    if (beyond) beyond->clear();
    CoverageCheck check;
    const std::size_t count = only ? only->size() : samples.points.size();
    check.samples = count;
    if (count == 0 || mesh.triangles.empty()) return check;
    // The triangles relative to the samples' origin, so the two meet in the
    // same frame without rounding the mesh to float.
    std::vector<glm::dvec3> corners(mesh.vertices.size());
    for (std::size_t v = 0; v < corners.size(); ++v)
        corners[v] = mesh.vertices[v] - samples.origin;
    TriangleTree tree;
    glm::dvec3 meshLo(std::numeric_limits<double>::infinity()), meshHi(-std::numeric_limits<double>::infinity());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const glm::dvec3 a = corners[tri[0]], b = corners[tri[1]], c = corners[tri[2]];
        const glm::dvec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
        tree.insert(std::uint32_t(t), lo, hi);
        meshLo = glm::min(meshLo, lo);
        meshHi = glm::max(meshHi, hi);
    }
    const double span = glm::length(meshHi - meshLo);
    auto distanceTo = [&](const glm::dvec3& p, std::uint32_t t) {
        const Triangle& tri = mesh.triangles[t];
        return pointTriangleDistance(p, corners[tri[0]], corners[tri[1]], corners[tri[2]]);
    };
    // The exact distance of a sample beyond the tolerance: the nearest
    // triangle's box meets a cube of any radius at least its distance, so
    // the least distance found within a cube's radius is the distance.
    auto nearest = [&](const glm::dvec3& p) {
        for (double r = 2.0 * tolerance;; r *= 2.0) {
            double best = std::numeric_limits<double>::infinity();
            tree.query(p - glm::dvec3(r), p + glm::dvec3(r),
                       [&](std::uint32_t t) { best = std::min(best, distanceTo(p, t)); });
            if (best <= r || r > 2.0 * span + tolerance) return best;
        }
    };
    tbb::enumerable_thread_specific<std::vector<std::pair<double, std::uint32_t>>> found;
    const Worst worst = arena.execute([&] {
        return tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, count, 4096), Worst{},
            [&](const tbb::blocked_range<std::size_t>& range, Worst w) {
                // The samples come in the lattice's order, neighbours after
                // one another, and a simplified mesh's triangles are large:
                // a triangle that held one of the last samples mostly holds
                // this one too (on either side of an edge they alternate),
                // and a distance or two answer what a walk of the tree
                // would (the same answer: either finds a triangle within).
                constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
                std::array<std::uint32_t, 4> holders;
                holders.fill(kNone);
                const auto heldByRecent = [&](const glm::dvec3& p) {
                    for (std::size_t h = 0; h < holders.size() && holders[h] != kNone; ++h)
                        if (distanceTo(p, holders[h]) <= tolerance) {
                            std::rotate(holders.begin(), holders.begin() + std::ptrdiff_t(h),
                                        holders.begin() + std::ptrdiff_t(h) + 1);
                            return true;
                        }
                    return false;
                };
                for (std::size_t k = range.begin(); k != range.end(); ++k) {
                    const std::size_t i = only ? (*only)[k] : k;
                    const glm::dvec3 p(samples.points[i]);
                    if (heldByRecent(p)) continue;
                    const bool within =
                        tree.queryAny(p - glm::dvec3(tolerance), p + glm::dvec3(tolerance), [&](std::uint32_t t) {
                            if (!(distanceTo(p, t) <= tolerance)) return false;
                            std::rotate(holders.begin(), holders.end() - 1, holders.end());
                            holders[0] = t;
                            return true;
                        });
                    if (within) continue;
                    ++w.beyond;
                    const double d = nearest(p);
                    if (beyond) found.local().emplace_back(-d, std::uint32_t(i));
                    if (d > w.distance) w = {d, i, w.beyond};
                }
                return w;
            },
            join);
    });
    if (beyond) {
        for (const auto& part : found)
            beyond->insert(beyond->end(), part.begin(), part.end());
        std::sort(beyond->begin(), beyond->end());
        for (auto& [d, i] : *beyond)
            d = -d;
    }
    check.samplesBeyond = worst.beyond;
    if (worst.beyond > 0) {
        check.worst = worst.distance;
        check.worstAt = samples.origin + glm::dvec3(samples.points[worst.sample]);
    }
    return check;
}

} // namespace kerf::mesher

#include "PlanarFans.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kerf::mesher {

namespace {

using Tri = std::array<std::uint32_t, 3>;

constexpr std::uint32_t kUnseen = 0xFFFFFFFFu;

// One block's fan: where its triangles are (in the sorted order), the
// centre, the plane's normal and the boundary loop (in the triangles' turn).
struct Fan {
    std::uint32_t first = 0, count = 0; // its triangles' slice of the block order
    glm::dvec3 centre{0.0}, normal{0.0};
    std::vector<std::uint32_t> loop;
};

struct Scratch {
    std::vector<std::uint64_t> halfedges, boundary;
    std::vector<std::uint32_t> vertices;
    std::vector<Fan> fans;
};

std::uint64_t halfedge(std::uint32_t from, std::uint32_t to) { return std::uint64_t(from) << 32 | to; }

// The fan of one block's triangles, or false where they are not one flat disk.
bool fanOf(const Mesh& mesh, const std::vector<glm::dvec3>& normals, const std::vector<std::uint32_t>& valence,
           const std::pair<std::uint64_t, std::uint32_t>* tris, std::uint32_t count, double cellSize, double flatness,
           Scratch& s, Fan& fan)
{
    const glm::dvec3 n = normals[mesh.triangles[tris[0].second][0]];
    const glm::dvec3 p0 = mesh.vertices[mesh.triangles[tris[0].second][0]];
    if (n == glm::dvec3(0.0)) return false;
    s.halfedges.clear();
    s.vertices.clear();
    for (std::uint32_t i = 0; i < count; ++i) {
        const Tri& t = mesh.triangles[tris[i].second];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = t[std::size_t(k)];
            // The same sheet (the simplification's own test of a plane) and
            // the same plane (parallel faces of a step have the same normal).
            if (!(glm::dot(normals[v], n) > 1.0 - 1e-12)) return false;
            if (!(std::abs(glm::dot(mesh.vertices[v] - p0, n)) <= flatness)) return false;
            s.halfedges.push_back(halfedge(v, t[std::size_t(k + 1) % 3]));
            s.vertices.push_back(v);
        }
    }
    std::sort(s.halfedges.begin(), s.halfedges.end());
    if (std::adjacent_find(s.halfedges.begin(), s.halfedges.end()) != s.halfedges.end()) return false;
    s.boundary.clear();
    for (const std::uint64_t h : s.halfedges) {
        const std::uint64_t reverse = halfedge(std::uint32_t(h), std::uint32_t(h >> 32));
        if (!std::binary_search(s.halfedges.begin(), s.halfedges.end(), reverse)) s.boundary.push_back(h);
    }
    const std::size_t b = s.boundary.size();
    // Worth it only where the fan has fewer triangles.
    if (b < 3 || b + 2 >= count) return false;
    // One loop: every boundary vertex leaves once, and following the loop
    // from one edge comes back after all of them.
    for (std::size_t i = 1; i < b; ++i)
        if ((s.boundary[i] >> 32) == (s.boundary[i - 1] >> 32)) return false;
    fan.loop.clear();
    std::uint32_t at = std::uint32_t(s.boundary[0] >> 32);
    for (std::size_t i = 0; i < b; ++i) {
        fan.loop.push_back(at);
        const auto next = std::lower_bound(s.boundary.begin(), s.boundary.end(), halfedge(at, 0));
        if (next == s.boundary.end() || (*next >> 32) != at) return false;
        at = std::uint32_t(*next);
    }
    if (at != fan.loop[0]) return false;
    // A disk: V - E + F = 1. Its vertices off the loop go with its
    // triangles, so none may be used outside the block.
    // (A vertex off the loop has as many of the block's triangles as it has
    // in the whole mesh.)
    std::sort(s.vertices.begin(), s.vertices.end());
    std::vector<std::uint32_t> loopSorted = fan.loop;
    std::sort(loopSorted.begin(), loopSorted.end());
    if (std::adjacent_find(loopSorted.begin(), loopSorted.end()) != loopSorted.end()) return false;
    std::size_t distinct = 0;
    for (std::size_t i = 0; i < s.vertices.size();) {
        const std::uint32_t v = s.vertices[i];
        std::size_t j = i;
        while (j < s.vertices.size() && s.vertices[j] == v)
            ++j;
        if (!std::binary_search(loopSorted.begin(), loopSorted.end(), v) && valence[v] != j - i) return false;
        ++distinct;
        i = j;
    }
    const std::int64_t edges = (3 * std::int64_t(count) + std::int64_t(b)) / 2;
    if (std::int64_t(distinct) - edges + std::int64_t(count) != 1) return false;
    // The centre: the loop's mean, put on the plane.
    glm::dvec3 c(0.0);
    for (const std::uint32_t v : fan.loop)
        c += mesh.vertices[v];
    c /= double(b);
    c -= n * glm::dot(c - p0, n);
    // Every fan triangle turns the plane's way with a height (so none is a
    // sliver the simplification must first undo), and their angles at the
    // centre add up to one turn: the fan covers the disk once.
    double turn = 0.0;
    for (std::size_t i = 0; i < b; ++i) {
        const glm::dvec3 pa = mesh.vertices[fan.loop[i]], pb = mesh.vertices[fan.loop[(i + 1) % b]];
        const glm::dvec3 cr = glm::cross(pa - c, pb - c);
        const double twiceArea = glm::dot(cr, n);
        if (!(twiceArea >= 0.05 * cellSize * glm::length(pb - pa))) return false;
        turn += std::atan2(twiceArea, glm::dot(pa - c, pb - c));
    }
    if (!(std::abs(turn - 2.0 * std::numbers::pi) < 1e-6)) return false;
    fan.centre = c;
    fan.normal = n;
    return true;
}

// The block key of a point: its block's coordinates, 21 bits each.
std::uint64_t blockKey(const glm::dvec3& p, const glm::dvec3& origin, double blockSize)
{
    const glm::dvec3 q = glm::floor((p - origin) / blockSize) + glm::dvec3(double(1 << 20));
    const glm::u64vec3 k = glm::u64vec3(glm::clamp(q, glm::dvec3(0.0), glm::dvec3(double((1 << 21) - 1))));
    return k.x << 42 | k.y << 21 | k.z;
}

glm::dvec3 centroid(const Mesh& mesh, std::uint32_t t)
{
    const Tri& tri = mesh.triangles[t];
    return (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
}

// A block's triangles (order[first, first + count), all of one block of
// `blockSize`): its fan, or, where they are no flat disk, its eight halves'
// fans down to blocks of `smallest`.
void fanBlock(const Mesh& mesh, const std::vector<glm::dvec3>& normals, const std::vector<std::uint32_t>& valence,
              std::pair<std::uint64_t, std::uint32_t>* order, std::uint32_t first, std::uint32_t count,
              const glm::dvec3& origin, double blockSize, double smallest, double cellSize, double flatness,
              Scratch& s)
{
    Fan fan;
    if (fanOf(mesh, normals, valence, order + first, count, cellSize, flatness, s, fan)) {
        fan.first = first;
        fan.count = count;
        s.fans.push_back(std::move(fan));
        return;
    }
    const double half = 0.5 * blockSize;
    if (half < smallest * (1.0 - 1e-9) || count < 8) return;
    for (std::uint32_t i = first; i < first + count; ++i)
        order[i].first = blockKey(centroid(mesh, order[i].second), origin, half);
    std::sort(order + first, order + first + count);
    for (std::uint32_t i = first; i < first + count;) {
        std::uint32_t j = i;
        while (j < first + count && order[j].first == order[i].first)
            ++j;
        fanBlock(mesh, normals, valence, order, i, j - i, origin, half, smallest, cellSize, flatness, s);
        i = j;
    }
}

// The distance of p from the segment ab.
double fromSegment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b)
{
    const glm::dvec3 ab = b - a;
    const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    return glm::length(p - (a + t * ab));
}

// Where two fans meet, their loops share the marching cubes' vertices along
// the seam, one per cell, on a straight line: a loop vertex whose every
// triangle was in a fanned block, and which lies on the straight run of
// every loop through it, is dropped from all of them (both sides of the
// seam drop it, so they still meet edge for edge, and each fan's triangle
// over the run covers what its triangles over the vertices did). A run
// whose vertices do not all lie within `flatness` of the segment between
// its kept ends keeps them all, as does a loop that would have fewer than
// three. Returns the vertices dropped.
std::uint64_t dropSeamVertices(const Mesh& mesh, std::vector<Fan>& fans,
                               const std::vector<std::pair<std::uint64_t, std::uint32_t>>& order,
                               const std::vector<std::uint32_t>& valence, double flatness)
{
    const std::size_t n = mesh.vertices.size();
    std::vector<std::uint32_t> fanned(n, 0); // triangles in fanned blocks
    for (const Fan& f : fans)
        for (std::uint32_t i = f.first; i < f.first + f.count; ++i)
            for (const std::uint32_t v : mesh.triangles[order[i].second])
                ++fanned[v];
    std::vector<std::uint8_t> drop(n, 0);
    for (const Fan& f : fans)
        for (const std::uint32_t v : f.loop)
            drop[v] = fanned[v] == valence[v];
    auto straight = [&](std::uint32_t a, std::uint32_t v, std::uint32_t b) {
        // (The same figure whichever way a loop runs.)
        if (a > b) std::swap(a, b);
        const glm::dvec3 pa = mesh.vertices[a], pb = mesh.vertices[b], pv = mesh.vertices[v];
        const double along = glm::dot(pv - pa, pb - pa);
        return along > 0.0 && along < glm::dot(pb - pa, pb - pa) && fromSegment(pv, pa, pb) <= flatness;
    };
    for (const Fan& f : fans) {
        const std::size_t b = f.loop.size();
        for (std::size_t i = 0; i < b; ++i)
            if (!straight(f.loop[(i + b - 1) % b], f.loop[i], f.loop[(i + 1) % b])) drop[f.loop[i]] = 0;
    }
    // Runs judged whole against their kept ends, until nothing changes.
    for (bool changed = true; changed;) {
        changed = false;
        for (const Fan& f : fans) {
            const std::size_t b = f.loop.size();
            std::size_t start = b;
            for (std::size_t i = 0; i < b; ++i)
                if (!drop[f.loop[i]]) start = i;
            if (start == b) {
                // Every vertex would go: keep them all.
                for (const std::uint32_t v : f.loop)
                    drop[v] = 0;
                changed = true;
                continue;
            }
            std::size_t kept = 0;
            for (std::size_t k = 0; k < b;) {
                const std::size_t i = (start + k) % b;
                ++kept;
                std::size_t j = k + 1;
                while (j < b && drop[f.loop[(start + j) % b]])
                    ++j;
                const std::uint32_t a = f.loop[i], c = f.loop[(start + j) % b];
                bool within = true;
                for (std::size_t r = k + 1; r < j && within; ++r)
                    within = fromSegment(mesh.vertices[f.loop[(start + r) % b]], mesh.vertices[std::min(a, c)],
                                         mesh.vertices[std::max(a, c)]) <= flatness;
                if (!within) {
                    for (std::size_t r = k + 1; r < j; ++r)
                        drop[f.loop[(start + r) % b]] = 0;
                    changed = true;
                }
                k = j;
            }
            if (kept < 3) {
                for (const std::uint32_t v : f.loop)
                    drop[v] = 0;
                changed = true;
            }
        }
    }
    std::uint64_t dropped = 0;
    for (Fan& f : fans) {
        std::erase_if(f.loop, [&](std::uint32_t v) { return drop[v] != 0; });
    }
    for (std::size_t v = 0; v < n; ++v)
        dropped += drop[v];
    return dropped;
}

} // namespace

PlanarFanStats fanPlanarBlocks(Mesh& mesh, std::vector<glm::dvec3>& normals, const glm::dvec3& origin,
                               double cellSize, int blockCells, int smallestCells, double flatness,
                               tbb::task_arena& arena)
{
    PlanarFanStats stats;
    const std::size_t triangleCount = mesh.triangles.size();
    if (triangleCount == 0 || !(cellSize > 0.0) || blockCells < 1) return stats;
    // Each triangle's block, from its centroid (inside its cell), and the
    // triangles grouped by block.
    const double blockSize = cellSize * blockCells;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(triangleCount);
    std::vector<std::uint32_t> valence(mesh.vertices.size(), 0);
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), triangleCount, [&](std::size_t t) {
            order[t] = {blockKey(centroid(mesh, std::uint32_t(t)), origin, blockSize), std::uint32_t(t)};
        });
        tbb::parallel_sort(order.begin(), order.end());
    });
    // Each vertex's triangles, in the whole mesh.
    for (const Tri& t : mesh.triangles)
        for (const std::uint32_t v : t)
            ++valence[v];
    std::vector<std::uint32_t> groupStart;
    for (std::size_t i = 0; i < triangleCount; ++i)
        if (i == 0 || order[i].first != order[i - 1].first) groupStart.push_back(std::uint32_t(i));
    groupStart.push_back(std::uint32_t(triangleCount));
    const std::size_t groups = groupStart.size() - 1;

    tbb::enumerable_thread_specific<Scratch> scratch;
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), groups, [&](std::size_t g) {
            fanBlock(mesh, normals, valence, order.data(), groupStart[g], groupStart[g + 1] - groupStart[g], origin,
                     blockSize, cellSize * std::max(1, smallestCells), cellSize, flatness, scratch.local());
        });
    });
    std::vector<Fan> fans;
    for (Scratch& s : scratch)
        for (Fan& f : s.fans)
            fans.push_back(std::move(f));
    if (fans.empty()) return stats;
    std::sort(fans.begin(), fans.end(), [](const Fan& a, const Fan& b) { return a.first < b.first; });
    stats.seamVertices = dropSeamVertices(mesh, fans, order, valence, flatness);

    // The mesh rewritten in place: the other triangles in their order, then
    // the fans; the vertices no triangle uses any more dropped first, so
    // that the fans' centres take their room (no vector grows).
    std::vector<std::uint8_t> gone(triangleCount, 0);
    for (const Fan& f : fans)
        for (std::uint32_t i = f.first; i < f.first + f.count; ++i)
            gone[order[i].second] = 1;
    order = {};
    std::size_t kept = 0;
    for (std::size_t t = 0; t < triangleCount; ++t)
        if (!gone[t]) mesh.triangles[kept++] = mesh.triangles[t];
    mesh.triangles.resize(kept);
    std::vector<std::uint32_t> remap(mesh.vertices.size(), kUnseen);
    for (const Tri& t : mesh.triangles)
        for (const std::uint32_t v : t)
            remap[v] = 0;
    for (const Fan& f : fans)
        for (const std::uint32_t v : f.loop)
            remap[v] = 0;
    std::uint32_t vertices = 0;
    for (std::size_t v = 0; v < remap.size(); ++v)
        if (remap[v] == 0) {
            remap[v] = vertices;
            mesh.vertices[vertices] = mesh.vertices[v];
            normals[vertices] = normals[v];
            ++vertices;
        }
    mesh.vertices.resize(vertices);
    normals.resize(vertices);
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), mesh.triangles.size(), [&](std::size_t t) {
            for (std::uint32_t& v : mesh.triangles[t])
                v = remap[v];
        });
    });
    for (const Fan& f : fans) {
        const std::uint32_t centre = std::uint32_t(mesh.vertices.size());
        mesh.vertices.push_back(f.centre);
        normals.push_back(f.normal);
        for (std::size_t i = 0; i < f.loop.size(); ++i)
            mesh.triangles.push_back({centre, remap[f.loop[i]], remap[f.loop[(i + 1) % f.loop.size()]]});
    }
    stats.blocks = fans.size();
    stats.removed = triangleCount - mesh.triangles.size();
    return stats;
}

} // namespace kerf::mesher

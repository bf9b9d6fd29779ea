#include "kerf/mesher/MeshCheck.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

namespace kerf {

namespace {

struct VertexCounts {
    std::size_t unused = 0, edges = 0, boundary = 0, nonManifold = 0, misoriented = 0, nonManifoldVertices = 0;
    VertexCounts& operator+=(const VertexCounts& o)
    {
        unused += o.unused;
        edges += o.edges;
        boundary += o.boundary;
        nonManifold += o.nonManifold;
        misoriented += o.misoriented;
        nonManifoldVertices += o.nonManifoldVertices;
        return *this;
    }
};

struct TriangleSums {
    std::size_t degenerate = 0;
    double volume = 0.0, area = 0.0;
    double smallest = std::numeric_limits<double>::infinity();
};

struct Neighbour {
    std::uint32_t vertex;
    int out;            // triangles with edge v -> vertex
    int in;             // triangles with edge vertex -> v
    std::uint32_t next; // link successor when out == 1
};

bool repeated(const std::array<std::uint32_t, 3>& t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; }

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

} // namespace

MeshReport checkMesh(const Mesh& mesh)
{
    MeshReport r;
    const std::size_t vertexCount = mesh.vertices.size();
    const std::size_t triangleCount = mesh.triangles.size();
    r.triangles = triangleCount;
    if (3 * triangleCount >= std::numeric_limits<std::uint32_t>::max())
        throw std::runtime_error("mesh check: too many triangles");
    for (const auto& t : mesh.triangles)
        for (const std::uint32_t v : t)
            if (v >= vertexCount) throw std::runtime_error("mesh check: a triangle refers to a missing vertex");

    // Vertex -> triangles.
    std::vector<std::uint32_t> start(vertexCount + 1, 0);
    for (const auto& t : mesh.triangles)
        for (const std::uint32_t v : t)
            ++start[v + 1];
    for (std::size_t v = 0; v < vertexCount; ++v)
        start[v + 1] += start[v];
    std::vector<std::uint32_t> incident(start.back());
    {
        std::vector<std::uint32_t> cursor(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < triangleCount; ++i)
            for (const std::uint32_t v : mesh.triangles[i])
                incident[cursor[v]++] = std::uint32_t(i);
    }

    const VertexCounts counts = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, vertexCount, 4096), VertexCounts{},
        [&](const tbb::blocked_range<std::size_t>& range, VertexCounts c) {
            std::vector<Neighbour> nb;
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                if (start[v] == start[v + 1]) {
                    ++c.unused;
                    continue;
                }
                nb.clear();
                auto neighbour = [&](std::uint32_t u) -> Neighbour& {
                    for (auto& n : nb)
                        if (n.vertex == u) return n;
                    nb.push_back({u, 0, 0, 0});
                    return nb.back();
                };
                std::size_t linkEdges = 0;
                for (std::uint32_t k = start[v]; k < start[v + 1]; ++k) {
                    const auto& t = mesh.triangles[incident[k]];
                    if (repeated(t)) continue;
                    const int at = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
                    const std::uint32_t a = t[std::size_t((at + 1) % 3)], b = t[std::size_t((at + 2) % 3)];
                    Neighbour& na = neighbour(a);
                    ++na.out;
                    na.next = b;
                    ++neighbour(b).in;
                    ++linkEdges;
                }
                bool edgesFine = true;
                for (const Neighbour& n : nb) {
                    edgesFine = edgesFine && n.out == 1 && n.in == 1;
                    if (n.vertex < v) continue; // each edge counted at its lower vertex
                    ++c.edges;
                    const int total = n.out + n.in;
                    if (total == 1)
                        ++c.boundary;
                    else if (total > 2)
                        ++c.nonManifold;
                    else if (n.out != 1)
                        ++c.misoriented;
                }
                if (!edgesFine || nb.empty()) continue;
                // One disc: following the link from any neighbour visits every triangle.
                std::size_t steps = 0;
                std::uint32_t x = nb.front().vertex;
                do {
                    x = neighbour(x).next;
                    ++steps;
                } while (x != nb.front().vertex && steps <= linkEdges);
                if (steps != linkEdges) ++c.nonManifoldVertices;
            }
            return c;
        },
        [](VertexCounts a, const VertexCounts& b) { return a += b; });
    r.unusedVertices = counts.unused;
    r.vertices = vertexCount - counts.unused;
    r.edges = counts.edges;
    r.boundaryEdges = counts.boundary;
    r.nonManifoldEdges = counts.nonManifold;
    r.misorientedEdges = counts.misoriented;
    r.nonManifoldVertices = counts.nonManifoldVertices;
    std::vector<std::uint32_t>().swap(incident);
    std::vector<std::uint32_t>().swap(start);

    // Volume relative to a point of the mesh: exact differences far from the origin.
    const glm::dvec3 ref =
        vertexCount ? mesh.vertices[mesh.triangles.empty() ? 0 : mesh.triangles[0][0]] : glm::dvec3(0.0);
    const TriangleSums sums = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, triangleCount, 8192), TriangleSums{},
        [&](const tbb::blocked_range<std::size_t>& range, TriangleSums s) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const auto& t = mesh.triangles[i];
                if (repeated(t)) {
                    ++s.degenerate;
                    s.smallest = 0.0;
                    continue;
                }
                const glm::dvec3 a = mesh.vertices[t[0]] - ref, b = mesh.vertices[t[1]] - ref,
                                 c = mesh.vertices[t[2]] - ref;
                const glm::dvec3 cr = glm::cross(b - a, c - a);
                const double doubleArea = glm::length(cr);
                if (!(doubleArea > 0.0)) ++s.degenerate;
                s.area += 0.5 * doubleArea;
                s.smallest = std::min(s.smallest, 0.5 * doubleArea);
                s.volume += glm::dot(a, glm::cross(b, c)) / 6.0;
            }
            return s;
        },
        [](TriangleSums a, const TriangleSums& b) {
            a.degenerate += b.degenerate;
            a.volume += b.volume;
            a.area += b.area;
            a.smallest = std::min(a.smallest, b.smallest);
            return a;
        });
    r.degenerateTriangles = sums.degenerate;
    r.volume = sums.volume;
    r.area = sums.area;
    r.smallestArea = triangleCount ? sums.smallest : 0.0;

    // Components, through triangle edges.
    std::vector<std::uint32_t> parent(vertexCount);
    for (std::size_t v = 0; v < vertexCount; ++v)
        parent[v] = std::uint32_t(v);
    for (const auto& t : mesh.triangles) {
        const std::uint32_t a = findRoot(parent, t[0]);
        for (int k = 1; k < 3; ++k) {
            const std::uint32_t b = findRoot(parent, t[std::size_t(k)]);
            if (b != a) parent[b] = a;
        }
    }
    std::vector<bool> used(vertexCount, false);
    for (const auto& t : mesh.triangles)
        for (const std::uint32_t v : t)
            used[v] = true;
    for (std::size_t v = 0; v < vertexCount; ++v)
        if (used[v] && findRoot(parent, std::uint32_t(v)) == v) ++r.components;
    r.eulerCharacteristic = long(r.vertices) - long(r.edges) + long(r.triangles);
    return r;
}

} // namespace kerf

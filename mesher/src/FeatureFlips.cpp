#include "FeatureFlips.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <unordered_set>

namespace kerf::mesher {

namespace {

bool isFeature(const std::vector<glm::dvec3>& normals, std::uint32_t v) { return normals[v] == glm::dvec3(0.0); }

std::uint64_t undirected(std::uint32_t a, std::uint32_t b)
{
    return a < b ? std::uint64_t(a) << 32 | b : std::uint64_t(b) << 32 | a;
}

} // namespace

std::uint64_t flipFeatureEdges(Mesh& mesh, const std::vector<glm::dvec3>& normals)
{
    // Fan triangles: one feature vertex, the edge opposite it between two
    // ordinary vertices. Keyed by that edge.
    struct Fan {
        std::uint64_t edge;
        std::uint32_t triangle;
        bool operator<(const Fan& o) const { return edge < o.edge || (edge == o.edge && triangle < o.triangle); }
    };
    std::vector<Fan> fans;
    std::unordered_set<std::uint64_t> edgesOfFeatures; // existing edges between two feature vertices
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        int features = 0, at = -1;
        for (int k = 0; k < 3; ++k)
            if (isFeature(normals, tri[std::size_t(k)])) {
                ++features;
                at = k;
            }
        if (features == 1) fans.push_back({undirected(tri[std::size_t(at + 1) % 3], tri[std::size_t(at + 2) % 3]), t});
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = tri[std::size_t(k)], b = tri[std::size_t(k + 1) % 3];
            if (isFeature(normals, a) && isFeature(normals, b)) edgesOfFeatures.insert(undirected(a, b));
        }
    }
    std::sort(fans.begin(), fans.end());
    std::vector<std::uint8_t> changed(mesh.triangles.size(), 0);
    std::uint64_t flips = 0;
    for (std::size_t i = 0; i + 1 < fans.size(); ++i) {
        if (fans[i].edge != fans[i + 1].edge) continue;
        const std::uint32_t t1 = fans[i].triangle, t2 = fans[i + 1].triangle;
        ++i;
        if (changed[t1] || changed[t2]) continue;
        // Rotate each so its feature vertex comes first: t1 = (f1, u, w), t2 = (f2, w, u).
        auto rotated = [&](std::uint32_t t) {
            std::array<std::uint32_t, 3> r = mesh.triangles[t];
            while (!isFeature(normals, r[0]))
                std::rotate(r.begin(), r.begin() + 1, r.end());
            return r;
        };
        const auto a = rotated(t1), b = rotated(t2);
        const std::uint32_t f1 = a[0], u = a[1], w = a[2], f2 = b[0];
        if (f1 == f2 || b[1] != w || b[2] != u) continue;
        if (edgesOfFeatures.count(undirected(f1, f2))) continue;
        const glm::dvec3 p1 = mesh.vertices[f1], pu = mesh.vertices[u], pw = mesh.vertices[w], p2 = mesh.vertices[f2];
        const glm::dvec3 before = glm::cross(pu - p1, pw - p1) + glm::cross(pw - p2, pu - p2);
        const glm::dvec3 n1 = glm::cross(pu - p1, p2 - p1), n2 = glm::cross(pw - p2, p1 - p2);
        if (!(glm::dot(n1, before) > 0.0) || !(glm::dot(n2, before) > 0.0)) continue;
        mesh.triangles[t1] = {f1, u, f2};
        mesh.triangles[t2] = {f2, w, f1};
        changed[t1] = changed[t2] = 1;
        edgesOfFeatures.insert(undirected(f1, f2));
        ++flips;
    }
    return flips;
}

} // namespace kerf::mesher

#include "kerf/viewport/OverlayMeshes.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>

namespace kerf {

namespace {

constexpr int kSides = 10; // round enough at the few pixels these bars span

void addTriangle(TriangleMesh& m, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& n)
{
    for (const glm::dvec3& v : {a, b, c}) {
        m.positions.push_back(v);
        m.normals.push_back(glm::vec3(n));
        m.bounds = m.bounds.merged(Aabb{v, v});
    }
}

// Two unit vectors perpendicular to `axis` and to each other.
void perpendiculars(const glm::dvec3& axis, glm::dvec3& u, glm::dvec3& v)
{
    const glm::dvec3 other = std::abs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    u = glm::normalize(glm::cross(axis, other));
    v = glm::cross(axis, u);
}

// The side of a truncated cone from `a` (radius ra) to `b` (radius rb).
void addFrustum(TriangleMesh& m, const glm::dvec3& a, const glm::dvec3& b, double ra, double rb)
{
    const glm::dvec3 axis = glm::normalize(b - a);
    glm::dvec3 u, v;
    perpendiculars(axis, u, v);
    const double slope = (ra - rb) / glm::length(b - a); // normals lean towards the narrow end
    for (int i = 0; i < kSides; ++i) {
        const double t0 = 2.0 * std::numbers::pi * i / kSides, t1 = 2.0 * std::numbers::pi * (i + 1) / kSides;
        const glm::dvec3 d0 = std::cos(t0) * u + std::sin(t0) * v, d1 = std::cos(t1) * u + std::sin(t1) * v;
        const glm::dvec3 n = glm::normalize(d0 + d1 + slope * axis);
        addTriangle(m, a + ra * d0, a + ra * d1, b + rb * d1, n);
        if (rb > 0.0) addTriangle(m, a + ra * d0, b + rb * d1, b + rb * d0, n);
    }
}

PlacedMesh placed(TriangleMesh mesh, glm::vec3 color, const char* id)
{
    PlacedMesh p;
    p.id = id;
    p.mesh = std::move(mesh);
    p.color = color;
    return p;
}

} // namespace

PlacedMesh markerMesh(const glm::dvec3& p, double radius, glm::vec3 color)
{
    TriangleMesh m;
    m.bounds = Aabb::empty();
    const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int sx : {0, 1})
        for (int sy : {2, 3})
            for (int sz : {4, 5}) {
                glm::dvec3 a = axes[sx], b = axes[sy], c = axes[sz];
                // Counter-clockwise seen from outside.
                if (glm::dot(glm::cross(b - a, c - a), a + b + c) < 0.0) std::swap(b, c);
                addTriangle(m, p + radius * a, p + radius * b, p + radius * c, glm::normalize(a + b + c));
            }
    return placed(std::move(m), color, "marker");
}

PlacedMesh barMesh(const glm::dvec3& a, const glm::dvec3& b, double radius, glm::vec3 color)
{
    TriangleMesh m;
    m.bounds = Aabb::empty();
    if (glm::length(b - a) > 0.0) addFrustum(m, a, b, radius, radius);
    return placed(std::move(m), color, "bar");
}

PlacedMesh arrowMesh(const glm::dvec3& from, const glm::dvec3& axis, double length, double radius, glm::vec3 color)
{
    TriangleMesh m;
    m.bounds = Aabb::empty();
    const glm::dvec3 neck = from + 0.78 * length * axis, tip = from + length * axis;
    addFrustum(m, from, neck, radius, radius);
    addFrustum(m, neck, tip, 3.0 * radius, 0.0);
    // The cone's base, facing back along the shaft.
    glm::dvec3 u, v;
    perpendiculars(axis, u, v);
    for (int i = 0; i < kSides; ++i) {
        const double t0 = 2.0 * std::numbers::pi * i / kSides, t1 = 2.0 * std::numbers::pi * (i + 1) / kSides;
        addTriangle(m, neck, neck + 3.0 * radius * (std::cos(t1) * u + std::sin(t1) * v),
                    neck + 3.0 * radius * (std::cos(t0) * u + std::sin(t0) * v), -axis);
    }
    return placed(std::move(m), color, "arrow");
}

PlacedMesh quadMesh(const std::array<glm::dvec3, 4>& c, glm::vec3 color)
{
    TriangleMesh m;
    m.bounds = Aabb::empty();
    const glm::dvec3 n = glm::normalize(glm::cross(c[1] - c[0], c[2] - c[0]));
    addTriangle(m, c[0], c[1], c[2], n);
    addTriangle(m, c[0], c[2], c[3], n);
    addTriangle(m, c[0], c[2], c[1], -n);
    addTriangle(m, c[0], c[3], c[2], -n);
    return placed(std::move(m), color, "quad");
}

PlacedMesh boxEdgesMesh(const Aabb& box, double radius, glm::vec3 color)
{
    TriangleMesh m;
    m.bounds = Aabb::empty();
    const auto corner = [&](int i) {
        return glm::dvec3((i & 1) ? box.max.x : box.min.x, (i & 2) ? box.max.y : box.min.y,
                          (i & 4) ? box.max.z : box.min.z);
    };
    for (int a = 0; a < 8; ++a)
        for (int bit : {1, 2, 4})
            if (!(a & bit) && glm::length(corner(a | bit) - corner(a)) > 0.0)
                addFrustum(m, corner(a), corner(a | bit), radius, radius);
    return placed(std::move(m), color, "box edges");
}

} // namespace kerf

#pragma once
// Axis-aligned boxes in double precision. Infinite coordinates are allowed
// (halfspaces are unbounded); an empty box has min > max.

#include <glm/vec3.hpp>

#include <algorithm>
#include <limits>

namespace kerf {

struct Aabb {
    glm::dvec3 min{std::numeric_limits<double>::infinity()};
    glm::dvec3 max{-std::numeric_limits<double>::infinity()};

    static Aabb empty() { return {}; }
    static Aabb infinite()
    {
        const double inf = std::numeric_limits<double>::infinity();
        return {glm::dvec3(-inf), glm::dvec3(inf)};
    }
    static Aabb centered(const glm::dvec3& halfSize) { return {-halfSize, halfSize}; }

    bool isEmpty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    /// Finite in every coordinate (an empty box counts as bounded).
    bool isBounded() const;
    glm::dvec3 size() const { return max - min; }
    glm::dvec3 center() const { return 0.5 * (min + max); }
    bool contains(const glm::dvec3& p) const;
    bool overlaps(const Aabb& o) const;

    /// Grows every side by `d` (d < 0 shrinks; an over-shrunk box becomes empty).
    Aabb grown(double d) const;
    Aabb merged(const Aabb& o) const;
    Aabb intersected(const Aabb& o) const;
    /// Minkowski sum with another box (used for array sweeps).
    Aabb swept(const Aabb& offsets) const;

    bool operator==(const Aabb&) const = default;
};

} // namespace kerf

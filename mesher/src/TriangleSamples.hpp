#pragma once
// Where a triangle is checked against the exact surface: three points on
// each edge (at 1/4, 1/2, 3/4) and four inside (the centroid and halfway
// from it to each vertex). The vertices themselves lie on the surface by
// construction. A flat triangle strays from a smooth surface most near its
// middle and its edges' middles, from a cut-off sharp edge along the edge
// it cuts: these points see both.

#include <glm/vec3.hpp>

#include <cstddef>

namespace kerf::mesher {

struct TriangleSample {
    double w[3]; // barycentric weights of the triangle's vertices
    int edge;    // edge e runs from vertex e to vertex e + 1; -1 inside
};

inline constexpr std::size_t kTriangleSamples = 13;
inline constexpr TriangleSample kTriangleSamplePattern[kTriangleSamples] = {
    {{0.75, 0.25, 0.0}, 0},          {{0.5, 0.5, 0.0}, 0},           {{0.25, 0.75, 0.0}, 0},
    {{0.0, 0.75, 0.25}, 1},          {{0.0, 0.5, 0.5}, 1},           {{0.0, 0.25, 0.75}, 1},
    {{0.25, 0.0, 0.75}, 2},          {{0.5, 0.0, 0.5}, 2},           {{0.75, 0.0, 0.25}, 2},
    {{1 / 3.0, 1 / 3.0, 1 / 3.0}, -1}, {{2 / 3.0, 1 / 6.0, 1 / 6.0}, -1}, {{1 / 6.0, 2 / 3.0, 1 / 6.0}, -1},
    {{1 / 6.0, 1 / 6.0, 2 / 3.0}, -1},
};

/// Appends the sample points of triangle (a, b, c) to `out`.
template <class Out> void appendTriangleSamples(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, Out& out)
{
    for (const TriangleSample& s : kTriangleSamplePattern)
        out.push_back(s.w[0] * a + s.w[1] * b + s.w[2] * c);
}

} // namespace kerf::mesher

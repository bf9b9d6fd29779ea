#pragma once
// "Would this new triangle cross one already in the mesh, or come so close
// that the file's rounding could make it cross?": the guard of the
// refiner's splits and flips and of the collapser's collapses. A change
// that makes two triangles cross leaves a mesh that no longer bounds a
// solid (a slicer fills it wrongly), so such changes are not made.

#include "TriangleClearance.hpp"
#include "TriangleTree.hpp"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>

namespace kerf::mesher {

/// Whether triangle `tri` (vertex indices) with corners p[0..2] crosses, or
/// comes within `clearance` of (TriangleClearance.hpp), a triangle t of
/// `grid` for which skip(t) is false. corners(t, q) fills q with t's
/// corners and returns t's vertex indices (shared indices are what two
/// triangles may share).
template <class Skip, class Corners>
bool crossesAnyInGrid(const TriangleTree& grid, const std::array<std::uint32_t, 3>& tri, const glm::dvec3 (&p)[3],
                      double clearance, Skip&& skip, Corners&& corners)
{
    const glm::dvec3 lo = glm::min(p[0], glm::min(p[1], p[2])) - clearance;
    const glm::dvec3 hi = glm::max(p[0], glm::max(p[1], p[2])) + clearance;
    bool crossing = false;
    grid.query(lo, hi, [&](std::uint32_t t) {
        if (crossing || skip(t)) return;
        glm::dvec3 q[3];
        const std::array<std::uint32_t, 3> other = corners(t, q);
        if (glm::any(glm::lessThan(hi, glm::min(q[0], glm::min(q[1], q[2])))) ||
            glm::any(glm::greaterThan(lo, glm::max(q[0], glm::max(q[1], q[2])))))
            return;
        crossing = trianglesTooClose(tri, p, other, q, clearance);
    });
    return crossing;
}

} // namespace kerf::mesher

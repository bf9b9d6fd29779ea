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
#include <cstddef>
#include <cstdint>
#include <limits>

namespace kerf::mesher {

/// A triangle about to be made: vertex indices and corners.
struct NewTriangle {
    std::array<std::uint32_t, 3> tri;
    glm::dvec3 p[3];
};

/// Whether any of the new triangles crosses, or comes within `clearance`
/// of (TriangleClearance.hpp), a triangle t of `grid` for which skip(t) is
/// false. corners(t, q) fills q with t's corners and returns t's vertex
/// indices (shared indices are what two triangles may share). The new
/// triangles of one change lie around one vertex: one walk of the tree
/// over the box of them all finds every triangle that any of them could
/// meet (a walk per triangle went down the same branches each time), and
/// each is tested against the new triangles whose own box it meets. The
/// new triangles among themselves are not tested here.
template <class Skip, class Corners>
bool anyCrossesInGrid(const TriangleTree& grid, const NewTriangle* added, std::size_t count, double clearance,
                      Skip&& skip, Corners&& corners)
{
    constexpr std::size_t kMax = 32;
    if (count > kMax) { // a fan of more than 32 triangles (a hub of a flat face): one walk each
        for (std::size_t i = 0; i < count; ++i)
            if (anyCrossesInGrid(grid, added + i, 1, clearance, skip, corners)) return true;
        return false;
    }
    glm::dvec3 lo[kMax], hi[kMax];
    glm::dvec3 allLo(std::numeric_limits<double>::infinity()), allHi(-std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < count; ++i) {
        const glm::dvec3* p = added[i].p;
        lo[i] = glm::min(p[0], glm::min(p[1], p[2])) - clearance;
        hi[i] = glm::max(p[0], glm::max(p[1], p[2])) + clearance;
        allLo = glm::min(allLo, lo[i]);
        allHi = glm::max(allHi, hi[i]);
    }
    bool crossing = false;
    grid.query(allLo, allHi, [&](std::uint32_t t) {
        if (crossing || skip(t)) return;
        glm::dvec3 q[3];
        const std::array<std::uint32_t, 3> other = corners(t, q);
        const glm::dvec3 qlo = glm::min(q[0], glm::min(q[1], q[2])), qhi = glm::max(q[0], glm::max(q[1], q[2]));
        for (std::size_t i = 0; i < count && !crossing; ++i) {
            if (glm::any(glm::lessThan(hi[i], qlo)) || glm::any(glm::greaterThan(lo[i], qhi))) continue;
            crossing = trianglesTooClose(added[i].tri, added[i].p, other, q, clearance);
        }
    });
    return crossing;
}

/// Whether two of the new triangles of one change cross or come within
/// `clearance` of each other (the guard above leaves them out).
inline bool newTrianglesTooClose(const NewTriangle* added, std::size_t count, double clearance)
{
    for (std::size_t i = 0; i < count; ++i)
        for (std::size_t j = i + 1; j < count; ++j)
            if (trianglesTooClose(added[i].tri, added[i].p, added[j].tri, added[j].p, clearance)) return true;
    return false;
}

} // namespace kerf::mesher

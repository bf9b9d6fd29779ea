#pragma once
// The triangulation of a polygon (a rim of n corners, no corner inside)
// whose worst triangle is best: dynamic programming over the polygon's
// diagonals (the minimum-weight triangulation of a polygon, Klincsek 1980,
// with the worst triangle's cost in place of the sum). Ties go to the
// smaller sum. O(n^3) costs asked for, each at most once; a cost of
// infinity forbids a triangle.
//
// The refinement uses it where no split or flip of a triangle helps (the
// turned leg's pommel, where two sharp edges of the part meet at a tangent
// and the cells' triangles reach across both): the disk of triangles round
// it is triangulated anew on its own corners.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace kerf::mesher {

struct RimTriangulation {
    double worst = 0.0; // the largest cost of its triangles
    double sum = 0.0;
    std::vector<std::array<int, 3>> triangles; // corners (i, k, j), i < k < j: the rim's winding
};

/// The best triangulation of the rim's corners 0..n-1 (n >= 3), cost(i, k, j)
/// the cost of triangle (i, k, j) for i < k < j; nothing when every
/// triangulation has a forbidden triangle.
std::optional<RimTriangulation> triangulateRim(int n, const std::function<double(int, int, int)>& cost);

} // namespace kerf::mesher

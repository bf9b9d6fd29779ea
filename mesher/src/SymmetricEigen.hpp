#pragma once
// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations,
// and the least-squares solution of A x = r around a point with small
// eigenvalues left out (a truncated pseudo-inverse): what dual contouring
// and extended marching cubes use to place a vertex on a sharp edge (two
// strong directions) or corner (three) without being thrown off by the
// directions the data do not constrain.

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace kerf::mesher {

/// a = v diag(w) v^T with orthonormal columns v[.][k]; `a` is destroyed.
inline void symmetricEigen(double a[3][3], double w[3], double v[3][3])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            v[i][j] = i == j ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 32; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * diag || off == 0.0) break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    for (int i = 0; i < 3; ++i)
        w[i] = a[i][i];
}

/// The x nearest `around` that minimises |A x - r|^2 over the directions
/// whose eigenvalue exceeds `ratio` times the largest; `rank` receives how
/// many directions that was. A is symmetric (given by its six entries).
inline glm::dvec3 truncatedSolve(const double A[3][3], const glm::dvec3& r, const glm::dvec3& around, double ratio,
                                 int* rank = nullptr)
{
    double a[3][3], w[3], v[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            a[i][j] = A[i][j];
    symmetricEigen(a, w, v);
    const double largest = std::max({w[0], w[1], w[2]});
    // Residual at `around`, solved along the strong directions only.
    glm::dvec3 residual = r;
    for (int i = 0; i < 3; ++i)
        residual[i] -= A[i][0] * around.x + A[i][1] * around.y + A[i][2] * around.z;
    glm::dvec3 x = around;
    int kept = 0;
    for (int k = 0; k < 3; ++k) {
        if (!(w[k] > ratio * largest) || !(largest > 0.0)) continue;
        const glm::dvec3 u(v[0][k], v[1][k], v[2][k]);
        x += u * (glm::dot(u, residual) / w[k]);
        ++kept;
    }
    if (rank) *rank = kept;
    return x;
}

} // namespace kerf::mesher

#include "FeaturePoint.hpp"

#include "SymmetricEigen.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace kerf::mesher {


double smallestNormalCosine(const glm::dvec3* normals, int count)
{
    double smallest = 1.0;
    for (int i = 0; i < count; ++i)
        for (int j = i + 1; j < count; ++j)
            smallest = std::min(smallest, glm::dot(normals[i], normals[j]));
    return smallest;
}

FeatureFit fitTangentPlanes(const glm::dvec3* points, const glm::dvec3* normals, int count)
{
    FeatureFit fit;
    if (count <= 0) return fit;
    glm::dvec3 mean(0.0);
    for (int i = 0; i < count; ++i)
        mean += points[i];
    mean /= double(count);
    double a[3][3] = {};
    glm::dvec3 rhs(0.0); // sum n (n . (p - mean))
    for (int i = 0; i < count; ++i) {
        const glm::dvec3& n = normals[i];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                a[r][c] += n[r] * n[c];
        rhs += n * glm::dot(n, points[i] - mean);
    }
    double w[3], v[3][3];
    symmetricEigen(a, w, v);
    // Strongest direction first.
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int i, int j) { return w[i] > w[j]; });
    const double largest = w[order[0]];
    glm::dvec3 offset(0.0);
    // Singular values of the normal matrix are sqrt(w): keep those above a
    // tenth of the largest, so w above a hundredth.
    for (int j = 0; j < 3; ++j) {
        const int k = order[j];
        if (!(w[k] > 0.01 * largest)) break;
        const glm::dvec3 u(v[0][k], v[1][k], v[2][k]);
        offset += u * (glm::dot(u, rhs) / w[k]);
        ++fit.rank;
        if (j == 1) {
            fit.edgePoint = mean + offset;
            const int weakest = order[2];
            fit.edgeDirection = glm::dvec3(v[0][weakest], v[1][weakest], v[2][weakest]);
        }
    }
    fit.point = mean + offset;
    return fit;
}

std::optional<glm::dvec3> edgePointInBox(const FeatureFit& fit, const glm::dvec3& lo, const glm::dvec3& hi)
{
    if (fit.rank < 2) return std::nullopt;
    // The line edgePoint + s * edgeDirection: the interval of s inside the
    // box (slab by slab), then the s nearest the fit's point.
    const glm::dvec3 c = fit.edgePoint, d = fit.edgeDirection;
    double sMin = -std::numeric_limits<double>::infinity(), sMax = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-12) {
            if (!(c[a] > lo[a] && c[a] < hi[a])) return std::nullopt;
            continue;
        }
        double s0 = (lo[a] - c[a]) / d[a], s1 = (hi[a] - c[a]) / d[a];
        if (s0 > s1) std::swap(s0, s1);
        sMin = std::max(sMin, s0);
        sMax = std::min(sMax, s1);
    }
    if (!(sMin < sMax)) return std::nullopt;
    // Stay a little inside: a point on the cell's face would sit on the
    // polygon's edges.
    const double inset = 1e-3 * (sMax - sMin);
    const double s = std::clamp(glm::dot(fit.point - c, d), sMin + inset, sMax - inset);
    return c + s * d;
}

} // namespace kerf::mesher

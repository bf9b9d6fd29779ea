#include "kerf/mesher/Triangulate.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace kerf {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

bool chordAllowed(const std::uint8_t* faceMasks, int n, int i, int j)
{
    if (j == i + 1 || (i == 0 && j == n - 1)) return true; // a polygon edge
    return (faceMasks[i] & faceMasks[j]) == 0;
}

// best[i][j]: the best worst-quality of the sub-polygon i..j (j - i >= 2),
// -infinity when none is allowed; split[i][j]: its apex.
struct Table {
    double best[kMaxPolygon][kMaxPolygon];
    std::int8_t split[kMaxPolygon][kMaxPolygon];
};

template <class Quality> bool solve(const std::uint8_t* faceMasks, int n, Quality quality, Table& t)
{
    for (int i = 0; i + 1 < n; ++i)
        t.best[i][i + 1] = kInfinity;
    for (int len = 2; len < n; ++len) {
        for (int i = 0; i + len < n; ++i) {
            const int j = i + len;
            double best = -kInfinity;
            std::int8_t split = -1;
            for (int k = i + 1; k < j; ++k) {
                if (!chordAllowed(faceMasks, n, i, k) || !chordAllowed(faceMasks, n, k, j)) continue;
                const double a = t.best[i][k], b = t.best[k][j];
                if (a == -kInfinity || b == -kInfinity) continue;
                const double q = std::min({a, b, quality(i, k, j)});
                // Near-ties keep the first apex, so that rounding noise (a
                // part far from the origin) does not flip the choice.
                if (split < 0 || q > best + 1e-9) {
                    best = q;
                    split = std::int8_t(k);
                }
            }
            t.best[i][j] = split < 0 ? -kInfinity : best;
            t.split[i][j] = split;
        }
    }
    return t.split[0][n - 1] >= 0;
}

int emit(const Table& t, int i, int j, std::array<std::uint8_t, 3>* out, int written)
{
    if (j - i < 2) return written;
    const int k = t.split[i][j];
    out[written++] = {std::uint8_t(i), std::uint8_t(k), std::uint8_t(j)};
    written = emit(t, i, k, out, written);
    return emit(t, k, j, out, written);
}

} // namespace

int triangulatePolygon(const glm::dvec3* points, const std::uint8_t* faceMasks, int n, std::array<std::uint8_t, 3>* out)
{
    if (n < 3 || n > kMaxPolygon) return 0;
    if (n == 3) {
        out[0] = {0, 1, 2};
        return 1;
    }
    // Relative to the first vertex: exact differences even far from the origin.
    glm::dvec3 p[kMaxPolygon];
    for (int i = 0; i < n; ++i)
        p[i] = points[i] - points[0];
    glm::dvec3 normal(0.0); // Newell
    for (int i = 0; i < n; ++i)
        normal += glm::cross(p[i], p[(i + 1) % n]);
    const double len = glm::length(normal);
    const glm::dvec3 unit = len > 0.0 ? normal / len : glm::dvec3(0.0);
    const double k = 2.0 * std::sqrt(3.0);
    auto quality = [&](int a, int b, int c) {
        const glm::dvec3 ab = p[b] - p[a], bc = p[c] - p[b], ca = p[a] - p[c];
        const glm::dvec3 cr = glm::cross(ab, -ca);
        const double sum = glm::dot(ab, ab) + glm::dot(bc, bc) + glm::dot(ca, ca);
        if (!(sum > 0.0)) return -1.0;
        const double signedDoubleArea = len > 0.0 ? glm::dot(cr, unit) : glm::length(cr);
        return k * signedDoubleArea / sum;
    };
    Table t;
    if (!solve(faceMasks, n, quality, t)) return 0;
    return emit(t, 0, n - 1, out, 0);
}

bool hasAllowedTriangulation(const std::uint8_t* faceMasks, int n)
{
    if (n < 3 || n > kMaxPolygon) return false;
    Table t;
    return solve(
        faceMasks, n, [](int, int, int) { return 1.0; }, t);
}

} // namespace kerf

#include "RimTriangulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace kerf::mesher {

std::optional<RimTriangulation> triangulateRim(int n, const std::function<double(int, int, int)>& cost)
{
    if (n < 3) return std::nullopt;
    constexpr double kForbidden = std::numeric_limits<double>::infinity();
    const auto at = [n](int i, int j) { return std::size_t(i) * std::size_t(n) + std::size_t(j); };
    // best[i][j]: the polygon of corners i..j (j - i >= 2) closed by the
    // diagonal (i, j), as (worst, sum), and the corner k of its triangle on (i, j).
    std::vector<std::pair<double, double>> best(std::size_t(n) * std::size_t(n), {0.0, 0.0});
    std::vector<int> apex(std::size_t(n) * std::size_t(n), -1);
    for (int span = 2; span < n; ++span)
        for (int i = 0; i + span < n; ++i) {
            const int j = i + span;
            std::pair<double, double> chosen{kForbidden, kForbidden};
            for (int k = i + 1; k < j; ++k) {
                const auto& left = best[at(i, k)];
                const auto& right = best[at(k, j)];
                if (left.first == kForbidden || right.first == kForbidden) continue;
                const double c = cost(i, k, j);
                if (!(c < kForbidden)) continue;
                const std::pair<double, double> total{std::max({c, left.first, right.first}),
                                                      c + left.second + right.second};
                if (total < chosen) {
                    chosen = total;
                    apex[at(i, j)] = k;
                }
            }
            best[at(i, j)] = chosen;
        }
    if (apex[at(0, n - 1)] < 0) return std::nullopt;
    RimTriangulation result{best[at(0, n - 1)].first, best[at(0, n - 1)].second, {}};
    std::vector<std::pair<int, int>> open{{0, n - 1}};
    while (!open.empty()) {
        const auto [i, j] = open.back();
        open.pop_back();
        if (j - i < 2) continue;
        const int k = apex[at(i, j)];
        result.triangles.push_back({i, k, j});
        open.emplace_back(i, k);
        open.emplace_back(k, j);
    }
    return result;
}

} // namespace kerf::mesher

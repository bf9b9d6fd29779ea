#pragma once
// Triangles by where they are, for "what could this new triangle cross?"
// while a mesh changes (the refiner's splits and flips).
//
// A loose hierarchical grid: a triangle lives at the level whose cell is at
// least as large as its bounding box, in the cell of its box's centre; a
// query at each level looks at the cells its box, widened by one cell,
// covers. Triangles from a hundredth of a millimetre to a metre across
// share one structure without a large triangle filling thousands of cells.

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace kerf::mesher {

class TriangleGrid {
public:
    /// `smallest`: the cell edge of the finest level (mm).
    explicit TriangleGrid(double smallest) : base_(smallest > 0.0 ? smallest : 1.0), levels_(kLevels) {}

    void insert(std::uint32_t t, const glm::dvec3& lo, const glm::dvec3& hi)
    {
        const auto [level, key] = place(lo, hi);
        levels_[std::size_t(level)][key].push_back(t);
    }

    void erase(std::uint32_t t, const glm::dvec3& lo, const glm::dvec3& hi)
    {
        const auto [level, key] = place(lo, hi);
        auto& cells = levels_[std::size_t(level)];
        const auto it = cells.find(key);
        if (it == cells.end()) return;
        auto& bucket = it->second;
        const auto pos = std::find(bucket.begin(), bucket.end(), t);
        if (pos != bucket.end()) {
            *pos = bucket.back();
            bucket.pop_back();
        }
        if (bucket.empty()) cells.erase(it);
    }

    /// Calls visit(t) for every triangle whose cell is near the box (a
    /// superset of those whose boxes meet it).
    template <class Visit> void query(const glm::dvec3& lo, const glm::dvec3& hi, Visit&& visit) const
    {
        for (int level = 0; level <= maxLevel_; ++level) {
            const auto& cells = levels_[std::size_t(level)];
            if (cells.empty()) continue;
            const double cell = base_ * std::ldexp(1.0, level);
            const glm::ivec3 a = cellOf(lo, cell) - 1, b = cellOf(hi, cell) + 1;
            const double span = double(b.x - a.x + 1) * double(b.y - a.y + 1) * double(b.z - a.z + 1);
            if (span > double(cells.size())) {
                // Fewer occupied cells than cells in the box: look at those.
                for (const auto& [key, bucket] : cells) {
                    const glm::ivec3 c = unpack(key);
                    if (glm::all(glm::greaterThanEqual(c, a)) && glm::all(glm::lessThanEqual(c, b)))
                        for (const std::uint32_t t : bucket)
                            visit(t);
                }
                continue;
            }
            for (int z = a.z; z <= b.z; ++z)
                for (int y = a.y; y <= b.y; ++y)
                    for (int x = a.x; x <= b.x; ++x) {
                        const auto it = cells.find(pack({x, y, z}));
                        if (it == cells.end()) continue;
                        for (const std::uint32_t t : it->second)
                            visit(t);
                    }
        }
    }

private:
    static constexpr int kLevels = 48;
    static constexpr int kBias = 1 << 20; // cell indices kept within 21 bits

    static glm::ivec3 cellOf(const glm::dvec3& p, double cell)
    {
        return glm::ivec3(glm::floor(glm::clamp(p / cell, -double(kBias - 2), double(kBias - 2))));
    }

    static std::uint64_t pack(const glm::ivec3& c)
    {
        auto field = [](int v) { return std::uint64_t(std::uint32_t(v + kBias)); };
        return field(c.x) << 42 | field(c.y) << 21 | field(c.z);
    }
    static glm::ivec3 unpack(std::uint64_t key)
    {
        auto field = [&](int shift) { return int((key >> shift) & 0x1FFFFFu) - kBias; };
        return {field(42), field(21), field(0)};
    }

    std::pair<int, std::uint64_t> place(const glm::dvec3& lo, const glm::dvec3& hi)
    {
        const glm::dvec3 size = hi - lo;
        const double extent = std::max({size.x, size.y, size.z});
        int level = 0;
        while (level < kLevels - 1 && base_ * std::ldexp(1.0, level) < extent)
            ++level;
        maxLevel_ = std::max(maxLevel_, level);
        return {level, pack(cellOf(0.5 * (lo + hi), base_ * std::ldexp(1.0, level)))};
    }

    double base_;
    int maxLevel_ = 0;
    std::vector<std::unordered_map<std::uint64_t, std::vector<std::uint32_t>>> levels_;
};

} // namespace kerf::mesher

#include "kerf/voxelizer/OcclusionMap.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace kerf {

namespace {

constexpr float kNothing = std::numeric_limits<float>::infinity();

glm::dvec3 corner(const Aabb& box, int c)
{
    return {c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y, c & 4 ? box.max.z : box.min.z};
}

} // namespace

OcclusionMap OcclusionMap::fromDepths(const ViewRequirement& view, int width, int height, std::span<const float> depths,
                                      int block)
{
    if (width <= 0 || height <= 0 || block <= 0 || depths.size() != std::size_t(width) * std::size_t(height))
        throw std::invalid_argument("OcclusionMap: the depths do not match the picture's size");
    OcclusionMap m;
    m.view = view;
    m.width = width;
    m.height = height;
    m.block = block;
    m.columns = (width + block - 1) / block;
    m.rows = (height + block - 1) / block;
    m.farthest.assign(std::size_t(m.columns) * std::size_t(m.rows), 0.0f);
    for (int y = 0; y < height; ++y) {
        float* row = m.farthest.data() + std::size_t(y / block) * std::size_t(m.columns);
        const float* d = depths.data() + std::size_t(y) * std::size_t(width);
        for (int x = 0; x < width; ++x) {
            const float v = d[x] > 0.0f ? d[x] : kNothing; // NaN fails the test too
            float& f = row[x / block];
            f = std::max(f, v);
        }
    }
    return m;
}

bool OcclusionMap::project(const glm::dvec3& p, glm::dvec2& pixel) const
{
    const glm::dvec3 d = p - view.eye;
    const double along = glm::dot(d, view.forward);
    double scale = view.halfHeight; // half the picture's height at `along`, in the units of d
    if (!view.orthographic) {
        if (along <= 1e-9) return false;
        scale *= along;
    }
    const double x = glm::dot(d, view.right) / (scale * view.aspect); // -1..1 across the picture
    const double y = glm::dot(d, view.up) / scale;
    pixel = {(x + 1.0) * 0.5 * double(width), (1.0 - y) * 0.5 * double(height)};
    return std::isfinite(pixel.x) && std::isfinite(pixel.y);
}

bool OcclusionMap::hides(const Aabb& box, double margin) const
{
    if (farthest.empty() || box.isEmpty() || !box.isBounded()) return false;
    // The box's picture lies inside the rectangle of its corners' pictures.
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
        glm::dvec2 px;
        if (!project(corner(box, c), px)) return false; // reaches the eye's plane: not judged
        lo = glm::min(lo, px);
        hi = glm::max(hi, px);
    }
    // One pixel more on each side for the rays through pixel centres.
    const int x0 = std::max(0, int(std::floor(lo.x)) - 1), x1 = std::min(width - 1, int(std::floor(hi.x)) + 1);
    const int y0 = std::max(0, int(std::floor(lo.y)) - 1), y1 = std::min(height - 1, int(std::floor(hi.y)) + 1);
    if (x0 > x1 || y0 > y1) return false; // outside the picture: the frustum test's business
    // No ray reaches the box before this depth.
    double entry = std::numeric_limits<double>::infinity();
    if (view.orthographic) {
        for (int c = 0; c < 8; ++c) entry = std::min(entry, glm::dot(corner(box, c) - view.eye, view.forward));
    } else {
        const glm::dvec3 nearest = glm::clamp(view.eye, box.min, box.max);
        entry = glm::length(nearest - view.eye);
    }
    const double limit = entry - margin;
    if (!(limit > 0.0)) return false;
    for (int by = y0 / block; by <= y1 / block; ++by)
        for (int bx = x0 / block; bx <= x1 / block; ++bx)
            if (!(double(farthest[std::size_t(by) * std::size_t(columns) + std::size_t(bx)]) < limit)) return false;
    return true;
}

} // namespace kerf

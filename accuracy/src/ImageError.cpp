#include "kerf/accuracy/ImageError.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace kerf {

namespace {

// The angle between two directions, in degrees; 0 when either is zero.
double angleDegrees(const glm::vec3& a, const glm::vec3& b)
{
    const glm::dvec3 u(a), v(b);
    const double cross = glm::length(glm::cross(u, v)), dot = glm::dot(u, v);
    if (cross == 0.0 && dot == 0.0) return 0.0;
    return std::atan2(cross, dot) * 180.0 / std::numbers::pi;
}

} // namespace

ImageError compareImages(const TraceImage& image, const TraceImage& reference)
{
    if (image.width != reference.width || image.height != reference.height)
        throw std::invalid_argument("compareImages: the images differ in size (" + std::to_string(image.width) + "x" +
                                    std::to_string(image.height) + " against " + std::to_string(reference.width) + "x" +
                                    std::to_string(reference.height) + ")");
    ImageError e;
    e.pixels = image.depth.size();
    std::vector<double> depth, normal;
    for (std::size_t i = 0; i < e.pixels; ++i) {
        const bool a = image.hit(i), b = reference.hit(i);
        if (a && b) {
            depth.push_back(std::abs(double(image.depth[i]) - double(reference.depth[i])));
            normal.push_back(angleDegrees(image.normal[i], reference.normal[i]));
        } else if (a) {
            ++e.onlyImage;
        } else if (b) {
            ++e.onlyReference;
        }
    }
    e.bothHit = depth.size();
    e.depthMm = summarizeErrors(depth);
    e.normalDegrees = summarizeErrors(normal);
    return e;
}

} // namespace kerf

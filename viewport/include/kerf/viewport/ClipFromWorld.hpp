#pragma once
// The projection every rasterizing pass shares with the tracers' rays:
// depth planes around what is drawn, and clip = P * V with the view's
// translation taken in double from a render origin near the drawn geometry
// (so float only sees small, local numbers).

#include "kerf/document/Aabb.hpp"
#include "kerf/tracer/Camera.hpp"

#include <glm/mat4x4.hpp>

namespace kerf::vk {

struct DepthPlanes {
    double near = 0.1, far = 1000.0; // mm along the view direction (ortho: near may be negative)
};

/// Near and far planes around `scene` (what is drawn) for `camera`.
DepthPlanes depthPlanesAround(const Camera& camera, const Aabb& scene);

/// Clip coordinates (Vulkan: y down, depth 0..1) of points given relative
/// to `origin` (world mm).
glm::dmat4 clipFromWorld(const Camera& camera, const glm::dvec3& origin, const DepthPlanes& planes);

} // namespace kerf::vk

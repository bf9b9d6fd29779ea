#include "kerf/viewport/ClipFromWorld.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <limits>

namespace kerf::vk {

DepthPlanes depthPlanesAround(const Camera& camera, const Aabb& scene)
{
    double zMin = std::numeric_limits<double>::max(), zMax = 0.0;
    for (int c = 0; c < 8 && !scene.isEmpty(); ++c) {
        const glm::dvec3 p(c & 1 ? scene.max.x : scene.min.x, c & 2 ? scene.max.y : scene.min.y,
                           c & 4 ? scene.max.z : scene.min.z);
        const double z = glm::dot(p - camera.eye(), camera.forward());
        zMin = std::min(zMin, z);
        zMax = std::max(zMax, z);
    }
    if (scene.isEmpty()) zMin = 1.0, zMax = 10.0;
    const bool ortho = camera.projection() == Projection::Orthographic;
    DepthPlanes planes;
    planes.far = std::max(zMax, 1.0) * 1.01 + 1.0;
    planes.near = ortho ? std::min(zMin, 0.0) - 1.0 : std::max(std::max(zMin, 0.0) * 0.99, planes.far * 1e-5);
    return planes;
}

glm::dmat4 clipFromWorld(const Camera& camera, const glm::dvec3& origin, const DepthPlanes& planes)
{
    const double aspect = double(camera.width()) / double(camera.height());
    const double halfHeight = camera.halfHeight(), near = planes.near, far = planes.far;
    const glm::dvec3 r = camera.right(), u = camera.up(), f = camera.forward();
    const glm::dvec3 d = origin - camera.eye();
    glm::dmat4 view(1.0);
    for (int c = 0; c < 3; ++c) {
        view[c][0] = r[c];
        view[c][1] = u[c];
        view[c][2] = f[c];
    }
    view[3] = glm::dvec4(glm::dot(d, r), glm::dot(d, u), glm::dot(d, f), 1.0);
    glm::dmat4 proj(0.0);
    proj[0][0] = 1.0 / (halfHeight * aspect);
    proj[1][1] = -1.0 / halfHeight;
    if (camera.projection() == Projection::Orthographic) {
        proj[2][2] = 1.0 / (far - near);
        proj[3][2] = -near / (far - near);
        proj[3][3] = 1.0;
    } else {
        proj[2][2] = far / (far - near);
        proj[3][2] = -far * near / (far - near);
        proj[2][3] = 1.0;
    }
    return proj * view;
}

} // namespace kerf::vk

#include "kerf/document/Aabb.hpp"

#include <glm/common.hpp>

#include <cmath>

namespace kerf {

bool Aabb::isBounded() const
{
    if (isEmpty()) return true;
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(min[i]) || !std::isfinite(max[i])) return false;
    return true;
}

bool Aabb::contains(const glm::dvec3& p) const
{
    return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z && p.z <= max.z;
}

bool Aabb::overlaps(const Aabb& o) const
{
    return !isEmpty() && !o.isEmpty() && min.x <= o.max.x && o.min.x <= max.x && min.y <= o.max.y &&
           o.min.y <= max.y && min.z <= o.max.z && o.min.z <= max.z;
}

Aabb Aabb::grown(double d) const
{
    if (isEmpty()) return *this;
    Aabb r{min - glm::dvec3(d), max + glm::dvec3(d)};
    return r.isEmpty() ? empty() : r;
}

Aabb Aabb::merged(const Aabb& o) const
{
    if (isEmpty()) return o;
    if (o.isEmpty()) return *this;
    return {glm::min(min, o.min), glm::max(max, o.max)};
}

Aabb Aabb::intersected(const Aabb& o) const
{
    Aabb r{glm::max(min, o.min), glm::min(max, o.max)};
    return r.isEmpty() ? empty() : r;
}

Aabb Aabb::swept(const Aabb& offsets) const
{
    if (isEmpty() || offsets.isEmpty()) return empty();
    return {min + offsets.min, max + offsets.max};
}

} // namespace kerf

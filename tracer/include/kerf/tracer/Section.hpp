#pragma once
// A section view: the part cut by a plane, as a drawing shows it. Everything
// on the plane's positive side (dot(normal, p) > offset) is taken away; where
// the plane passes through the solid, the tracers report the cut face (the
// cap) with the plane's normal and the feature kSectionCap, so that it can
// be shaded apart from the part's own surfaces.

#include "kerf/tracer/SectionCap.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace kerf {

/// The feature id of a section's cut face (kNoFeature - 1).
inline constexpr std::uint32_t kSectionCap = KERF_SECTION_CAP_FEATURE;

struct Section {
    bool enabled = false;
    glm::dvec3 normal{1.0, 0.0, 0.0}; // unit, world frame
    double offset = 0.0;              // mm: the plane is dot(normal, p) = offset
    bool operator==(const Section&) const = default;

    /// A plane across axis 0, 1 or 2 (X, Y, Z) at `at` mm, cutting away the
    /// side towards +axis (or -axis when `flip`).
    static Section alongAxis(int axis, double at, bool flip = false)
    {
        Section s;
        s.enabled = true;
        s.normal = glm::dvec3(0.0);
        s.normal[axis] = flip ? -1.0 : 1.0;
        s.offset = flip ? -at : at;
        return s;
    }
};

} // namespace kerf

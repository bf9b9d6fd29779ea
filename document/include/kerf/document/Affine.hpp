#pragma once
// Rigid (and mirrored) placements: p' = linear * p + translation, in double.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Node.hpp"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace kerf {

struct Affine {
    glm::dmat3 linear{1.0};
    glm::dvec3 translation{0.0};

    glm::dvec3 apply(const glm::dvec3& p) const { return linear * p + translation; }
    glm::dvec3 applyLinear(const glm::dvec3& v) const { return linear * v; }
    /// this ∘ other: first other, then this.
    Affine operator*(const Affine& other) const
    {
        return {linear * other.linear, linear * other.translation + translation};
    }
    /// Inverse of an orthogonal placement (rotation and reflection only).
    Affine inverseOrthogonal() const;
    /// Tightest axis-aligned box around the image of `box`. Infinite sides stay
    /// infinite only along the axes they reach (no 0 * inf).
    Aabb apply(const Aabb& box) const;

    static Affine translate(const glm::dvec3& t) { return {glm::dmat3(1.0), t}; }
    /// The document's node transform: translate + Rz * Ry * Rx (degrees).
    static Affine fromTransform(const Transform& t);
    /// Reflection across the plane dot(n, p) = offset (n of unit length).
    static Affine reflection(const glm::dvec3& unitNormal, double offset);
};

/// Rotation about the parent's fixed axes X, then Y, then Z (degrees). Exact
/// for multiples of 90 degrees, so axis-aligned parts stay axis-aligned.
glm::dmat3 rotationFromDegrees(const glm::dvec3& degrees);

/// The document transform of a rigid placement (a proper rotation and a
/// translation; no reflection): the inverse of Affine::fromTransform up to
/// rounding. Angles within 1e-9 degrees of a multiple of 90 are snapped to
/// it, so axis-aligned placements stay exact through a round trip.
Transform transformFromAffine(const Affine& placement);

} // namespace kerf

#pragma once
// What a click on the part means when measuring: the point a person aims at,
// not the pixel they hit. Near the cursor, in order of preference:
//   1. a corner of a sharp box           (Vertex)
//   2. the centre of a round edge         (CircleCentre: the rim of a hole
//      or the end of a dowel, where it lies in a face across its axis)
//   3. a point on a sharp box edge        (Edge)
//   4. the surface under the cursor       (Face)
// Candidates come from the tape's primitives and are kept only when the
// exact field says they are on the part's surface (a corner that a cut
// removed, or a box edge buried inside another body, is no snap) and, for
// corners and edges, visible from the camera. The point returned is exact
// to the document's placement (a hole centre is the cylinder's axis, not a
// root found by a ray), so two snaps measure what the document says.
//
// Pure functions of their arguments; safe from any thread.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/tracer/Camera.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>

namespace kerf {

enum class SnapKind { Face, Edge, Vertex, CircleCentre };

/// "face", "edge", "corner", "centre".
const char* snapKindName(SnapKind kind);

struct SnapPoint {
    SnapKind kind = SnapKind::Face;
    glm::dvec3 point{0.0}; // world, mm
    std::uint32_t feature = 0; // index into tape.features() of the primitive it came from
};

struct SnapOptions {
    /// How far from the cursor (pixels) a corner, centre or edge is taken.
    double radiusPixels = 10.0;
    /// How close to the surface (|f|, mm) a candidate must be to count as on it.
    double onSurface = 1e-3;
};

/// The snap for the image position `pixel` (Camera::ray's convention), or
/// none when nothing of the part is under or near the cursor.
std::optional<SnapPoint> snapAt(const Tape& tape, const Camera& camera, glm::dvec2 pixel, const SnapOptions& options = {});

} // namespace kerf

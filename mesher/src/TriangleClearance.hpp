#pragma once
// "Do these two triangles come closer than the file can tell apart?": the
// guard that keeps simplification and refinement robust to the rounding of
// the written coordinates.
//
// A crossing test in double (SelfIntersections.hpp) decides touching
// configurations by rounding noise: a face triangle whose edge passes
// through a neighbouring wall's edge, or a vertex lying on another sheet,
// reads as "not crossing" in memory and as crossing once the coordinates
// are float32 (the table top's mortise corners did exactly that). A change
// is therefore refused unless every new triangle keeps a clearance from the
// triangles it does not share a vertex with, and, around a shared vertex,
// the edges away from it keep that clearance from the other triangle. A
// clearance of a few float32 spacings survives any rounding the file does.
//
// Triangles that share an edge are judged by trianglesCross alone (they
// can only overlap by folding onto each other, which it sees).

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace kerf::mesher {

/// The distance between point p and triangle abc (Ericson, Real-Time
/// Collision Detection, 5.1.5).
double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

/// The distance between segments pq and rs (Ericson 5.1.9).
double segmentSegmentDistance(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r, const glm::dvec3& s);

/// The distance between segment pq and triangle abc (0 when it passes
/// through it).
double segmentTriangleDistance(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b,
                               const glm::dvec3& c);

/// Whether segment pq is shown to lie further than `clearance` from
/// triangle t by one plane with all of t on one side and p and q beyond it:
/// t's own plane, or a plane through one of its edges square to it.
/// Conservative (a hair more than the clearance is asked for, against
/// rounding): true means segmentTriangleDistance exceeds the clearance;
/// false decides nothing. Around a shared vertex, the far edge of a
/// neighbour on a curved sheet clears the other's plane and one on the same
/// flat face clears an edge, at a fraction of the distance's cost.
bool segmentClearOf(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3* t, double clearance);

/// Whether triangles A and B (vertex indices, corners a[3], b[3]) cross, or
/// come within `clearance` of each other other than at what they share (see
/// above).
bool trianglesTooClose(const std::array<std::uint32_t, 3>& A, const glm::dvec3* a,
                       const std::array<std::uint32_t, 3>& B, const glm::dvec3* b, double clearance);

} // namespace kerf::mesher

#pragma once
// Checks that an extrude profile is a simple polygon: at least three points,
// non-zero area, no repeated consecutive point, no two edges touching except
// neighbours at their shared point. Either winding is accepted.

#include <glm/vec2.hpp>

#include <optional>
#include <string>
#include <vector>

namespace kerf {

/// Empty when the profile is a simple polygon; otherwise the first defect
/// found, naming the points or edges involved (0-based indices).
std::optional<std::string> findProfileDefect(const std::vector<glm::dvec2>& profile);

/// Signed area (positive when counter-clockwise).
double signedArea(const std::vector<glm::dvec2>& profile);

} // namespace kerf

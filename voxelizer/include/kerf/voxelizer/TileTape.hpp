#pragma once
// A tile's exact tape in the GPU form (TileTapeFormat.h): the tape the tile
// was built from (simplified for the tile's box, rebased to its corner),
// flattened into 32-bit words so that the tracer can evaluate the exact
// field near the surface (the hybrid refinement) on the GPU and, through
// evaluateTileTape(), identically on the CPU.
//
// The simplified tape equals the part's field exactly inside the tile's box
// (IntervalEvaluator::simplify), and only there: evaluate it at tile-relative
// points within the tile.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/voxelizer/TileTapeFormat.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

namespace kerf::voxel {

inline constexpr std::uint32_t kNoTape = KERF_NO_TAPE;

/// The GPU form of `tape` (whose origin should be the tile's corner, so that
/// the frames' float translations are small). Empty when the tape is empty,
/// needs a deeper stack than KERF_TAPE_MAX_STACK or has more instructions
/// than KERF_TAPE_MAX_INSTRUCTIONS: such a tile is traced on its voxels.
std::vector<std::uint32_t> encodeTileTape(const Tape& tape);

/// The field of an encoded tape at `p` (relative to the tape's origin, mm),
/// in float, as shaders/trace.comp computes it. `tape` points at the tape's
/// first word.
float evaluateTileTape(const std::uint32_t* tape, const glm::vec3& p);

/// The field with its gradient by forward-mode differentiation (the
/// evaluator's Dual semantics: comparisons look at values, the derivative
/// of sqrt at 0 is taken as 0): x the field, yzw its gradient in the tape's
/// frame; `feature` receives the deciding feature (an index into the part's
/// features). The normal of the hybrid refinement: exact on either side of
/// a crease, where central differences would blur it.
glm::vec4 evaluateTileTapeGradient(const std::uint32_t* tape, const glm::vec3& p, std::uint32_t& feature);

} // namespace kerf::voxel

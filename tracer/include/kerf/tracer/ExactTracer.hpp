#pragma once
// The exact reference image: sphere tracing of the field itself, in double,
// no voxels involved. Slow; used by tests to check the voxel tracer and by
// trace-preview --exact.
//
// Each ray is clipped to the tape's bounds (grown by epsilon) and marched by
// the field's value, which never oversteps the surface because every
// operation keeps the field 1-Lipschitz (the evaluator's primitives are exact
// distances, placements isometries, booleans and blends non-expanding). The
// ray hits where the field drops below `epsilon` (mm); the normal is the
// normalised gradient there, the feature the one deciding the value there.
// Rays that take more than a few thousand steps (skimming a surface) count
// as misses. Rays are marched 64 at a time so that the evaluator's batched,
// vectorised loops do the work.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/Image.hpp"

namespace kerf {

/// Traces every pixel of `camera`'s image against `tape` (any origin), rows
/// in parallel with oneTBB on `threads` threads (0: every core). `epsilon`
/// (mm, > 0) is the hit distance. An empty tape gives an image of misses.
TraceImage traceExact(const Tape& tape, const Camera& camera, double epsilon, int threads = 0);

} // namespace kerf

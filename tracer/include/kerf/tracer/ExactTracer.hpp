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

#include "kerf/document/Progress.hpp"
#include "kerf/evaluator/Tape.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/Image.hpp"

namespace kerf {

/// Traces every pixel of `camera`'s image against `tape` (any origin), rows
/// in parallel with oneTBB on `threads` threads (0: every core). `epsilon`
/// (mm, > 0) is the hit distance. An empty tape gives an image of misses.
/// `work` hears the fraction of rows traced; cancelled, the tracing stops
/// between rows and the image is not complete.
TraceImage traceExact(const Tape& tape, const Camera& camera, double epsilon, int threads = 0,
                      const Progress& work = {});

/// What one exactly traced ray found (picking and measuring in the viewport).
struct ExactHit {
    bool hit = false;
    double depth = 0.0;        // mm along the ray from its origin
    glm::dvec3 point{0.0};     // world, mm
    glm::dvec3 normal{0.0};    // unit outward normal
    std::uint32_t feature = kNoFeature; // index into tape.features()
};

/// Sphere-traces one world-space ray against `tape`, as traceExact() does
/// per pixel. Pure function; safe from any thread.
ExactHit castExactRay(const Tape& tape, const Ray& ray, double epsilon);

} // namespace kerf

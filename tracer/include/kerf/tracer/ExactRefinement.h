// Tuning of the hybrid refinement (TraceQuality::Exact), shared by the CPU
// reference tracer (tracer/src/ReferenceTracer.cpp) and the GPU one
// (shaders/trace.comp) so that the two cannot drift. Preprocessor
// definitions only: C++ and GLSL both read it. Lengths are in voxel edges
// of the voxel being searched; docs/benchmarks.md has what they cost.
#ifndef KERF_EXACT_REFINEMENT_H
#define KERF_EXACT_REFINEMENT_H

// How far beyond a populated voxel's segment, both ways, the exact field is
// searched: the exact surface departs from the trilinear one by a fraction
// of a voxel (sharp edges rounded off, creases filled in).
#define KERF_EXACT_MARGIN 1.0
// Sphere-tracing steps per populated voxel before the window's end is tried
// as a bracket; and with a bracket already known (the trilinear crossing
// inside the exact surface), before regula falsi takes over.
#define KERF_EXACT_STEPS 8
#define KERF_EXACT_BRACKETED_STEPS 2
// Regula falsi (Illinois) steps on a bracketed crossing.
#define KERF_EXACT_REFINEMENTS 8
// The ray hits where the exact field drops below this.
#define KERF_EXACT_EPSILON 0.001

#endif

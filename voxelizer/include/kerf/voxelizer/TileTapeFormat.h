// The GPU form of a tile's exact tape, shared by C++ (voxelizer/src/TileTape.cpp,
// the CPU reference tracer) and GLSL (shaders/trace.comp), so that the two
// sides cannot drift. Preprocessor definitions only: both languages read it.
// docs/voxel-format.md ("A tile's exact tape") describes the layout:
//
//   word 0                 instruction count n
//   word 1                 shape count m
//   2 words per instruction  op | shape << 8, then k (f32 bits)
//   20 words per shape     kind, feature, frame (12 x f32: row-major 3x3, then
//                          the translation; tape-relative point -> local
//                          frame), 6 parameters (f32; an extrude's and a
//                          revolve's are its half height (unused by a
//                          revolve), then its polygon's first word and point
//                          count as u32)
//   2 words per polygon point  x, y (f32)
//
// Everything is relative to the tape's first word; positions are
// tile-relative millimetres (the tape is rebased to the tile's corner).
#ifndef KERF_TILE_TAPE_FORMAT_H
#define KERF_TILE_TAPE_FORMAT_H

// Operations (the values of kerf::Op).
#define KERF_TAPE_PRIMITIVE 0u
#define KERF_TAPE_MIN 1u
#define KERF_TAPE_MAX 2u
#define KERF_TAPE_SMOOTH_MIN 3u
#define KERF_TAPE_SMOOTH_MAX 4u
#define KERF_TAPE_NEGATE 5u
#define KERF_TAPE_OFFSET 6u
#define KERF_TAPE_SHELL 7u

// Shape kinds: evaluator/include/kerf/evaluator/ShapeKinds.h.
#include "kerf/evaluator/ShapeKinds.h"

#define KERF_TAPE_HEADER_WORDS 2u
#define KERF_TAPE_INSTRUCTION_WORDS 2u
#define KERF_TAPE_SHAPE_WORDS 20u
#define KERF_TAPE_SHAPE_FRAME 2u  // first frame word within a shape
#define KERF_TAPE_SHAPE_PARAMS 14u // first parameter word within a shape

// The evaluator's stack lives in registers (eight named ones in the shader;
// a dynamically indexed array would live in local memory, and slowed
// lavapipe's whole kernel fourfold): a tile whose tape needs a deeper stack,
// or has more instructions than this, carries no tape and is traced on its
// voxels alone. The bundled examples' tile tapes need at most 7.
#define KERF_TAPE_MAX_STACK 8
#define KERF_TAPE_MAX_INSTRUCTIONS 256u

// TileEntry.tape of a tile without an exact tape.
#define KERF_NO_TAPE 0xFFFFFFFFu

#endif

// The numbers of the shape kinds (a tape's primitives), read by C++ (the
// kerf::ShapeKind enum below) and by GLSL (shaders/tape_shapes.glsl, through
// TileTapeFormat.h), so that the two languages cannot number them apart.
// Each kind's formula is its unit in Primitives.hpp and its function in
// tape_shapes.glsl; TapeLanguagesTest evaluates every kind in both.
#ifndef KERF_SHAPE_KINDS_H
#define KERF_SHAPE_KINDS_H

#define KERF_SHAPE_BOX 0u
#define KERF_SHAPE_SPHERE 1u
#define KERF_SHAPE_CYLINDER 2u
#define KERF_SHAPE_CONE 3u
#define KERF_SHAPE_TORUS 4u
#define KERF_SHAPE_EXTRUDE 5u
#define KERF_SHAPE_HALFSPACE 6u
#define KERF_SHAPE_REVOLVE 7u
#define KERF_SHAPE_KINDS 8u // kinds from 0 to this, exclusive; any other word is an error (NaN)

#ifdef __cplusplus
#include <cstdint>
namespace kerf {
enum class ShapeKind : std::uint8_t {
    Box = KERF_SHAPE_BOX,
    Sphere = KERF_SHAPE_SPHERE,
    Cylinder = KERF_SHAPE_CYLINDER,
    Cone = KERF_SHAPE_CONE,
    Torus = KERF_SHAPE_TORUS,
    Extrude = KERF_SHAPE_EXTRUDE,
    Halfspace = KERF_SHAPE_HALFSPACE,
    Revolve = KERF_SHAPE_REVOLVE,
};
} // namespace kerf
#endif

#endif

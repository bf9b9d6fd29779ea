// Shared by C++ and GLSL: the band within which a min or max keeps its left
// operand's feature (the tape's earlier child) rather than the right one's.
//
// Why: faces of two features that lie in one plane (a round-over box flush
// with the board it shapes, both turned 30 degrees) give the same distance
// up to rounding, and the exact comparison picked one or the other from
// point to point: the viewport drew stripes and speckle of feature edges
// over a flat face. A ten-thousandth of a millimetre is far above rounding
// near the origin and far below anything a part shows; it moves which
// feature a point belongs to, never a value.
#ifndef KERF_FEATURE_TIE_H
#define KERF_FEATURE_TIE_H

#define KERF_FEATURE_TIE 1e-4

#endif

#pragma once
// What a mesh file can hold: STL stores float32 coordinates, so two vertices
// closer than float32's spacing at their magnitude become one vertex to a
// reader that welds by position (every slicer does), and a triangle thinner
// than that spacing becomes a line. The mesher keeps its vertices apart by a
// few of these spacings and checks its result in the coordinates written.
//
// Float32 values have 24 significant bits: at 1,000 mm they are 61 nm apart,
// at 100,000 mm 7.8 micrometres.

#include "kerf/document/Aabb.hpp"

namespace kerf {

/// The distance between adjacent float32 values at magnitude |x| (the
/// spacing just above it, so never zero).
double float32Spacing(double x);

/// The float32 spacing at the largest coordinate magnitude of `box`.
double float32Spacing(const Aabb& box);

} // namespace kerf

#pragma once
// A mesh as the file holds it, and as another program reads it back.
//
// STL stores each triangle's corners as float32 coordinates, and every
// slicer and CAM program welds them by position: two vertices that the
// mesher keeps apart but that round to the same float32 point are one
// vertex to them, and a triangle thinner than float32's spacing becomes a
// line or turns over. A mesh that is a closed 2-manifold by its indices can
// be open, pinched or self-intersecting as a file. 3MF keeps the indices,
// but lib3mf writes coordinates as float32 printed with six decimals.
//
// fitToWritten() makes the mesh hold up in its written coordinates: it
// rounds every vertex as the file will, finds what the rounding broke
// (vertices that became one point, triangles without area or turned over)
// and mends it: collapses an edge that rounding shortened to nothing (the
// link condition keeps the topology), or moves a vertex by a step of the
// file's precision away from what it met. readBack() then gives what a
// reader sees: the written coordinates, welded by position (STL) or kept
// by index (3MF).
//
// Threads: both run their passes over the vertices and triangles in the
// caller's oneTBB arena (the weld sorts, in parallel, instead of a hash
// table); the result does not depend on them. The repairs themselves are
// sequential and run only where writing breaks something, which the
// mesher's spacing of vertices (FilePrecision.hpp) makes rare.

#include "kerf/mesher/Mesh.hpp"

#include <glm/vec3.hpp>

#include <cstddef>

namespace kerf {

enum class WrittenFormat {
    Float32,            // binary and ASCII STL (ASCII printed to round-trip float32), OBJ, PLY
    Float32SixDecimals, // 3MF through lib3mf: float32, printed with %f
};

/// The coordinate a reader gets for x (mm, file coordinates).
double writtenCoordinate(double x, WrittenFormat format);

struct WrittenFit {
    std::size_t collapses = 0;  // edges collapsed because rounding joined their ends
    std::size_t nudges = 0;     // vertices moved by a step of the file's precision
    std::size_t unresolved = 0; // problems left (0 unless the part is beyond the format's precision)
    double largestMove = 0.0;   // mm: the furthest any vertex moved (rounding, nudges, collapses)
};

/// Makes `mesh` (closed, oriented, world coordinates) keep its topology and
/// orientation in the file's coordinates, where the file stores
/// `position - offset`. Vertices keep their double positions except those
/// nudged; every vertex then rounds to a distinct point and every triangle
/// keeps a non-zero, rightly oriented area in the written coordinates.
WrittenFit fitToWritten(Mesh& mesh, WrittenFormat format, const glm::dvec3& offset = glm::dvec3(0.0));

/// What a reader gets from the file: vertices at their written coordinates
/// (file coordinates, plus `offset`, in double); with `weld`, vertices that
/// were written to the same point joined into one (as STL readers do).
Mesh readBack(const Mesh& mesh, WrittenFormat format, bool weld, const glm::dvec3& offset = glm::dvec3(0.0));

} // namespace kerf

#pragma once
// The surface inside one marching-cubes cell, as closed polygons whose
// vertices are the cell's sign-changing edges. No case table: the polygons
// are assembled from the cell's six faces.
//
// Cell numbering. Corner q = x + 2y + 4z (x, y, z in {0, 1}). Edge
// e = 4 * axis + j runs along `axis` from its lower corner, whose two other
// coordinates (in increasing axis order) are the bits of j. Face
// f = 2 * axis + side is the face where that coordinate equals `side`.
//
// Why the result is a closed, consistently oriented 2-manifold (with the
// mesher's flood fill guaranteeing that both cells of every face with a sign
// change are meshed):
// - Face segments. On a face, marching squares joins its sign-changing
//   edges in pairs: one segment when one corner (or three) is inside or two
//   adjacent corners are; on an ambiguous face (diagonal corners inside) two
//   segments, chosen by the asymptotic decider: the bilinear interpolant of
//   the face's four values has a saddle of value
//   S = (v00 v11 - v10 v01) / (v00 + v11 - v10 - v01), and the inside corners
//   are joined through the face iff S < 0 (inside; S = 0 counts as outside,
//   like a corner value of 0). This uses the face's four values only, in a
//   fixed corner order (the global axes), so the two cells sharing the face
//   compute the same bits and choose the same segments: no crack, no overlap.
// - Orientation. Each segment is directed so that, seen from outside the
//   cell, the inside corners are on its right. The neighbour across the face
//   sees the face from the other side, so it directs the same segment the
//   other way: every shared mesh edge is traversed once in each direction.
//   At a vertex (a lattice edge with an inside end I) the two faces of the
//   cell meeting there have outward normals n1, n2; the segment leaves the
//   vertex in the face where (n1 x n2) . (I - vertex) has one sign and enters
//   in the other, so every vertex has exactly one incoming and one outgoing
//   segment per cell, and the segments link into disjoint directed cycles.
// - Triangulating a cycle inside its cell (Triangulate.hpp) adds only edges
//   between vertices of the same cycle that share no cell face, so those
//   edges belong to that cell alone; every cycle edge (a face segment) gets
//   one triangle from each of the face's two cells. Around a vertex, the fans
//   of the four cells sharing its lattice edge join through the four face
//   segments into a single disc.
// - Interior (tunnel) ambiguities, where the trilinear interpolant would
//   connect two separate polygons through the cell's interior, are resolved
//   by the face decisions alone: each cycle becomes its own disc. That can
//   differ from the trilinear topology inside one cell (at the scale of the
//   feature size) but never breaks closedness or orientation.

#include <array>
#include <cstdint>

namespace kerf::cell {

inline constexpr int kCorners = 8;
inline constexpr int kEdges = 12;
inline constexpr int kFaces = 6;

inline int edgeAxis(int e) { return e >> 2; }
/// The corner the edge starts from (its coordinate along the edge's axis is 0).
int edgeLowerCorner(int e);
inline int edgeUpperCorner(int e) { return edgeLowerCorner(e) | (1 << edgeAxis(e)); }
/// The two faces containing edge e, as a bit mask over faces.
std::uint8_t edgeFaceMask(int e);
/// The edge along `axis` whose lower corner is q (q's bit for `axis` clear).
int edgeFrom(int q, int axis);

/// Asymptotic decider for a face whose corners alternate in sign, corners in
/// the face's own axis order (u < v): v00 at (0, 0), v10 at (1, 0), v01 at
/// (0, 1), v11 at (1, 1). True when the two inside corners are connected
/// through the face (saddle value < 0). Deterministic in its four arguments.
bool insideConnected(double v00, double v10, double v01, double v11);

/// Closed directed polygons of one cell: cycles of cell edges, concatenated.
struct CellCycles {
    int count = 0;                      // cycles
    std::array<std::uint8_t, 4> size{}; // edges in each cycle (3 to 12)
    std::array<std::uint8_t, 12> edges{};
};

/// The polygons for a cell with the given inside corners (bit q set when
/// corner q is inside) and, for each ambiguous face f, bit f of
/// `connectInside` set when its inside corners are connected.
CellCycles cellCycles(std::uint8_t insideMask, std::uint8_t connectInside);

/// The polygons for a cell with the given corner values (index q).
CellCycles cellCycles(const double* values);

/// Bit mask of faces whose four corners do not all lie on one side.
std::uint8_t crossedFaces(std::uint8_t insideMask);

} // namespace kerf::cell

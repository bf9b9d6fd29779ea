#pragma once
// Flat faces before the simplification: the marching cubes cover a board's
// face with two triangles per cell, and the simplification then spends most
// of an export collapsing them one edge at a time (the side chair at 0.5 mm:
// 9.5 M lattice triangles, 4.7 M collapses, nearly all of them on planes).
// Here each block of cells whose triangles are one flat disk (every vertex
// with the same normal, all on one plane, one boundary loop, no vertex
// inside used by a triangle outside) is replaced, at once, by a fan from a
// point of that plane over the disk's boundary loop: the same region of the
// same plane, the same boundary (so the neighbouring blocks still meet it
// vertex for vertex), a fraction of the triangles. The fan is checked:
// every triangle of it turns the plane's way with a height, so it covers
// the disk once, without folds. Blocks that fail any check keep their
// triangles. Where fans meet, the marching cubes' vertices along the
// straight seam (one per cell) are then dropped from both loops, which
// still meet edge for edge.
//
// The surface is unchanged wherever a fan is made (the disk is a piece of
// one plane of the part, and so is the fan); the simplification afterwards
// meets fewer, longer triangles on the planes and the same ones elsewhere.
//
// Threads: the blocks are examined in the arena; the mesh is rewritten on
// the calling thread. Deterministic.

#include "kerf/mesher/Mesh.hpp"

#include <tbb/task_arena.h>

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace kerf::mesher {

struct PlanarFanStats {
    std::uint64_t blocks = 0;  // blocks replaced by a fan
    std::uint64_t removed = 0; // triangles fewer in all
    std::uint64_t seamVertices = 0; // vertices on straight seams between fans, dropped
};

/// Replaces the triangles of each flat block of `blockCells`^3 lattice cells
/// (cell edge `cellSize`, lattice points at origin + i * cellSize) by a fan;
/// a block that is not flat is tried again as eight halves, down to blocks
/// of `smallestCells`.
/// `normals[i]` is vertex i's unit normal (0 on a sharp feature), extended
/// for the fans' centres; unused vertices are dropped. `flatness` (mm): how
/// far from the block's plane a vertex may lie.
PlanarFanStats fanPlanarBlocks(Mesh& mesh, std::vector<glm::dvec3>& normals, const glm::dvec3& origin,
                               double cellSize, int blockCells, int smallestCells, double flatness,
                               tbb::task_arena& arena);

} // namespace kerf::mesher

#pragma once
// The other half of "within the tolerance": how far the part's surface lies
// from the mesh. The refinement samples the mesh's triangles against the
// exact field (the mesh's distance from the part); a mesh can pass that
// everywhere and still miss the part, where a triangle cuts a sharp edge
// off (its samples lie on the chamfer, nearer either face than the edge is
// to the chamfer: by the square root of two at a right angle, more at a
// sharper edge) or skips a corner. A newcomer's apron had its top edge cut
// off 0.058 mm while every triangle sample was within 0.049 mm.
//
// The part's side is sampled where the marching cubes found it: every
// vertex of the lattice mesh, a root of the exact field on a lattice edge,
// and every feature vertex, a point of a sharp edge or corner (fitted in
// its cell from the exact field; one that lies off the surface, a snap
// refused, is left out). At the feature size that is every cell the
// surface passes through, and every cell an edge does.
//
// Threads: the queries run in the arena. Deterministic (the worst sample
// is the first of the largest distance in the samples' order).

#include "kerf/evaluator/Tape.hpp"
#include "kerf/mesher/Mesh.hpp"

#include <tbb/task_arena.h>

#include <cstdint>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace kerf::mesher {

/// Points of the part's surface, stored relative to an origin (float: a
/// lattice mesh has millions; the rounding, 1e-7 of the part's size, is far
/// below any tolerance).
struct SurfaceSamples {
    glm::dvec3 origin{0.0};
    std::vector<glm::vec3> points;
    std::vector<std::uint8_t> onSharpEdge; // 1 for a point of a sharp edge or corner
};

/// The lattice mesh's vertices as samples of the part (`normals[i]`: vertex
/// i's unit normal, 0 on a sharp feature): all its roots, and its feature
/// vertices that lie within a twentieth of `tolerance` of the surface of
/// `tape` (|f| / |grad f|).
SurfaceSamples surfaceSamples(const Mesh& lattice, const std::vector<glm::dvec3>& normals, const Tape& tape,
                              double tolerance);

struct CoverageCheck {
    std::uint64_t samples = 0;
    /// The largest distance of a sample from the mesh (mm), and where.
    double worst = 0.0;
    glm::dvec3 worstAt{0.0};
    /// Samples further than the tolerance from every triangle.
    std::uint64_t samplesBeyond = 0;
};

/// How far the samples lie from `mesh` (world coordinates): each sample's
/// distance to its nearest triangle, counted beyond `tolerance` where no
/// triangle comes within it. Distances beyond the tolerance are exact;
/// within it, a sample only knows that it is within.
/// `beyond` (optional): the samples further than the tolerance, as
/// (distance, index), furthest first (then by index). `only` (optional):
/// the indices of the samples to measure, in increasing order (the others
/// are left out, of the count too).
CoverageCheck measureCoverage(const SurfaceSamples& samples, const Mesh& mesh, double tolerance,
                              tbb::task_arena& arena,
                              std::vector<std::pair<double, std::uint32_t>>* beyond = nullptr,
                              const std::vector<std::uint32_t>* only = nullptr);

} // namespace kerf::mesher

#pragma once
// Makes a mesh keep to a tolerance of the exact surface: every triangle is
// sampled on the exact field (the distance of a sample is |f| / |grad f|,
// SampleDistance.hpp: |f| where the field is an exact distance, which is
// most of a part, and more in blends, where |f| understates it), and a
// triangle with a sample further than the tolerance has an edge split, the
// new vertex placed on the surface, until every sample is within it.
//
// Samples per triangle: three on each edge (at 1/4, 1/2, 3/4) and four
// inside (the centroid and halfway from it to each vertex). The worst one
// chooses the edge to split: its own edge, or for an inside sample the
// longest edge.
//
// Where the new vertex goes: the edge's midpoint moved onto the surface by
// Newton steps along the gradient; on a sharp edge of the part (the edge's
// two triangles meet at more than 30 degrees and the surface on either side
// has its own normal) onto the crease instead: the point of the crease in
// the plane through the midpoint across the edge, from the two sides'
// tangent planes. A placement that would fold a triangle over leaves the
// vertex at the midpoint (the next round splits again, closer).
//
// Folds: a triangle whose normal points against the field's gradient at
// its centroid faces into the part (a flap turned over, or a fin of two
// thin triangles facing apart). No split mends it (a split's triangles turn
// their parent's way), so its edge is flipped first, where the flip turns
// the pair the surface's way and keeps the tolerance.
//
// The part's side (RefineSettings::partSamples): a mesh whose every sample
// keeps to the tolerance can still miss the part, where a triangle cuts a
// sharp edge off or a curved face bows out between a large triangle's
// samples. Points of the part the lattice found are measured against the
// mesh (SurfaceCoverage.hpp), and the edge nearest each point beyond the
// tolerance is split as any other.
//
// Threads: the sampling runs in the arena, per chunk of triangles; the
// splits are sequential (there are few). Deterministic.

#include "SurfaceCoverage.hpp"

#include "kerf/document/Progress.hpp"
#include "kerf/evaluator/Tape.hpp"
#include "kerf/mesher/Mesh.hpp"

#include <tbb/task_arena.h>

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

namespace kerf::mesher {

struct RefineStats {
    std::uint64_t splits = 0;
    std::uint64_t creaseSplits = 0;
    std::uint64_t samples = 0;
    int rounds = 0;
    /// The largest distance of a sample once done (mm, SampleDistance.hpp): at most the tolerance
    /// unless the round limit was reached.
    double worstSample = 0.0;
    glm::dvec3 worstAt{0.0}; // the centroid of the triangle with the worst sample (world mm)
    std::uint64_t trianglesOverTolerance = 0; // left over the tolerance at the round limit
    double areaOverTolerance = 0.0;           // mm^2: their area
    std::uint64_t unfolds = 0;                // flips that turned a folded triangle the surface's way
    std::uint64_t foldedTriangles = 0;        // left facing into the part (no flip helped)
    std::uint64_t retriangulations = 0;       // disks round a stuck triangle triangulated anew
    /// Stopped by a limit (rounds, triangles, patience) while triangles were
    /// still to split: the splits were not closing in on the surface.
    bool gaveUp = false;
    std::uint64_t partPointSplits = 0; // splits for points of the part the mesh missed (RefineSettings::partSamples)
};

struct RefineSettings {
    double tolerance = 0.0; // mm
    double minHeight = 0.0; // mm: no new triangle lower than this (EdgeCollapse.hpp)
    double clearance = 0.0; // mm: new triangles keep this far from others (TriangleClearance.hpp)
    int maxRounds = 40;
    /// Refinement stops once this many rounds have passed without fewer
    /// triangles over the tolerance than ever before. Splits that close in
    /// on the surface make them fewer within a few rounds; splits that dig
    /// at detail the cells missed (pin holes in cells coarser than the
    /// holes) make them more, round after round, up to the round limit:
    /// the door frame at 8 mm cells grew to 250 k triangles in 50 s.
    int patienceRounds = 10;
    /// The splits evaluate tapes simplified for cubes of this size (mm)
    /// around them (RegionTapes.hpp); 0: the whole part's tape.
    double regionSize = 0.0;
    /// A safety limit: refinement stops once the mesh has this many
    /// triangles (what is left over the tolerance is then reported).
    std::size_t maxTriangles = std::size_t(1) << 26;
    /// Flip upright, before any split, not only the triangles that face into
    /// the part but also those leaning more than 75 degrees from the
    /// surface's normal (MeshPart.cpp: a last attempt where triangles stay
    /// over the tolerance; as the rule throughout, it left a few more over
    /// on the turned leg's default export).
    bool unfoldLeaning = false;
    /// Where no edge of a triangle over the tolerance splits or flips (a
    /// new vertex there would turn a neighbour over), split one of its
    /// other edges, longest first: the triangle's parts are smaller, and
    /// their edges beyond the tolerance may then split (the stool's cross
    /// stretcher at 0.01 mm: needles 112 mm long and under a millimetre
    /// wide, 0.0126 mm off; the door frame's two small triangles across
    /// the crease where a rail's round meets a stile). MeshPart.cpp tries
    /// it last, on a copy, kept where it leaves fewer over: in every
    /// refinement it left the door frame 1,511 triangles over at 0.01 mm
    /// instead of 2.
    bool splitOtherEdges = false;
    /// Where no split or flip of a triangle over the tolerance helps (and
    /// before splitOtherEdges), the disk of triangles round it is
    /// triangulated anew on its own vertices (the turned leg's pommel at
    /// 0.01 mm, where two sharp edges meet at a tangent and the triangles
    /// reach across both).
    bool retriangulateStuck = false;
    /// False: no edge is split, only flips and retriangulations change the
    /// mesh (no new vertex: the refinement cannot dig at detail the cells
    /// missed, so MeshPart.cpp runs it even where the first refinement gave up).
    bool splitEdges = true;
    /// A split's new vertex may also go on the sharp edge between an end's
    /// sheet and a third sheet met between the ends (the edge's midpoint
    /// projected onto the surface faces apart from both ends' normals):
    /// where a square pommel's side touches the turning's cylinder at a
    /// tangent, the pommel's underside between them is a sliver narrower
    /// than a cell, the cells' triangles reach across it from the side to
    /// the cylinder (whose normals are nearly the same), and the split's
    /// vertex, projected from the midpoint, lands beside the two sharp
    /// edges and never on them. MeshPart.cpp runs it as a second
    /// refinement where the first leaves triangles over.
    bool splitsOnThirdSheet = false;
    /// Points of the part's surface (SurfaceCoverage.hpp) that the mesh
    /// must come within the tolerance of. Once the triangles' samples keep
    /// to it (or the splits for them are stuck), each point further from
    /// the mesh, furthest first, has the edge of its nearest triangle
    /// nearest to it split, the new vertex on the surface as for any split
    /// (on the crease where the edge runs along a sharp edge of the part);
    /// then the triangles' samples again, and another pass, up to this
    /// many. A pass measures the points the pass before found beyond, and
    /// every point once those keep to it. Null: none.
    const SurfaceSamples* partSamples = nullptr;
    int coveragePasses = 32;
    /// The points of partSamples beyond the tolerance of the mesh as given
    /// (measureCoverage's `beyond`), where the caller has measured them: the
    /// first pass takes them instead of measuring again, if no split or
    /// flip came before it. Null: the first pass measures.
    const std::vector<std::pair<double, std::uint32_t>>* partSamplesBeyond = nullptr;
};

/// Refines `mesh` (world coordinates, outward triangles), the surface of
/// `tape`, whose vertex i has unit normal normals[i] (0 on a sharp feature;
/// extended for new vertices), until every sample lies within the tolerance
/// of the surface, or a limit is reached. Returns false when cancelled (the
/// mesh is then valid but unfinished).
bool refineToTolerance(Mesh& mesh, std::vector<glm::dvec3>& normals, const Tape& tape, const RefineSettings& settings,
                       tbb::task_arena& arena, RefineStats& stats, const Progress& work = {});

/// A mesh's triangles sampled as the refinement samples them: the worst
/// sample's distance, the centroid of the triangle it is on, and how many triangles have
/// a sample beyond the tolerance. What the simplification after the
/// refinement leaves is measured with it, so that what is reported is the
/// mesh written.
struct ToleranceCheck {
    double worstSample = 0.0;
    glm::dvec3 worstAt{0.0};
    std::uint64_t trianglesOverTolerance = 0;
    double areaOverTolerance = 0.0; // mm^2
    std::uint64_t foldedTriangles = 0; // triangles facing into the part at their centroid
};
ToleranceCheck checkTolerance(const Mesh& mesh, const Tape& tape, double tolerance, tbb::task_arena& arena);

} // namespace kerf::mesher

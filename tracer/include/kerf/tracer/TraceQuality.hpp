#pragma once
// The tracers' quality switch. Voxels: the hit is where the trilinear
// interpolation of a populated voxel's corner distances crosses zero, with
// interpolated corner normals (the fast path). Exact: the hybrid refinement
// of ../shared/seeds/hierarchical-evaluator-and-brick-renderer.md ("The
// hybrid ray marcher"): near the surface (in and around populated voxels)
// the ray is marched on the exact field of the tile's simplified tape, and
// the normal and feature come from that field, which keeps sharp edges and
// CSG intersections sharp (tracer/include/kerf/tracer/ReferenceTracer.hpp).
// Exact refines only the rays whose voxel hit the exact field does not
// confirm (VoxelHitCheck.hpp): the same picture for a fraction of the
// cost. ExactEverywhere refines every ray; it is the definition Exact is
// measured against (docs/benchmarks.md).

#include <optional>
#include <string_view>

namespace kerf {

enum class TraceQuality : unsigned { Voxels = 0, Exact = 1, ExactEverywhere = 2 };

/// "voxels", "exact" or "exact-everywhere".
std::string_view traceQualityName(TraceQuality q);
/// The quality named `name` ("voxels", "exact", "exact-everywhere"), or nothing.
std::optional<TraceQuality> parseTraceQuality(std::string_view name);

} // namespace kerf

// Measures any mesh file against a Kerf part's exact surface, the same way
// for Kerf's own exports and for other programs' (issue 13's comparison
// with Manifold): the file read as a slicer reads it (STL welded by float32
// position, 3MF by index: the test suite's reader), then the distance of
// its triangles to the exact surface (SurfaceDistance.hpp: samples at the
// vertices, edge midpoints and centroids), its closedness and crossings,
// its volume, and how many triangles face across the surface (their normal
// more than 75 or 90 degrees from the field's gradient at their centroid: a
// fold, which a reader's checks for closedness do not see).
//
//   build/bench/kerf_mesh_distance FILE.kerf MESH.stl|MESH.3mf
//
// Prints one JSON object.

#include "kerf/accuracy/SurfaceDistance.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/SelfIntersections.hpp"
#include "support/MeshFileReader.hpp"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <exception>
#include <iostream>

namespace {
struct Facing {
    std::uint64_t across = 0;   // normal more than 90 degrees from the gradient
    std::uint64_t steep = 0;    // more than 75 degrees
    double worstCosine = 1.0;
    glm::dvec3 worstAt{0.0};
};

Facing facing(const kerf::Mesh& mesh, const kerf::Tape& tape)
{
    constexpr double kSteepCosine = 0.25881904510252074; // 75 degrees
    kerf::GradientEvaluator<double> field;
    Facing f;
    for (const std::array<std::uint32_t, 3>& t : mesh.triangles) {
        const glm::dvec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const glm::dvec3 centroid = (a + b + c) / 3.0;
        const kerf::Dual<double> g = field.evaluate(tape, centroid.x, centroid.y, centroid.z);
        const glm::dvec3 grad(g.d[0], g.d[1], g.d[2]);
        if (!(glm::length(n) > 0.0) || !(glm::length(grad) > 0.0)) continue;
        const double cosine = glm::dot(n, grad) / (glm::length(n) * glm::length(grad));
        if (cosine < 0.0) ++f.across;
        if (cosine < kSteepCosine) ++f.steep;
        if (cosine < f.worstCosine) {
            f.worstCosine = cosine;
            f.worstAt = centroid;
        }
    }
    return f;
}
} // namespace

int main(int argc, char** argv)
{
    if (argc != 3) {
        std::fprintf(stderr, "usage: kerf_mesh_distance FILE.kerf MESH.stl|MESH.3mf\n");
        return 2;
    }
    try {
        const kerf::Document doc = kerf::Document::load(argv[1]);
        const kerf::Tape tape = kerf::compileTape(doc);
        const kerf::Mesh mesh = kerf::test::readMeshFile(argv[2]);
        const kerf::MeshReport report = kerf::checkMesh(mesh);
        const kerf::SurfaceDistance d = kerf::measureSurfaceDistance(mesh, tape);
        nlohmann::json j;
        j["file"] = argv[2];
        j["triangles"] = report.triangles;
        j["watertight"] = report.watertight();
        j["self_intersections"] = kerf::findSelfIntersections(mesh, 0).pairs;
        if (const auto g = report.genus()) j["genus"] = *g;
        j["components"] = report.components;
        j["volume_mm3"] = report.volume;
        j["distance_max_mm"] = d.max;
        j["distance_max_at_mm"] = {d.maxAt.x, d.maxAt.y, d.maxAt.z};
        j["distance_mean_mm"] = d.mean;
        j["distance_max_lower_bound_mm"] = d.maxLowerBound;
        j["unresolved_samples"] = d.unresolved;
        const Facing f = facing(mesh, tape);
        j["triangles_facing_across"] = f.across;
        j["triangles_facing_over_75_degrees"] = f.steep;
        j["worst_facing_cosine"] = f.worstCosine;
        j["worst_facing_at_mm"] = {f.worstAt.x, f.worstAt.y, f.worstAt.z};
        std::cout << j.dump() << "\n";
    } catch (const std::exception& e) {
        std::fprintf(stderr, "kerf_mesh_distance: %s\n", e.what());
        return 1;
    }
    return 0;
}

// Measures any mesh file against a Kerf part's exact surface, the same way
// for Kerf's own exports and for other programs' (issue 13's comparison
// with Manifold): the file read as a slicer reads it (STL welded by float32
// position, 3MF by index: the test suite's reader), then the distance of
// its triangles to the exact surface (SurfaceDistance.hpp: samples at the
// vertices, edge midpoints and centroids), its closedness and crossings,
// and its volume.
//
//   build/bench/kerf_mesh_distance FILE.kerf MESH.stl|MESH.3mf
//
// Prints one JSON object.

#include "kerf/accuracy/SurfaceDistance.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/SelfIntersections.hpp"
#include "support/MeshFileReader.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <exception>
#include <iostream>

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
        std::cout << j.dump() << "\n";
    } catch (const std::exception& e) {
        std::fprintf(stderr, "kerf_mesh_distance: %s\n", e.what());
        return 1;
    }
    return 0;
}

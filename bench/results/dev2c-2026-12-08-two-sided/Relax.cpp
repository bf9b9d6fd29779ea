// Experiment (not for the tree): smooth-sheet vertices of an exported mesh
// moved along the field's gradient so that each one's triangles' samples
// deviate to both sides of the surface (minimax), then written as binary STL.
#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "support/MeshFileReader.hpp"
#include <glm/glm.hpp>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

using glm::dvec3;
int main(int argc, char** argv)
{
    if (argc < 4) { std::fprintf(stderr, "usage: relax DOC IN.stl OUT.stl [sweeps] [maxmove]\n"); return 2; }
    const kerf::Document doc = kerf::Document::load(argv[1]);
    const kerf::Tape tape = kerf::compileTape(doc);
    kerf::Mesh mesh = kerf::test::readMeshFile(argv[2]);
    const int sweeps = argc > 4 ? std::atoi(argv[4]) : 6;
    const double maxMove = argc > 5 ? std::atof(argv[5]) : 0.02;
    const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();
    // samples per triangle: barycentric (w0,w1,w2)
    std::vector<dvec3> bary;
    const int N = 4; // subdivisions per edge
    for (int i = 0; i <= N; ++i) for (int j = 0; j <= N - i; ++j) bary.push_back(dvec3(i, j, N - i - j) / double(N));
    const std::size_t S = bary.size();
    std::vector<std::vector<std::uint32_t>> vt(nv);
    for (std::uint32_t t = 0; t < nt; ++t) for (auto v : mesh.triangles[t]) vt[v].push_back(t);
    auto value = [&](const dvec3& p) { thread_local kerf::PointEvaluator<double> e; return e.evaluate(tape, p.x, p.y, p.z); };
    auto samplePos = [&](std::uint32_t t, std::size_t s) {
        const auto& tr = mesh.triangles[t];
        return bary[s].x * mesh.vertices[tr[0]] + bary[s].y * mesh.vertices[tr[1]] + bary[s].z * mesh.vertices[tr[2]];
    };
    std::vector<double> f(nt * S);
    auto evalTri = [&](std::uint32_t t) { for (std::size_t s = 0; s < S; ++s) f[t * S + s] = value(samplePos(t, s)); };
    tbb::parallel_for(std::uint32_t(0), std::uint32_t(nt), [&](std::uint32_t t) { evalTri(t); });
    auto report = [&](const char* what) {
        double m = 0; for (double x : f) m = std::max(m, std::abs(x));
        std::size_t over = 0; for (std::uint32_t t = 0; t < nt; ++t) { double w = 0; for (std::size_t s = 0; s < S; ++s) w = std::max(w, std::abs(f[t*S+s])); if (w > 0.01) ++over; }
        std::fprintf(stderr, "%s: max |f| %.5f, triangles with a sample over 0.01: %zu\n", what, m, over);
    };
    report("before");
    {
        std::size_t one = 0, two = 0, big = 0; std::vector<std::size_t> hist(6);
        for (std::uint32_t t = 0; t < nt; ++t) {
            double lo = 1e9, hi = -1e9; for (std::size_t s = 0; s < S; ++s) { lo = std::min(lo, f[t*S+s]); hi = std::max(hi, f[t*S+s]); }
            const double w = std::max(-lo, hi);
            hist[std::min<std::size_t>(5, std::size_t(w / 0.004))]++;
            if (w <= 0.01) continue;
            ++big;
            if (std::min(-lo, hi) < 0.2 * w) ++one; else ++two;
        }
        std::fprintf(stderr, "over 0.01: %zu, one-sided %zu, two-sided %zu; hist by 0.004:", big, one, two);
        for (auto h : hist) std::fprintf(stderr, " %zu", h);
        std::fprintf(stderr, "\n");
    }
    // movable: gradient defined, every adjacent triangle normal within 30 deg of it
    std::vector<dvec3> normal(nv, dvec3(0));
    kerf::GradientEvaluator<double> ge;
    std::size_t movable = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        const auto g = ge.evaluate(tape, mesh.vertices[v].x, mesh.vertices[v].y, mesh.vertices[v].z);
        dvec3 n(g.d[0], g.d[1], g.d[2]);
        if (!(glm::length(n) > 0.5)) continue;
        n = glm::normalize(n);
        bool ok = true;
        for (auto t : vt[v]) {
            const auto& tr = mesh.triangles[t];
            dvec3 tn = glm::cross(mesh.vertices[tr[1]] - mesh.vertices[tr[0]], mesh.vertices[tr[2]] - mesh.vertices[tr[0]]);
            if (!(glm::length(tn) > 0) || glm::dot(glm::normalize(tn), n) < std::cos(0.5236)) { ok = false; break; }
        }
        if (ok) { normal[v] = n; ++movable; }
    }
    std::fprintf(stderr, "vertices %zu, movable %zu\n", nv, movable);
    std::vector<dvec3> origin = mesh.vertices;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        for (std::size_t v = 0; v < nv; ++v) {
            if (normal[v] == dvec3(0)) continue;
            // samples of v's triangles and their weights for v
            std::vector<std::pair<double, double>> fw; // (f, w)
            for (auto t : vt[v]) {
                const auto& tr = mesh.triangles[t];
                const int k = tr[0] == v ? 0 : tr[1] == v ? 1 : 2;
                for (std::size_t s = 0; s < S; ++s) fw.push_back({f[t * S + s], bary[s][k]});
            }
            const double cur = glm::dot(mesh.vertices[v] - origin[v], normal[v]);
            auto g = [&](double d) { double m = 0; for (auto& [fi, wi] : fw) m = std::max(m, std::abs(fi + wi * d)); return m; };
            double lo = -maxMove - cur, hi = maxMove - cur;
            for (int it = 0; it < 60; ++it) { double a = lo + (hi - lo) / 3, b = hi - (hi - lo) / 3; if (g(a) < g(b)) hi = b; else lo = a; }
            const double d = 0.5 * (lo + hi);
            if (!(g(d) < g(0.0) - 1e-9)) continue;
            mesh.vertices[v] += d * normal[v];
            for (auto t : vt[v]) evalTri(t);
        }
        char buf[64]; std::snprintf(buf, sizeof buf, "sweep %d", sweep + 1); report(buf);
    }
    std::ofstream out(argv[3], std::ios::binary);
    char header[80] = {}; out.write(header, 80);
    std::uint32_t count = std::uint32_t(nt); out.write(reinterpret_cast<char*>(&count), 4);
    for (auto& tr : mesh.triangles) {
        float rec[12] = {}; 
        for (int k = 0; k < 3; ++k) { rec[3 + 3*k] = float(mesh.vertices[tr[k]].x); rec[4 + 3*k] = float(mesh.vertices[tr[k]].y); rec[5 + 3*k] = float(mesh.vertices[tr[k]].z); }
        out.write(reinterpret_cast<char*>(rec), 48); std::uint16_t attr = 0; out.write(reinterpret_cast<char*>(&attr), 2);
    }
    return 0;
}

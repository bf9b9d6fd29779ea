// A Kerf document's compiled tape as JSON, for evaluators outside C++:
// issue 13's comparison on blended parts hands Kerf's exact field to
// Manifold's level set (bench/manifold/levelset.mjs), through a JavaScript
// port of the double-precision point evaluator (bench/manifold/tape.mjs).
// The port is only as good as its agreement with this program's samples,
// which are the values of kerf::PointEvaluator<double> itself.
//
//   build/bench/kerf_tape_json FILE.kerf [--samples N] [--seed S] > TAPE.json
//
// The JSON holds what the double path reads, nothing it does not:
//   origin        the tape's origin; points are measured from it (world
//                 points minus origin; a document's tape has origin 0)
//   bounds        the part's world bounds (partBounds; null where infinite)
//   max_stack     the deepest stack the tape needs
//   code          per instruction: op (Tape.hpp's Op, by name), span,
//                 right_span, shape (primitives), k (blend, offset, shell)
//   shapes        per shape: kind (ShapeKinds.h, by name and number),
//                 param (ShapeInstance::param, Primitives.hpp's layout),
//                 frame (m row-major 3x3, then t: local = m p + t),
//                 polygon (extrude and revolve: the profile's points)
//   samples       with --samples N: [x, y, z, field] rows (tape-relative
//                 points), half uniform over the bounds, half near the
//                 surface (uniform points moved onto it by Newton steps
//                 along the gradient, then jittered by 1 um to 2 mm), so
//                 that blends, edges and polygon crossings are all hit
//
// Doubles are written shortest round-trip (nlohmann), so a reader that
// parses them as IEEE doubles gets the same bits.

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>

namespace {

const char* opName(kerf::Op op)
{
    switch (op) {
    case kerf::Op::Primitive: return "primitive";
    case kerf::Op::Min: return "min";
    case kerf::Op::Max: return "max";
    case kerf::Op::SmoothMin: return "smooth_min";
    case kerf::Op::SmoothMax: return "smooth_max";
    case kerf::Op::Negate: return "negate";
    case kerf::Op::Offset: return "offset";
    case kerf::Op::Shell: return "shell";
    }
    return "unknown";
}

const char* kindName(kerf::ShapeKind kind)
{
    switch (kind) {
    case kerf::ShapeKind::Box: return "box";
    case kerf::ShapeKind::Sphere: return "sphere";
    case kerf::ShapeKind::Cylinder: return "cylinder";
    case kerf::ShapeKind::Cone: return "cone";
    case kerf::ShapeKind::Torus: return "torus";
    case kerf::ShapeKind::Extrude: return "extrude";
    case kerf::ShapeKind::Halfspace: return "halfspace";
    case kerf::ShapeKind::Revolve: return "revolve";
    }
    return "unknown";
}

// JSON has no infinity: an unbounded side is null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json vec(const glm::dvec3& v) { return {number(v.x), number(v.y), number(v.z)}; }

} // namespace

int main(int argc, char** argv)
{
    std::string file;
    long samples = 0;
    unsigned long long seed = 13;
    bool ok = true;
    for (int i = 1; i < argc && ok; ++i) {
        const std::string a = argv[i];
        if (a == "--samples" && i + 1 < argc)
            samples = std::atol(argv[++i]);
        else if (a == "--seed" && i + 1 < argc)
            seed = std::strtoull(argv[++i], nullptr, 10);
        else if (file.empty() && a.rfind("--", 0) != 0)
            file = a;
        else
            ok = false;
    }
    if (!ok || file.empty() || samples < 0) {
        std::fprintf(stderr, "usage: kerf_tape_json FILE.kerf [--samples N] [--seed S]\n");
        return 2;
    }
    try {
        const kerf::Document doc = kerf::Document::load(file);
        const kerf::Tape tape = kerf::compileTape(doc);
        nlohmann::json j;
        j["file"] = file;
        j["origin"] = vec(tape.origin());
        if (tape.bounds().isEmpty())
            j["bounds"] = nullptr;
        else
            j["bounds"] = {{"min", vec(tape.bounds().min)}, {"max", vec(tape.bounds().max)}};
        j["max_stack"] = tape.maxStack();
        auto& code = j["code"] = nlohmann::json::array();
        for (const kerf::Instruction& ins : tape.code()) {
            nlohmann::json c;
            c["op"] = opName(ins.op);
            c["span"] = ins.span;
            c["right_span"] = ins.rightSpan;
            c["shape"] = ins.shape;
            c["k"] = ins.k;
            code.push_back(c);
        }
        auto& shapes = j["shapes"] = nlohmann::json::array();
        for (const kerf::ShapeInstance& s : tape.shapes()) {
            nlohmann::json o;
            o["kind"] = kindName(s.kind);
            o["kind_number"] = static_cast<unsigned>(s.kind);
            o["feature"] = tape.features()[s.feature].nodeId;
            o["param"] = s.param;
            o["frame"] = s.frame;
            if (s.polygon) {
                auto& pts = o["polygon"] = nlohmann::json::array();
                for (const auto& p : s.polygon->points) pts.push_back({p.x, p.y});
            }
            shapes.push_back(o);
        }

        if (samples > 0) {
            if (tape.empty() || tape.bounds().isEmpty() || !tape.bounds().isBounded())
                throw std::runtime_error("samples need a non-empty, bounded part");
            const glm::dvec3 lo = tape.bounds().min - tape.origin(), hi = tape.bounds().max - tape.origin();
            std::mt19937_64 rng(seed);
            std::uniform_real_distribution<double> unit(0.0, 1.0);
            const auto uniformPoint = [&] {
                return glm::dvec3(lo.x + unit(rng) * (hi.x - lo.x), lo.y + unit(rng) * (hi.y - lo.y),
                                  lo.z + unit(rng) * (hi.z - lo.z));
            };
            kerf::PointEvaluator<double> points;
            kerf::GradientEvaluator<double> gradients;
            auto& rows = j["samples"] = nlohmann::json::array();
            const auto emit = [&](const glm::dvec3& p) {
                rows.push_back({p.x, p.y, p.z, points.evaluate(tape, p.x, p.y, p.z)});
            };
            const long uniform = samples / 2;
            for (long i = 0; i < uniform; ++i) emit(uniformPoint());
            for (long i = uniform; i < samples; ++i) {
                glm::dvec3 p = uniformPoint();
                for (int step = 0; step < 8; ++step) {
                    const kerf::Dual<double> g = gradients.evaluate(tape, p.x, p.y, p.z);
                    const glm::dvec3 n(g.d[0], g.d[1], g.d[2]);
                    const double n2 = glm::dot(n, n);
                    if (!(n2 > 1e-12) || !std::isfinite(g.v)) break;
                    p -= (g.v / n2) * n;
                    if (std::abs(g.v) < 1e-9) break;
                }
                // Jitter from 1 um to 2 mm (log-uniform) in a random direction.
                const double r = 1e-3 * std::pow(2000.0, unit(rng));
                glm::dvec3 d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
                const double len = glm::length(d);
                if (len > 0) d *= r / len;
                emit(p + d);
            }
        }
        std::cout << j.dump() << "\n";
    } catch (const std::exception& e) {
        std::fprintf(stderr, "kerf_tape_json: %s\n", e.what());
        return 1;
    }
    return 0;
}

// kerf_trace_preview: renders a Kerf document to a PNG with the CPU reference
// voxel tracer (or, with --exact, by sphere tracing the exact field), for
// looking at what the viewport will show without a GPU.
//
//   kerf_trace_preview FILE.kerf OUT.png [--view iso] [--size 800x600]
//       [--feature-size MM] [--exact] [--ortho] [--threads N] [--repeat N]
//       [--diff DIFF.png] [--diff-epsilon MM] [--target X,Y,Z] [--zoom F] [--quality voxels|exact|exact-everywhere]
//
// --quality exact turns on the hybrid refinement where the voxels need it,
// exact-everywhere on every ray (kerf/tracer/TraceQuality.hpp).
// --target looks at that world point (mm) instead of the part's centre, from
// the same direction; --zoom F brings the camera F times closer (perspective)
// or shows an F times smaller field (orthographic), for close-ups.
//
// --diff also traces the exact field, prints how the two images agree and
// writes a map of the differences: red where only the voxels hit, blue
// where only the exact field does, yellow where the depths differ by more
// than a voxel, magenta where the normals differ by more than 10 degrees,
// grey where they agree.
//
// Prints the grid, the voxelization and the tracing times on stdout. Exit
// status 0 on success, 2 on bad arguments or a document that does not load,
// 1 on any other failure.

#include "kerf/document/DocumentError.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/tracer/Image.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace {

struct Options {
    std::string input, output;
    std::string view = "iso";
    int width = 800, height = 600;
    std::optional<double> featureSize;
    bool exact = false;
    bool ortho = false;
    int threads = 0;
    int repeat = 1;
    std::string diff;
    std::optional<glm::dvec3> target;
    double zoom = 1.0;
    kerf::TraceQuality quality = kerf::TraceQuality::Voxels;
    double diffEpsilon = 1e-3; // the exact tracer's hit distance for --diff (mm)
    int refineLanes = KERF_EDGE_REFINE_LANES; // Exact's lanes a ray (a GPU's: 32 on NVIDIA)
};

struct UsageError {
    std::string message;
};

void usage(std::ostream& out)
{
    out << "usage: kerf_trace_preview FILE.kerf OUT.png [--view iso|front|back|left|right|top|bottom]\n"
           "                          [--size WxH] [--feature-size MM] [--exact] [--ortho]\n"
           "                          [--threads N] [--repeat N] [--diff DIFF.png] [--diff-epsilon MM]\n"
           "                          [--target X,Y,Z] [--zoom F] [--quality voxels|exact|exact-everywhere]\n"
           "                          [--refine-lanes 2..32]\n";
}

double parseNumber(const std::string& flag, const std::string& text)
{
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v)) throw UsageError{flag + ": not a number: " + text};
    return v;
}

Options parse(int argc, char** argv)
{
    Options o;
    std::vector<std::string> positional;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError{a + " needs a value"};
            return argv[++i];
        };
        if (a == "--view") {
            o.view = value();
        } else if (a == "--size") {
            const std::string s = value();
            const auto x = s.find('x');
            if (x == std::string::npos) throw UsageError{"--size: expected WxH, got " + s};
            o.width = int(parseNumber("--size", s.substr(0, x)));
            o.height = int(parseNumber("--size", s.substr(x + 1)));
            if (o.width <= 0 || o.height <= 0 || o.width > 16384 || o.height > 16384)
                throw UsageError{"--size: out of range: " + s};
        } else if (a == "--feature-size") {
            o.featureSize = parseNumber(a, value());
            if (!(*o.featureSize > 0.0)) throw UsageError{"--feature-size must be positive"};
        } else if (a == "--threads") {
            o.threads = std::max(0, int(parseNumber(a, value())));
        } else if (a == "--repeat") {
            o.repeat = std::max(1, int(parseNumber(a, value())));
        } else if (a == "--target") {
            const std::string t = value();
            const auto c1 = t.find(','), c2 = t.find(',', c1 == std::string::npos ? c1 : c1 + 1);
            if (c1 == std::string::npos || c2 == std::string::npos) throw UsageError{"--target: expected X,Y,Z"};
            o.target = glm::dvec3(parseNumber(a, t.substr(0, c1)), parseNumber(a, t.substr(c1 + 1, c2 - c1 - 1)),
                                  parseNumber(a, t.substr(c2 + 1)));
        } else if (a == "--zoom") {
            o.zoom = parseNumber(a, value());
            if (!(o.zoom > 0.0)) throw UsageError{"--zoom must be positive"};
        } else if (a == "--quality") {
            const std::string q = value();
            const auto quality = kerf::parseTraceQuality(q);
            if (!quality) throw UsageError{"--quality must be voxels, exact or exact-everywhere, not " + q};
            o.quality = *quality;
        } else if (a == "--refine-lanes") {
            o.refineLanes = int(parseNumber(a, value()));
            if (o.refineLanes < 2 || o.refineLanes > KERF_EDGE_REFINE_MAX_LANES)
                throw UsageError{"--refine-lanes must be 2 to " + std::to_string(KERF_EDGE_REFINE_MAX_LANES)};
        } else if (a == "--diff") {
            o.diff = value();
        } else if (a == "--diff-epsilon") {
            o.diffEpsilon = parseNumber(a, value());
            if (!(o.diffEpsilon > 0.0)) throw UsageError{"--diff-epsilon must be a positive length in mm"};
        } else if (a == "--exact") {
            o.exact = true;
        } else if (a == "--ortho") {
            o.ortho = true;
        } else if (a == "-h" || a == "--help") {
            usage(std::cout);
            std::exit(0);
        } else if (a.starts_with("--")) {
            throw UsageError{"unknown option " + a};
        } else {
            positional.push_back(a);
        }
    }
    if (positional.size() != 2) throw UsageError{"expected FILE.kerf and OUT.png"};
    if (o.exact && !o.diff.empty()) throw UsageError{"--diff compares the voxel tracer with the exact one: no --exact"};
    o.input = positional[0];
    o.output = positional[1];
    return o;
}

// The voxelizer's default when a document names no feature size: about a
// thousandth of the part's largest extent, rounded down to 1, 2 or 5 times a
// power of ten.

// Compares the voxel image with the exact one; prints the agreement and
// writes the map of differences.
void writeDiff(const kerf::TraceImage& voxel, const kerf::TraceImage& exact, double voxelSize, const std::string& path)
{
    kerf::RgbaImage out;
    out.width = voxel.width;
    out.height = voxel.height;
    out.pixels.assign(voxel.depth.size() * 4, 255);
    long onlyVoxel = 0, onlyExact = 0, both = 0, depthOff = 0, normalOff = 0;
    std::vector<double> depthErrors, angleErrors; // of pixels hit both ways: mm, degrees
    const float cos10 = std::cos(10.0f * 3.14159265f / 180.0f);
    for (std::size_t i = 0; i < voxel.depth.size(); ++i) {
        const bool hv = voxel.hit(i), he = exact.hit(i);
        std::uint8_t* p = &out.pixels[4 * i];
        auto set = [&](int r, int g, int b) {
            p[0] = std::uint8_t(r);
            p[1] = std::uint8_t(g);
            p[2] = std::uint8_t(b);
        };
        if (hv && !he) {
            ++onlyVoxel;
            set(230, 30, 30);
        } else if (he && !hv) {
            ++onlyExact;
            set(30, 60, 230);
        } else if (!hv) {
            set(255, 255, 255);
        } else {
            ++both;
            const float dn = voxel.normal[i].x * exact.normal[i].x + voxel.normal[i].y * exact.normal[i].y +
                             voxel.normal[i].z * exact.normal[i].z;
            depthErrors.push_back(std::abs(double(voxel.depth[i]) - double(exact.depth[i])));
            angleErrors.push_back(std::acos(std::clamp(double(dn), -1.0, 1.0)) * 180.0 / 3.14159265358979);
            if (std::abs(double(voxel.depth[i]) - double(exact.depth[i])) > voxelSize) {
                ++depthOff;
                set(240, 200, 0);
            } else if (dn < cos10) {
                ++normalOff;
                set(200, 0, 200);
            } else {
                const int g = int(120 + 100 * std::max(0.0f, exact.normal[i].z));
                set(g, g, g);
            }
        }
    }
    const double px = double(voxel.depth.size());
    std::printf("diff: %ld hit only by voxels, %ld only exactly (mask agrees on %.3f%% of pixels); of %ld hit both, "
                "%.3f%% depth off by > %.3g mm, %.3f%% normals off by > 10 degrees\n",
                onlyVoxel, onlyExact, 100.0 * (1.0 - double(onlyVoxel + onlyExact) / px), both,
                both ? 100.0 * double(depthOff) / double(both) : 0.0, voxelSize,
                both ? 100.0 * double(normalOff) / double(both) : 0.0);
    auto quantile = [](std::vector<double> v, double q) {
        if (v.empty()) return 0.0;
        std::sort(v.begin(), v.end());
        return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
    };
    double depthSum = 0.0, angleSum = 0.0;
    for (double d : depthErrors) depthSum += d;
    for (double a : angleErrors) angleSum += a;
    const double n = std::max<double>(1.0, double(depthErrors.size()));
    std::printf("depth error mm: mean %.4g, median %.4g, p99 %.4g; normal error degrees: mean %.3g, median %.3g, "
                "p99 %.3g\n",
                depthSum / n, quantile(depthErrors, 0.5), quantile(depthErrors, 0.99), angleSum / n,
                quantile(angleErrors, 0.5), quantile(angleErrors, 0.99));
    kerf::writePng(path, out);
}

double msSince(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

int run(const Options& o)
{
    using Clock = std::chrono::steady_clock;
    const kerf::Document doc = kerf::Document::load(o.input);
    const kerf::Tape tape = kerf::compileTape(doc);
    if (tape.empty() || !tape.bounds().isBounded()) {
        std::cerr << o.input << ": the part is empty or unbounded; nothing to frame\n";
        return 1;
    }
    kerf::Camera camera =
        kerf::Camera::standardView(tape.bounds(), o.view, o.width, o.height,
                                   o.ortho ? kerf::Projection::Orthographic : kerf::Projection::Perspective);
    if (o.target || o.zoom != 1.0) {
        // The standard view's direction and up, aimed at the target, closer.
        const glm::dvec3 centre = tape.bounds().center();
        const glm::dvec3 target = o.target.value_or(centre);
        const double distance = glm::dot(centre - camera.eye(), camera.forward());
        if (camera.projection() == kerf::Projection::Perspective)
            camera = kerf::Camera::perspective(target - camera.forward() * (distance / o.zoom), target, camera.up(),
                                               camera.fovYDegrees(), o.width, o.height);
        else
            camera = kerf::Camera::orthographic(target - camera.forward() * distance, target, camera.up(),
                                                camera.orthoHeight() / o.zoom, o.width, o.height);
    }
    kerf::TraceImage image;
    if (o.exact) {
        const double epsilon = 1e-3;
        double best = 1e300;
        for (int r = 0; r < o.repeat; ++r) {
            const auto t0 = Clock::now();
            image = kerf::traceExact(tape, camera, epsilon, o.threads);
            best = std::min(best, msSince(t0));
        }
        std::printf("exact trace %dx%d: %.1f ms (best of %d)\n", o.width, o.height, best, o.repeat);
    } else {
        const double featureSize =
            o.featureSize.value_or(doc.settings.featureSize.value_or(defaultFeatureSize(tape.bounds())));
        const kerf::GridLayout layout = kerf::GridLayout::choose(tape.bounds(), featureSize);
        if (!layout.note.empty()) std::printf("note: %s\n", layout.note.c_str());
        const auto t0 = Clock::now();
        kerf::VoxelizeOptions vo;
        vo.threads = o.threads;
        const kerf::VoxelSnapshot snapshot = kerf::voxelize(tape, layout, vo);
        const kerf::FlatVoxelBuffers buffers = kerf::FlatVoxelBuffers::flatten(snapshot);
        std::printf("grid %dx%dx%d tiles of %.3f mm, %d levels, voxel %.4f mm; %zu surface tiles, %zu voxels, "
                    "%.1f MB (of which exact tapes %.3f MB); voxelized in %.0f ms\n",
                    layout.dims.x, layout.dims.y, layout.dims.z, layout.tileSize, layout.levels, layout.voxelSize,
                    buffers.entries.size(), buffers.leafData.size(), double(buffers.bytes()) / 1e6,
                    double(buffers.tapes.size() * sizeof(std::uint32_t)) / 1e6, msSince(t0));
        double best = 1e300;
        for (int r = 0; r < o.repeat; ++r) {
            const auto t1 = Clock::now();
            image = kerf::traceVoxels(buffers, camera, o.threads, {}, o.quality, {}, o.refineLanes);
            best = std::min(best, msSince(t1));
        }
        std::printf("voxel trace (quality %s) %dx%d: %.1f ms (best of %d)\n",
                    std::string(kerf::traceQualityName(o.quality)).c_str(), o.width, o.height, best, o.repeat);
        if (o.quality != kerf::TraceQuality::Voxels) {
            // The refinement's cost in exact tape evaluations (one gradient counts as one),
            // and how many rays it traced (Exact: those whose voxel hit the check did not confirm).
            std::size_t evaluations = 0, hits = 0, refined = 0, rays = 0;
            std::vector<std::uint32_t> perRefinedRay, inARow;
            for (int y = 0; y < o.height; ++y)
                for (int x = 0; x < o.width; ++x) {
                    const kerf::RayHit h = kerf::traceRay(buffers, camera.ray(x, y), {}, o.quality, o.refineLanes);
                    evaluations += h.evaluations;
                    hits += h.hit();
                    refined += h.hit() && h.evaluations > 0;
                    rays += o.quality == kerf::TraceQuality::ExactEverywhere || h.refined;
                    if (o.quality == kerf::TraceQuality::ExactEverywhere || h.refined)
                    {
                        perRefinedRay.push_back(h.evaluations);
                        inARow.push_back(h.evaluationsInARow);
                    }
                }
            // The slowest rays set a GPU's frame time: the tail of the refined rays' evaluations.
            // (Exact's refinement evaluates a round's points side by side: "in a row" counts each round once.)
            std::sort(perRefinedRay.begin(), perRefinedRay.end());
            std::sort(inARow.begin(), inARow.end());
            const auto quantile = [](const std::vector<std::uint32_t>& v, double q) {
                return v.empty() ? 0u : v[std::size_t(q * double(v.size() - 1))];
            };
            std::printf("exact evaluations per refined ray: median %u, p99 %u, p99.9 %u, max %u\n",
                        quantile(perRefinedRay, 0.5), quantile(perRefinedRay, 0.99), quantile(perRefinedRay, 0.999),
                        quantile(perRefinedRay, 1.0));
            std::printf("exact evaluations in a row per refined ray: median %u, p99 %u, p99.9 %u, max %u\n",
                        quantile(inARow, 0.5), quantile(inARow, 0.99), quantile(inARow, 0.999), quantile(inARow, 1.0));
            std::printf("exact evaluations: %.2f per pixel, %.2f per pixel hit; %zu of %zu hits evaluated on the exact field; "
                        "%zu rays of %d traced with the refinement (%.2f%%)\n",
                        double(evaluations) / (double(o.width) * o.height),
                        double(evaluations) / double(std::max<std::size_t>(hits, 1)), refined, hits, rays,
                        o.width * o.height, 100.0 * double(rays) / (double(o.width) * o.height));
        }
        if (!o.diff.empty()) {
            const auto t2 = Clock::now();
            const kerf::TraceImage exact = kerf::traceExact(tape, camera, o.diffEpsilon, o.threads);
            std::printf("exact trace %dx%d: %.1f ms\n", o.width, o.height, msSince(t2));
            writeDiff(image, exact, layout.voxelSize, o.diff);
        }
    }
    const kerf::RgbaImage rgba = kerf::shade(image, tape.features(), kerf::ShadeOptions::forCamera(camera));
    kerf::writePng(o.output, rgba);
    return 0;
}

} // namespace

int main(int argc, char** argv)
{
    Options options;
    try {
        options = parse(argc, argv);
    } catch (const UsageError& e) {
        std::cerr << "kerf_trace_preview: " << e.message << "\n";
        usage(std::cerr);
        return 2;
    }
    try {
        return run(options);
    } catch (const kerf::DocumentError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const std::invalid_argument& e) {
        std::cerr << "kerf_trace_preview: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "kerf_trace_preview: " << e.what() << "\n";
        return 1;
    }
}

#include "kerf/voxelizer/RequestBudget.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <unistd.h>

namespace kerf {

namespace {

// Measured on the 2-core development machine, Release, the six bundled
// examples at their own feature sizes (2026-11-27, docs/benchmarks.md,
// "A default tolerance"): 2.0 triangles per populated voxel (the side
// chair at 0.5 mm: 9.49 M estimated, 9.48 M made); peaks of 170 to 246
// bytes per marching-cubes triangle beyond the program for the plain mesh
// (the read-back check's welding included) and 42 to 142 simplified to a
// tolerance (the marching-cubes mesh is never held twice); 4 to 17 times
// the estimated voxelization's seconds plain, 11 to 34 times simplified.
// (Issue 14 measured 83 bytes and 3.7 times, before the export checked the
// file as read back.)
constexpr double kTrianglesPerVoxel = 2.0;
constexpr double kMeshBytesPerTriangle = 260.0;
constexpr double kMeshSecondsPerVoxelizeSecond = 12.0;
constexpr double kSimplifiedMeshBytesPerTriangle = 160.0;
constexpr double kSimplifiedMeshSecondsPerVoxelizeSecond = 25.0;
// kerf render: the snapshot, its flattened copy for the tracer and, on
// lavapipe, the device's copy in the same memory; 78 bytes per pixel with
// lavapipe (4096x4096: 1.44 GB), 27 with the CPU tracer; about 1.9 us per
// pixel traced on lavapipe (4096x4096: 31 s), 0.6 on the CPU tracer.
constexpr double kRenderVoxelCopies = 3.0;
constexpr double kRenderBytesPerPixel = 80.0;
constexpr double kRenderSecondsPerPixel = 2e-6;
// The program itself (libraries, Qt, Vulkan, the tape).
constexpr double kProgramBytes = 200e6;

constexpr double kMaxRequestBytes = 16.0 * 1024 * 1024 * 1024;
constexpr double kMaxRequestSeconds = 30 * 60;

std::string significant2(double v)
{
    char buf[32];
    if (v >= 100.0) std::snprintf(buf, sizeof buf, "%.0f", v);
    else if (v >= 10.0) std::snprintf(buf, sizeof buf, "%.0f", v);
    else std::snprintf(buf, sizeof buf, "%.2g", v);
    return buf;
}

// Rounds up to two significant digits (a feature size that surely fits).
double roundUp2(double v)
{
    if (!(v > 0.0) || !std::isfinite(v)) return v;
    const double scale = std::pow(10.0, std::floor(std::log10(v)) - 1.0);
    return std::ceil(v / scale - 1e-9) * scale;
}

std::string millimetres(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

} // namespace

std::uint64_t availableMemoryBytes()
{
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    std::uint64_t kb = 0;
    std::string unit;
    while (meminfo >> key >> kb >> unit)
        if (key == "MemAvailable:") return kb * 1024;
    const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? std::uint64_t(pages) * std::uint64_t(size) / 2 : std::uint64_t(4) << 30;
}

RequestBudget RequestBudget::forThisMachine()
{
    return {std::min(0.5 * double(availableMemoryBytes()), kMaxRequestBytes), kMaxRequestSeconds};
}

RequestCost estimateRequest(const Tape& tape, double featureSize, RequestKind kind, double pixels,
                            VoxelEstimate* voxelsOut)
{
    RequestCost c;
    c.fixedBytes = kProgramBytes;
    if (!tape.empty() && !tape.bounds().isEmpty() && tape.bounds().isBounded()) {
        // Estimated on a grid of few, deep tiles: the coarse probes then cost
        // a few hundred tile tests instead of tens of thousands (the per-tile
        // interval pass dominates them), at the same voxel size.
        const GridLayout request = GridLayout::choose(tape.bounds(), featureSize);
        const GridLayout layout = request.tileCount() <= 512
                                      ? request
                                      : GridLayout::choose(tape.bounds(), featureSize, {.maxTiles = 512, .maxLevels = 10});
        VoxelEstimate e = estimateVoxels(tape, layout);
        // A snapshot of another grid is of no use to the caller.
        if (!(layout == request)) {
            e.snapshot.reset();
            e.exact = false;
        }
        // Where even 10 levels of 512 tiles cannot reach the feature size,
        // the voxels are coarser: the surface scales as the inverse square.
        const double finer = std::pow(layout.voxelSize / featureSize, 2.0);
        e.populatedVoxels *= finer;
        e.bytes *= finer;
        e.seconds *= finer;
        c.voxels = e.populatedVoxels;
        switch (kind) {
        case RequestKind::Voxels:
            c.bytes = e.bytes;
            c.seconds = e.seconds;
            break;
        case RequestKind::Render:
            c.bytes = kRenderVoxelCopies * e.bytes;
            c.seconds = e.seconds;
            break;
        case RequestKind::Mesh:
            c.triangles = kTrianglesPerVoxel * e.populatedVoxels;
            c.bytes = kMeshBytesPerTriangle * c.triangles;
            c.seconds = kMeshSecondsPerVoxelizeSecond * e.seconds;
            break;
        case RequestKind::SimplifiedMesh:
            c.triangles = kTrianglesPerVoxel * e.populatedVoxels;
            c.bytes = kSimplifiedMeshBytesPerTriangle * c.triangles;
            c.seconds = kSimplifiedMeshSecondsPerVoxelizeSecond * e.seconds;
            break;
        }
        if (voxelsOut) *voxelsOut = std::move(e);
    }
    if (kind == RequestKind::Render) {
        c.pixels = pixels;
        c.fixedBytes += kRenderBytesPerPixel * pixels;
        c.fixedSeconds += kRenderSecondsPerPixel * pixels;
    }
    c.bytes += c.fixedBytes;
    c.seconds += c.fixedSeconds;
    return c;
}

double featureSizeThatFits(const RequestCost& cost, const RequestBudget& budget, double featureSize)
{
    const double inf = std::numeric_limits<double>::infinity();
    const double roomBytes = budget.bytes - cost.fixedBytes, roomSeconds = budget.seconds - cost.fixedSeconds;
    if (!(roomBytes > 0.0) || !(roomSeconds > 0.0)) return inf;
    const double over = std::max({(cost.bytes - cost.fixedBytes) / roomBytes,
                                  (cost.seconds - cost.fixedSeconds) / roomSeconds, 1e-300});
    // 10% to spare: the estimate is an estimate.
    return roundUp2(featureSize * std::sqrt(over) * 1.1);
}

std::optional<std::string> overBudget(const RequestCost& cost, const RequestBudget& budget, double featureSize)
{
    if (cost.bytes <= budget.bytes && cost.seconds <= budget.seconds) return std::nullopt;
    std::string s = millimetres(featureSize) + " mm needs about ";
    if (cost.pixels > 0.0) s += describeCount(cost.pixels) + " pixels, ";
    if (cost.triangles > 0.0) s += describeCount(cost.triangles) + " triangles, ";
    else if (cost.voxels > 0.0) s += describeCount(cost.voxels) + " voxels, ";
    s += describeBytes(cost.bytes) + " of memory and " + describeSeconds(cost.seconds) + "; this machine allows " +
         describeBytes(budget.bytes) + " and " + describeSeconds(budget.seconds) + " per request";
    const double fits = featureSizeThatFits(cost, budget, featureSize);
    if (std::isfinite(fits)) s += ": choose " + millimetres(fits) + " mm or more";
    return s;
}

std::string describeBytes(double bytes)
{
    static const char* kUnits[] = {"bytes", "KB", "MB", "GB", "TB", "PB", "EB"};
    int u = 0;
    while (bytes >= 1000.0 && u < 6) {
        bytes /= 1000.0;
        ++u;
    }
    if (bytes >= 1000.0) return "more than 1000 EB";
    return significant2(bytes) + " " + kUnits[u];
}

std::string describeSeconds(double s)
{
    if (!std::isfinite(s) || s > 3.15e9) return "more than a century";
    if (s < 1.0) return "under a second";
    if (s < 90.0) return significant2(s) + " s";
    if (s < 90.0 * 60.0) return significant2(s / 60.0) + " min";
    if (s < 48.0 * 3600.0) return significant2(s / 3600.0) + " h";
    if (s < 730.0 * 86400.0) return significant2(s / 86400.0) + " days";
    return significant2(s / (365.0 * 86400.0)) + " years";
}

std::string describeCount(double n)
{
    if (!std::isfinite(n)) return "infinitely many";
    if (n < 1e6) return std::to_string(std::llround(n));
    if (n < 1e9) return significant2(n / 1e6) + " million";
    if (n < 1e12) return significant2(n / 1e9) + " billion";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2g", n);
    return buf;
}

} // namespace kerf

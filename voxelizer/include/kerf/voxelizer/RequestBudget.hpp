#pragma once
// Work that cannot be done is refused before it starts. kerf check, render,
// export, bench and the application's export dialog estimate what a request
// needs (voxels, triangles, memory, time) from the part's bounds and a coarse
// voxelization of its surface (estimateVoxels: the interval pass and a few
// levels of the contree), compare it with the budget below, and refuse what
// exceeds it with one line that says what the request would take and which
// feature size would fit (memory and time both grow as the surface over the
// feature size squared). The budget (docs/cli.md, "Limits"):
//  - memory: half of the memory the machine has available when the request
//    starts (MemAvailable), and never more than 16 GiB;
//  - time: 30 minutes of estimated work; anything allowed that takes more
//    than a few seconds shows progress, and Ctrl+C stops it (no partial
//    file is ever left).
// The per-voxel, per-triangle and per-pixel costs are measured on the
// project's 2-core development machine (Release build) and written down next
// to each constant.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace kerf {

struct RequestBudget {
    double bytes = 0.0;
    double seconds = 0.0;
    /// Half of MemAvailable (at most 16 GiB), 30 minutes.
    static RequestBudget forThisMachine();
};

/// Bytes of memory the machine has available now (/proc/meminfo's
/// MemAvailable; half the physical memory where that cannot be read).
std::uint64_t availableMemoryBytes();

/// What a request needs.
struct RequestCost {
    double voxels = 0.0;    // populated voxels at the feature size
    double triangles = 0.0; // of a mesh (export), else 0
    double pixels = 0.0;    // of a picture (render), else 0
    double bytes = 0.0;     // peak memory
    double seconds = 0.0;   // with every core
    /// The part of bytes and seconds that does not shrink with a coarser
    /// feature size (a picture's pixels, the program itself).
    double fixedBytes = 0.0, fixedSeconds = 0.0;
};

enum class RequestKind {
    Voxels, // voxelize the whole part (kerf check)
    Render, // voxelize, flatten for the tracer, trace a picture (kerf render)
    Mesh,   // marching cubes on the exact field (kerf export --tolerance 0, the dialog unticked)
    SimplifiedMesh, // the same, simplified and refined to a tolerance (an export by default)
};

/// The kind of an export to `tolerance` mm (0: none).
inline RequestKind meshRequestKind(double tolerance)
{
    return tolerance > 0.0 ? RequestKind::SimplifiedMesh : RequestKind::Mesh;
}

/// Estimates a request at `featureSize` (mm) on the part `tape` describes.
/// The estimate voxelizes a few coarse levels (at most about two million
/// voxels; well under a second for any part the format allows). `pixels`:
/// the picture's, for Render.
RequestCost estimateRequest(const Tape& tape, double featureSize, RequestKind kind, double pixels = 0.0,
                            VoxelEstimate* voxelsOut = nullptr);

/// Empty when `cost` fits `budget`; otherwise one line: what the request
/// would take, the budget, and the feature size that would fit, like
/// "0.001 mm needs about 2.2e12 voxels, 75 TB of memory and 900 days; this
/// machine allows 11 GB and 30 min per request: choose 0.34 mm or more".
std::optional<std::string> overBudget(const RequestCost& cost, const RequestBudget& budget, double featureSize);

/// The smallest feature size (mm) at which `cost` fits `budget`, from
/// `featureSize`: surface work grows as 1/featureSize^2. Infinite when
/// even the fixed part does not fit.
double featureSizeThatFits(const RequestCost& cost, const RequestBudget& budget, double featureSize);

/// People's numbers: "3.4 GB", "12 s", "2.2 million".
std::string describeBytes(double bytes);
std::string describeSeconds(double seconds);
std::string describeCount(double count);

} // namespace kerf

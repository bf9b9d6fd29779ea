#pragma once
// The sizes a Kerf document may have (docs/document-format.md, "Limits").
// A document is something people download and share: every count, size and
// depth that drives work or memory is bounded here, and the loader refuses
// what exceeds a bound before any of that work starts, naming the node and
// the field. The bounds are chosen so that a document at every limit at once
// still loads, checks and compiles on a 2-core, 24 GB machine in seconds
// (tests/HostileInputTest.cpp measures it).

#include <cstdint>

namespace kerf::limits {

/// Bytes in a document file. Real parts are kilobytes; a profile at its
/// point limit is about 4 MB of JSON.
inline constexpr std::uint64_t kMaxDocumentBytes = std::uint64_t(32) << 20;

/// Nodes nested inside one another (the root is level 1). The loader checks
/// this while it parses, before any code that walks the tree runs, so
/// nothing recurses deeper than this on any input.
inline constexpr int kMaxNestingDepth = 100;

/// JSON nesting anywhere in the file (unknown fields included): enough for a
/// tree at kMaxNestingDepth with its transforms and profiles.
inline constexpr int kMaxJsonDepth = 2 * kMaxNestingDepth + 24;

/// Primitive copies the tree expands to after arrays and mirrors, hidden
/// ones included (showing a hidden node must not make a document invalid,
/// and the compiler and the cut list still walk hidden copies' structure).
/// Every tile of the voxel grid tests the part's tape against its box, so
/// the coarse work grows with tiles times copies: at 20,000 copies packed
/// in a 300 mm box, kerf check's estimate takes about 2 s on 2 cores
/// (100,000 took 8 s and a full coarse pass minutes).
inline constexpr std::uint64_t kMaxPrimitiveCopies = 20'000;

/// Points in one extrude profile.
inline constexpr std::uint64_t kMaxProfilePoints = 100'000;

/// Profile points over every copy of every extrude (each copy evaluates its
/// whole profile wherever it is near the surface).
inline constexpr std::uint64_t kMaxProfilePointCopies = 1'000'000;

/// Largest magnitude of a length or coordinate in a document (mm): 100 km.
/// Doubles still resolve a nanometre there, and the part's bounds, its
/// voxel grid and every estimate stay finite.
inline constexpr double kMaxLength = 1e8;

/// Largest magnitude of the part's bounds (mm) after arrays, mirrors,
/// offsets and blends: 1000 km.
inline constexpr double kMaxExtent = 1e9;

/// Feature sizes (document setting and command-line option), mm: finer
/// than a nanometre or coarser than a kilometre means nothing for a part.
inline constexpr double kMinFeatureSize = 1e-6;
inline constexpr double kMaxFeatureSize = 1e6;

} // namespace kerf::limits

// Shared by C++ and GLSL: the parameters of a GPU voxelization
// (viewport/src/GpuVoxelizer.cpp, shaders/voxelize.comp), so that the two
// sides cannot drift. Everything is reached by buffer device address.
#ifndef KERF_VOXELIZE_SHARED_H
#define KERF_VOXELIZE_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace kerf::gpu {
using vu64_ = std::uint64_t;
struct vuvec4_ {
    std::uint32_t x, y, z, w;
};
struct vvec4_ {
    float x, y, z, w;
};
#define KERF_U64 vu64_
#define KERF_UVEC4 vuvec4_
#define KERF_VEC4 vvec4_
#else
#define KERF_U64 uint64_t
#define KERF_UVEC4 uvec4
#define KERF_VEC4 vec4
#endif

// Workgroup size of every pass: a node's 64 children, or a leaf's 125 lattice points.
#define KERF_VOXELIZE_GROUP 128
// Words per job: the entry, the node's index, the node's minimum corner in
// finest voxels (x, y, z), and the instructions of the tile's tape that the
// node's box leaves out (2 words, bit i: instruction i; tapes of more than 64
// instructions leave none out): see "Tapes pruned per node" in voxelize.comp.
#define KERF_VOXELIZE_JOB_WORDS 7

// The counters' words (atomics).
#define KERF_COUNT_NODES 0
#define KERF_COUNT_LEAF_INDIRECTIONS 1
#define KERF_COUNT_LEAF_DATA 2
#define KERF_COUNT_VERTICES 3
#define KERF_COUNT_JOBS 4 // 4 and 5: the two job lists
#define KERF_COUNT_PRUNED_LEAF_JOBS 6 // leaf jobs whose tape leaves instructions out
#define KERF_COUNT_WORDS 8

// Passes (push constant `pass`).
#define KERF_PASS_INNER 0   // one group per node of the level: its 64 children by intervals
#define KERF_PASS_LEAF 1    // one group per leaf: 125 corners, populated voxels, vertices
#define KERF_PASS_FINISH 2  // one thread per entry: tile word (entry, or empty/full when nothing was populated)

struct VoxelizeParams {
    KERF_U64 tapes;            // the tiles' encoded tapes, concatenated
    KERF_U64 entries;          // TileEntry (8 words) per surface tile: written by the host
    KERF_U64 entryTiles;       // per entry: its tile's index in `tiles`
    KERF_U64 entryVoxels;      // per entry: populated voxels (atomics), zeroed by the host
    KERF_U64 tiles;            // per tile: entry, kEmptyTile or kFullTile
    KERF_U64 nodes;            // Node: 3 words
    KERF_U64 leafIndirections; // 2 words
    KERF_U64 leafData;         // 2 words
    KERF_U64 vertices;         // 2 words
    KERF_U64 jobs0;            // job lists, KERF_VOXELIZE_JOB_WORDS words each, used in turn by the levels
    KERF_U64 jobs1;
    KERF_U64 counters;         // KERF_COUNT_WORDS words
    KERF_U64 voxelMantissa;    // the finest voxel edge (mm) = voxelMantissa * 2^sizes.w, exactly to 40 bits
    KERF_U64 firstEntry;       // the first entry this build makes (an update's come after its base's);
                               // entryTiles and entryVoxels are indexed from it
    KERF_UVEC4 capacity;       // records the pools hold: nodes, leaf indirections, leaf data, vertices
    KERF_UVEC4 limits;         // x: jobs list 0 holds, y: entries, z: contree levels, w: jobs list 1 holds
    KERF_VEC4 sizes;           // x: finest voxel edge (mm, float), y: tile edge (mm), z: the interval boxes' margin (mm),
                               // w: the voxel edge's power of two (voxelMantissa)
};

#ifdef __cplusplus
static_assert(sizeof(VoxelizeParams) == 13 * 8 + 8 + 3 * 16);
} // namespace kerf::gpu
#endif

#undef KERF_U64
#undef KERF_UVEC4
#undef KERF_VEC4
#endif

#include "MergeTiles.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace kerf::mesher {

namespace {

// Returns the heap's free pages to the system (glibc keeps them otherwise).
void trimHeap()
{
#ifdef __GLIBC__
    ::malloc_trim(0);
#endif
}

void addCounters(const TileCounters& c, MeshStats& stats)
{
    stats.seeds += c.seeds;
    stats.seedsNotMeshed += c.seedsNotMeshed;
    stats.cellsMeshed += c.cellsMeshed;
    stats.cellsFromFloodFill += c.cellsFromFloodFill;
    stats.crossTileRequests += c.crossTileRequests;
    stats.pointEvaluations += c.pointEvaluations;
    stats.rootEvaluations += c.rootEvaluations;
    stats.centreVertices += c.centreVertices;
    stats.featureVertices += c.featureVertices;
    stats.zeroCorners += c.zeroCorners;
    stats.hiddenDetailSearches += c.hiddenDetailSearches;
    stats.hiddenDetailCells += c.hiddenDetailCells;
    // The thinnest; among equals the lowest position, so that the report
    // does not depend on the order of the tiles.
    if (const auto& found = c.thinnestHidden) {
        const auto key = [](double t, const glm::dvec3& p) { return std::make_tuple(t, p.x, p.y, p.z); };
        if (stats.hiddenDetailThickness == 0.0 ||
            key(found->thickness, found->at) < key(stats.hiddenDetailThickness, stats.hiddenDetailAt)) {
            stats.hiddenDetailThickness = found->thickness;
            stats.hiddenDetailAt = found->at;
            stats.hiddenDetailIsMaterial = found->material;
        }
    }
    if (c.cellsMeshed) ++stats.surfaceTiles;
}

// Global numbers of a tile's foreign vertices, from the owners' edge tables.
void resolveForeign(TileShare& st, const TileShares& shares,
                    const std::unordered_map<const TileShare*, std::uint64_t>& vertexOffset)
{
    st.foreignGlobal.resize(st.foreign.size());
    for (std::size_t i = 0; i < st.foreign.size(); ++i) {
        const ForeignVertex& fv = st.foreign[i];
        I3 ownerTile = st.tile;
        for (int a = 0; a < 3; ++a)
            if (fv.ownerStep >> a & 1) ownerTile[a] += 1;
        const TileShare* owner = shares.find(ownerTile);
        const std::uint32_t* ref = owner ? owner->edges.find(fv.ownerEdgeKey) : nullptr;
        if (!ref || (*ref & kForeign))
            throw std::logic_error("mesher: a shared vertex has no owner (the flood fill is incomplete)");
        st.foreignGlobal[i] = std::uint32_t(vertexOffset.at(owner) + *ref);
    }
}

// Copies one tile's vertices and triangles (references made global) to the
// mesh, freeing each chunk once copied.
void copyOut(TileShare& st, glm::dvec3* vertices, glm::dvec3* normals, Triangle* triangles, std::uint32_t vertexOffset)
{
    for (std::size_t c = 0; c < st.vertices.chunkCount(); ++c) {
        vertices = std::copy_n(st.vertices.chunk(c), st.vertices.chunkLength(c), vertices);
        st.vertices.releaseChunk(c);
    }
    for (std::size_t c = 0; c < st.normals.chunkCount(); ++c) {
        normals = std::copy_n(st.normals.chunk(c), st.normals.chunkLength(c), normals);
        st.normals.releaseChunk(c);
    }
    for (std::size_t c = 0; c < st.triangles.chunkCount(); ++c) {
        const Triangle* t = st.triangles.chunk(c);
        const std::size_t count = st.triangles.chunkLength(c);
        for (std::size_t i = 0; i < count; ++i) {
            Triangle g;
            for (std::size_t j = 0; j < 3; ++j) {
                const std::uint32_t r = t[i][j];
                g[j] = r & kForeign ? st.foreignGlobal[r & ~kForeign] : vertexOffset + r;
            }
            *triangles++ = g;
        }
        st.triangles.releaseChunk(c);
    }
    st.vertices.clear();
    st.normals.clear();
    st.triangles.clear();
    std::vector<std::uint32_t>().swap(st.foreignGlobal);
}

} // namespace

Mesh mergeTiles(TileShares& shares, tbb::task_arena& arena, MeshStats& stats, std::vector<glm::dvec3>& normals)
{
    const std::vector<TileShare*> order = shares.ordered();
    std::vector<std::uint64_t> vertexOffset(order.size() + 1, 0);
    std::vector<std::size_t> triangleOffset(order.size() + 1, 0);
    std::unordered_map<const TileShare*, std::uint64_t> offsetOf;
    for (std::size_t k = 0; k < order.size(); ++k) {
        offsetOf[order[k]] = vertexOffset[k];
        vertexOffset[k + 1] = vertexOffset[k] + order[k]->vertices.size();
        triangleOffset[k + 1] = triangleOffset[k] + order[k]->triangles.size();
        addCounters(order[k]->counters, stats);
    }
    if (vertexOffset.back() >= (std::uint64_t(1) << 32))
        throw std::runtime_error("the mesh would have more than 4 billion vertices");
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), order.size(),
                          [&](std::size_t k) { resolveForeign(*order[k], shares, offsetOf); });
    });
    for (TileShare* st : order) {
        st->processed.release();
        st->edges.release();
        std::vector<ForeignVertex>().swap(st->foreign);
    }

    // Copy out in eight batches of tiles, in parallel within a batch, each
    // tile freeing its share as it goes, so that the tiles' share and the
    // mesh are never both whole in memory: reserve() only maps address space,
    // and a batch's pages come as it is written. Most of a share sits in
    // malloc's heap, which keeps freed memory for reuse; nothing reuses it
    // here, so for large meshes it goes back to the system after each batch.
    // That costs about 0.5 s per GB on the development machine (a virtual
    // machine), so small meshes, whose peak does not matter, skip it.
    const std::size_t triangleCount = triangleOffset.back();
    const bool trim =
        vertexOffset.back() * sizeof(glm::dvec3) + triangleCount * sizeof(Triangle) >= (std::size_t(512) << 20);
    Mesh mesh;
    mesh.vertices.reserve(vertexOffset.back());
    normals.clear();
    normals.reserve(vertexOffset.back());
    mesh.triangles.reserve(triangleCount);
    for (std::size_t first = 0; first < order.size();) {
        std::size_t last = first + 1;
        while (last < order.size() && triangleOffset[last] - triangleOffset[first] < triangleCount / 8)
            ++last;
        mesh.vertices.resize(vertexOffset[last]);
        normals.resize(vertexOffset[last]);
        mesh.triangles.resize(triangleOffset[last]);
        arena.execute([&] {
            tbb::parallel_for(first, last, [&](std::size_t k) {
                copyOut(*order[k], mesh.vertices.data() + vertexOffset[k], normals.data() + vertexOffset[k],
                        mesh.triangles.data() + triangleOffset[k], std::uint32_t(vertexOffset[k]));
            });
        });
        if (trim) trimHeap();
        first = last;
    }
    shares.clear();
    if (trim) trimHeap();
    return mesh;
}

} // namespace kerf::mesher

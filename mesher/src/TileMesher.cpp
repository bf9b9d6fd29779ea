#include "TileMesher.hpp"

#include "kerf/mesher/CellPolygons.hpp"
#include "kerf/mesher/Triangulate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace kerf::mesher {

namespace {
inline I3 cornerOffset(int q) { return {q & 1, (q >> 1) & 1, q >> 2}; }
} // namespace

// Corner values of the cells in s.wave, with each lattice point's owning
// block's tape (LatticeTapes.hpp), in one batched call per block. Leaves 8
// indices into s.pointValue per wave cell in s.waveCorners. The wave goes in
// slices of spatially close cells (seeds come in contree order), each with
// its own small point table: a table for a whole large tile would miss the
// cache on nearly every lookup. A point on a slice border is evaluated once
// per slice, to the same double.
void TileMesher::evaluateCorners(TileShare& st, TileScratch& s) const
{
    constexpr std::size_t kSlice = 4096;
    s.waveCorners.resize(8 * s.wave.size());
    for (std::size_t begin = 0; begin < s.wave.size(); begin += kSlice) {
        const std::size_t end = std::min(s.wave.size(), begin + kSlice);
        s.pending.clear();
        s.pointIndex.clear();
        s.pointIndex.reserve(2 * (end - begin));
        for (std::size_t i = begin; i < end; ++i) {
            const I3 cell = fromLocalKey(s.wave[i] & ~kSeedFlag);
            for (int q = 0; q < cell::kCorners; ++q) {
                const I3 p = cell + cornerOffset(q);
                const std::uint64_t key = localKey(p);
                const auto [index, added] = s.pointIndex.insert(key, std::uint32_t(s.pointValue.size()));
                if (added) {
                    s.pending.push_back({localKey(p / lattice_.b), key, *index});
                    s.pointValue.push_back(0.0);
                }
                s.waveCorners[8 * i + std::size_t(q)] = *index;
            }
        }
        evaluatePending(st, s);
    }
}

void TileMesher::evaluatePending(TileShare& st, TileScratch& s) const
{
    // Group by owning block: each group is one batched call on one short tape.
    std::sort(s.pending.begin(), s.pending.end(),
              [](const TileScratch::Pending& a, const TileScratch::Pending& b) { return a.block < b.block; });
    const I3 base = st.tile * lattice_.n;
    const I3 blockBase = st.tile * (lattice_.n / lattice_.b);
    for (std::size_t first = 0; first < s.pending.size();) {
        std::size_t last = first;
        while (last < s.pending.size() && s.pending[last].block == s.pending[first].block)
            ++last;
        const Tape& tape = s.tapes.blockTape(blockBase + fromLocalKey(s.pending[first].block));
        const std::size_t count = last - first;
        s.x.resize(count);
        s.y.resize(count);
        s.z.resize(count);
        s.f.resize(count);
        for (std::size_t k = 0; k < count; ++k) {
            const glm::dvec3 p = lattice_.position(base + fromLocalKey(s.pending[first + k].point)) - tape.origin();
            s.x[k] = p.x;
            s.y[k] = p.y;
            s.z[k] = p.z;
        }
        s.points.evaluate(tape, s.x.data(), s.y.data(), s.z.data(), count, s.f.data());
        for (std::size_t k = 0; k < count; ++k)
            s.pointValue[s.pending[first + k].index] = s.f[k];
        first = last;
    }
    st.counters.pointEvaluations += s.pending.size();
}

std::uint32_t TileMesher::vertexRef(TileShare& st, const I3& cell, int edge, const double* values, TileScratch& s) const
{
    const int axis = cell::edgeAxis(edge);
    const int lowerCorner = cell::edgeLowerCorner(edge);
    const I3 lower = cell + cornerOffset(lowerCorner);
    auto [ref, inserted] = st.edges.insert(edgeKey(lower, axis), 0);
    if (!inserted) return *ref;
    const std::int64_t n = lattice_.n;
    std::uint32_t result;
    if (lower.x < n && lower.y < n && lower.z < n) {
        result = std::uint32_t(st.vertices.size());
        st.vertices.push_back(glm::dvec3(0.0));
    } else {
        // The edge's lower end lies on this tile's upper boundary: the next
        // tile up owns it.
        ForeignVertex fv;
        I3 ownerLocal = lower;
        for (int a = 0; a < 3; ++a)
            if (lower[a] == n) {
                fv.ownerStep |= std::uint8_t(1 << a);
                ownerLocal[a] = 0;
            }
        fv.ownerEdgeKey = edgeKey(ownerLocal, axis);
        result = kForeign | std::uint32_t(st.foreign.size());
        st.foreign.push_back(fv);
    }
    *ref = result;
    EdgeRootJob job;
    job.start = lattice_.position(st.tile * n + lower);
    job.delta[axis] = lattice_.h;
    job.f0 = values[lowerCorner];
    job.f1 = values[cell::edgeUpperCorner(edge)];
    s.jobs.push_back(job);
    s.jobTarget.push_back(result);
    s.jobOrder.emplace_back(localKey(lower / lattice_.b), std::uint32_t(s.jobs.size() - 1));
    return result;
}

void TileMesher::solveRoots(TileShare& st, TileScratch& s) const
{
    std::sort(s.jobOrder.begin(), s.jobOrder.end());
    const I3 blockBase = st.tile * (lattice_.n / lattice_.b);
    for (std::size_t first = 0; first < s.jobOrder.size();) {
        std::size_t last = first;
        while (last < s.jobOrder.size() && s.jobOrder[last].first == s.jobOrder[first].first)
            ++last;
        const Tape& tape = s.tapes.blockTape(blockBase + fromLocalKey(s.jobOrder[first].first));
        s.groupJobs.clear();
        for (std::size_t k = first; k < last; ++k)
            s.groupJobs.push_back(s.jobs[s.jobOrder[k].second]);
        s.groupRoots.resize(s.groupJobs.size());
        st.counters.rootEvaluations += s.roots.solve(tape, s.groupJobs, s.groupRoots.data());
        for (std::size_t k = first; k < last; ++k) {
            const glm::dvec3 p = s.groupJobs[k - first].at(s.groupRoots[k - first]);
            const std::uint32_t target = s.jobTarget[s.jobOrder[k].second];
            if (target & kForeign)
                st.foreign[target & ~kForeign].position = p;
            else
                st.vertices[target] = p;
        }
        first = last;
    }
}

void TileMesher::meshCells(TileShare& st, TileScratch& s) const
{
    s.jobs.clear();
    s.jobTarget.clear();
    s.jobOrder.clear();
    s.polygonRefs.clear();
    s.polygonMasks.clear();
    s.polygonSizes.clear();
    s.polygonCells.clear();
    double v[cell::kCorners];
    for (std::size_t m = 0; m < s.meshed.size(); ++m) {
        const I3 c = fromLocalKey(s.meshed[m]);
        for (int q = 0; q < cell::kCorners; ++q)
            v[q] = s.pointValue[s.meshedCorners[8 * m + std::size_t(q)]];
        const cell::CellCycles cycles = cell::cellCycles(v);
        int offset = 0;
        for (int k = 0; k < cycles.count; ++k) {
            const int size = cycles.size[std::size_t(k)];
            s.polygonSizes.push_back(std::uint8_t(size));
            s.polygonCells.push_back(std::uint32_t(m));
            for (int i = 0; i < size; ++i) {
                const int e = cycles.edges[std::size_t(offset + i)];
                s.polygonRefs.push_back(vertexRef(st, c, e, v, s));
                s.polygonMasks.push_back(cell::edgeFaceMask(e));
            }
            offset += size;
        }
    }
    solveRoots(st, s);

    glm::dvec3 points[kMaxPolygon];
    std::array<std::uint8_t, 3> triangles[kMaxPolygon];
    std::size_t at = 0;
    for (std::size_t k = 0; k < s.polygonSizes.size(); ++k) {
        const int size = s.polygonSizes[k];
        const std::uint32_t* refs = &s.polygonRefs[at];
        for (int i = 0; i < size; ++i)
            points[i] = refs[i] & kForeign ? st.foreign[refs[i] & ~kForeign].position : st.vertices[refs[i]];
        const int made = triangulatePolygon(points, &s.polygonMasks[at], size, triangles);
        if (made == size - 2) {
            for (int t = 0; t < made; ++t)
                st.triangles.push_back({refs[triangles[t][0]], refs[triangles[t][1]], refs[triangles[t][2]]});
        } else {
            const std::uint32_t m = s.polygonCells[k];
            for (int q = 0; q < cell::kCorners; ++q)
                v[q] = s.pointValue[s.meshedCorners[8 * m + std::size_t(q)]];
            const std::uint32_t centre = centreVertex(st, fromLocalKey(s.meshed[m]), v, points, size, s);
            for (int i = 0; i < size; ++i)
                st.triangles.push_back({centre, refs[i], refs[(i + 1) % size]});
        }
        at += std::size_t(size);
    }
}

std::uint32_t TileMesher::centreVertex(TileShare& st, const I3& cell, const double* values, const glm::dvec3* points,
                                       int size, TileScratch& s) const
{
    // A point of the surface inside the cell, near the polygon's centroid:
    // the root on the segment from the centroid to the nearest corner on the
    // other side (the cell is convex and has corners on both sides).
    glm::dvec3 centroid(0.0);
    for (int i = 0; i < size; ++i)
        centroid += points[i];
    centroid /= double(size);
    const I3 lower = st.tile * lattice_.n + cell;
    const Tape& tape = s.tapes.blockTape(lattice_.blockOf(lower));
    const glm::dvec3 c = centroid - tape.origin();
    const double fc = s.points.evaluate(tape, c.x, c.y, c.z);
    glm::dvec3 position = centroid;
    if (fc != 0.0) {
        EdgeRootJob job;
        double best = std::numeric_limits<double>::infinity();
        for (int q = 0; q < cell::kCorners; ++q) {
            if ((values[q] < 0.0) == (fc < 0.0)) continue;
            const glm::dvec3 corner = lattice_.position(lower + cornerOffset(q));
            const double d = glm::length(corner - centroid);
            if (d < best) {
                best = d;
                job = {centroid, corner - centroid, fc, values[q]};
            }
        }
        double t = 0.5;
        st.counters.rootEvaluations += 1 + s.roots.solve(tape, std::span<const EdgeRootJob>(&job, 1), &t);
        position = job.at(t);
    }
    ++st.counters.centreVertices;
    st.vertices.push_back(position);
    return std::uint32_t(st.vertices.size() - 1);
}

bool TileMesher::process(TileShare& st, const std::vector<std::uint64_t>& cells, TileScratch& s,
                         const std::function<bool()>& cancelled) const
{
    s.tapes.clear();
    s.pointValue.clear();
    s.wave.clear();
    s.meshed.clear();
    s.meshedCorners.clear();
    for (const std::uint64_t c : cells)
        if (st.processed.insert(fromLocalKey(c & ~kSeedFlag))) s.wave.push_back(c);
    if (st.edges.size() == 0) st.edges.reserve(s.wave.size()); // about one vertex per surface cell
    const I3 base = st.tile * lattice_.n;
    const std::int64_t n = lattice_.n;
    TileCounters& counters = st.counters;
    while (!s.wave.empty()) {
        if (cancelled && cancelled()) return false;
        evaluateCorners(st, s);
        s.next.clear();
        for (std::size_t i = 0; i < s.wave.size(); ++i) {
            const std::uint64_t c = s.wave[i];
            const bool seed = c & kSeedFlag;
            const std::uint64_t key = c & ~kSeedFlag;
            const std::uint32_t* corners = &s.waveCorners[8 * i];
            std::uint8_t inside = 0;
            for (int q = 0; q < cell::kCorners; ++q)
                inside |= std::uint8_t((s.pointValue[corners[q]] < 0.0) << q);
            if (inside == 0 || inside == 0xFF) {
                if (seed) ++counters.seedsNotMeshed;
                continue;
            }
            s.meshed.push_back(key);
            s.meshedCorners.insert(s.meshedCorners.end(), corners, corners + 8);
            ++counters.cellsMeshed;
            if (!seed) ++counters.cellsFromFloodFill;
            // Flood fill: the neighbour across every face with a sign change
            // must be meshed too, or the surface would stop at this face.
            const I3 cell = fromLocalKey(key);
            const std::uint8_t crossed = cell::crossedFaces(inside);
            for (int f = 0; f < cell::kFaces; ++f) {
                if (!(crossed >> f & 1)) continue;
                I3 neighbour = cell;
                neighbour[f >> 1] += (f & 1) ? 1 : -1;
                const std::int64_t a = neighbour[f >> 1];
                if (a < 0 || a >= n) {
                    st.outbox.push_back(base + neighbour);
                    ++counters.crossTileRequests;
                } else if (st.processed.insert(neighbour)) {
                    s.next.push_back(localKey(neighbour));
                }
            }
        }
        s.wave.swap(s.next);
    }
    meshCells(st, s);
    return true;
}

} // namespace kerf::mesher

#include "TileMesher.hpp"

#include "CreaseSnap.hpp"
#include "FeaturePoint.hpp"

#include "kerf/mesher/CellPolygons.hpp"
#include "kerf/mesher/Triangulate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace kerf::mesher {

namespace {
inline I3 cornerOffset(int q) { return {q & 1, (q >> 1) & 1, q >> 2}; }

// Where a vertex's normal is taken, from its root along its edge, outwards,
// as a fraction of the edge (see solveRoots).
constexpr double kNormalOffset = 1e-5;

// Directions for deciding the side of a lattice point where the field is
// (about) zero. Positive components: the nudged point stays inside the box
// of the block that owns the lattice point, where that block's tape equals
// the full field. Irrational ratios and three independent directions: a
// plane of a part (a board face, the contact of two boards) contains at most
// two of them, so one of the three always leaves the zero set.
const glm::dvec3 kNudgeDirections[3] = {
    glm::normalize(glm::dvec3(1.0, 0.41421356237309515, 0.14159265358979312)),
    glm::normalize(glm::dvec3(0.71828182845904509, 1.0, 0.7320508075688772)),
    glm::normalize(glm::dvec3(0.23606797749978981, 0.64575131106459072, 1.0)),
};
} // namespace

// Where the field is 0 at a lattice point (the face of a board at a round
// millimetre, the contact plane of two boards, a tool flush with the face it
// cuts), the side is that of the nearby point p + nudge * d: a lattice
// shifted by an infinitesimal generic offset. Taking 0 as outside everywhere
// would leave a double membrane where two boards of a union touch (the
// contact is inside the solid on both sides); taking it as inside would do
// the same where a difference's tool is flush with the body's face. The
// nudged value (about nudge in size) replaces the corner value, so every
// later decision (signs, the asymptotic decider, root brackets) agrees.
double TileMesher::sideOfZero(const Tape& tape, const glm::dvec3& p, TileScratch& s) const
{
    for (const glm::dvec3& d : kNudgeDirections) {
        const glm::dvec3 q = p + meshing_.nudge * d;
        const double v = s.points.evaluate(tape, q.x, q.y, q.z);
        if (std::abs(v) > meshing_.zeroBand) return v;
    }
    return meshing_.nudge > 0.0 ? meshing_.nudge : 0.0; // zero all around (a sheet of no thickness): outside
}

glm::dvec3 TileMesher::unitNormal(const Tape& tape, const glm::dvec3& world, TileScratch& s) const
{
    const glm::dvec3 p = world - tape.origin();
    const Dual<double> d = s.gradients.evaluate(tape, p.x, p.y, p.z);
    const glm::dvec3 g(d.d[0], d.d[1], d.d[2]);
    const double length = glm::length(g);
    return length > 0.0 && std::isfinite(length) ? g / length : glm::dvec3(0.0);
}

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
        for (std::size_t k = 0; k < count; ++k) {
            double v = s.f[k];
            if (std::abs(v) <= meshing_.zeroBand) {
                v = sideOfZero(tape, {s.x[k], s.y[k], s.z[k]}, s);
                ++st.counters.zeroCorners;
            }
            s.pointValue[s.pending[first + k].index] = v;
        }
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
        st.normals.push_back(glm::dvec3(0.0));
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
        const std::size_t count = s.groupJobs.size();
        s.groupRoots.resize(count);
        st.counters.rootEvaluations += s.roots.solve(tape, s.groupJobs, s.groupRoots.data());
        // Normals at the vertices (the exact field's gradient), one batch,
        // taken a hundred-thousandth of the edge outside the surface: right
        // at a root a primitive's distance is a length of a vector that is
        // itself rounding noise (sqrt(min(|q - c|^2, ...)) for a cone's side
        // or a profile's edge), and so is the direction of its gradient.
        s.x.resize(count);
        s.y.resize(count);
        s.z.resize(count);
        s.f.resize(count);
        s.gx.resize(count);
        s.gy.resize(count);
        s.gz.resize(count);
        for (std::size_t k = 0; k < count; ++k) {
            const EdgeRootJob& job = s.groupJobs[k];
            const double outward = job.f0 < 0.0 ? kNormalOffset : -kNormalOffset;
            const glm::dvec3 p = job.at(s.groupRoots[k] + outward) - tape.origin();
            s.x[k] = p.x;
            s.y[k] = p.y;
            s.z[k] = p.z;
        }
        s.gradients.evaluate(tape, s.x.data(), s.y.data(), s.z.data(), count, s.f.data(), s.gx.data(), s.gy.data(),
                             s.gz.data());
        for (std::size_t k = first; k < last; ++k) {
            const std::size_t g = k - first;
            const glm::dvec3 p = s.groupJobs[g].at(s.groupRoots[g]);
            const glm::dvec3 gradient(s.gx[g], s.gy[g], s.gz[g]);
            const double length = glm::length(gradient);
            const glm::dvec3 n = length > 0.0 && std::isfinite(length) ? gradient / length : glm::dvec3(0.0);
            const std::uint32_t target = s.jobTarget[s.jobOrder[k].second];
            if (target & kForeign) {
                st.foreign[target & ~kForeign].position = p;
                st.foreign[target & ~kForeign].normal = n;
            } else {
                st.vertices[target] = p;
                st.normals[target] = n;
            }
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

    glm::dvec3 points[kMaxPolygon], normals[kMaxPolygon];
    std::array<std::uint8_t, 3> triangles[kMaxPolygon];
    std::size_t at = 0;
    for (std::size_t k = 0; k < s.polygonSizes.size(); ++k) {
        const int size = s.polygonSizes[k];
        const std::uint32_t* refs = &s.polygonRefs[at];
        for (int i = 0; i < size; ++i) {
            const bool foreign = refs[i] & kForeign;
            points[i] = foreign ? st.foreign[refs[i] & ~kForeign].position : st.vertices[refs[i]];
            normals[i] = foreign ? st.foreign[refs[i] & ~kForeign].normal : st.normals[refs[i]];
        }
        if (meshing_.featureTolerance > 0.0 && smallestNormalCosine(normals, size) < kFeatureCosine) {
            const std::optional<std::uint32_t> feature =
                featureVertex(st, fromLocalKey(s.meshed[s.polygonCells[k]]), points, normals, size, s);
            if (feature) {
                for (int i = 0; i < size; ++i)
                    st.triangles.push_back({*feature, refs[i], refs[(i + 1) % size]});
                at += std::size_t(size);
                continue;
            }
        }
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
    glm::dvec3 position = centroid, normalAt = centroid;
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
        normalAt = job.at(t + (job.f0 < 0.0 ? kNormalOffset : -kNormalOffset));
    }
    ++st.counters.centreVertices;
    st.vertices.push_back(position);
    st.normals.push_back(unitNormal(tape, normalAt, s));
    return std::uint32_t(st.vertices.size() - 1);
}

// A vertex on the sharp edge or corner that crosses the cell, on the
// surface; the polygon then becomes a fan around it. Otherwise nothing (the
// polygon is triangulated as usual: a smooth patch whose normals turn fast,
// or a feature that cannot be pinned down here, left to the refinement).
//
// A corner: the tangent planes of the polygon's vertices meet in a point
// that lies on all of them (within the feature tolerance: planes that only
// seem to meet because a curved sheet's normals turn are no corner). An
// edge: the two vertices whose normals differ most name the two sheets, and
// CreaseSnap.hpp puts the point on the curve where they meet, across from
// the polygon's centre. The point may lie up to half a cell outside the
// cell: where a cell clips a sharp edge near its corner, marching cubes
// joins the two sides in one polygon while the edge runs just outside.
std::optional<std::uint32_t> TileMesher::featureVertex(TileShare& st, const I3& cell, const glm::dvec3* points,
                                                        const glm::dvec3* normals, int size, TileScratch& s) const
{
    for (int i = 0; i < size; ++i)
        if (normals[i] == glm::dvec3(0.0)) return std::nullopt; // a vertex without a normal: no fit
    const FeatureFit fit = fitTangentPlanes(points, normals, size);
    if (fit.rank < 2) return std::nullopt;
    const I3 lower = st.tile * lattice_.n + cell;
    const Aabb cellBox = lattice_.box(lower, 1);
    const glm::dvec3 grow(0.5 * lattice_.h);
    const Aabb box{cellBox.min - grow, cellBox.max + grow};
    auto inBox = [&](const glm::dvec3& p) {
        return p.x > box.min.x && p.y > box.min.y && p.z > box.min.z && p.x < box.max.x && p.y < box.max.y &&
               p.z < box.max.z;
    };
    // Not the block's tape: the point may leave the cell's block, where
    // that tape no longer equals the field. Every query below lies within
    // 4.4 cells of the cell's centre (the crease snap's within 3.25 cells
    // of the polygon's centre, CreaseSnap.cpp; the corner and its spokes'
    // midpoints within 1.5 cells of the cell on every axis): a tape
    // simplified for 5 cells about the centre equals the field there. The
    // whole part's tape made these queries 18% of a bookshelf side's export
    // (its 94 shelf-pin holes evaluated at every step; docs/benchmarks.md).
    const Tape& tape = s.near.near(0.5 * (cellBox.min + cellBox.max), 5.0 * lattice_.h);
    auto field = [&](const glm::dvec3& p) {
        const glm::dvec3 q = p - tape.origin();
        ++st.counters.pointEvaluations;
        return s.points.evaluate(tape, q.x, q.y, q.z);
    };
    std::optional<glm::dvec3> point;
    // A feature point is right when the fan's spokes lie on the surface:
    // from a corner (or a point of the edge) to a vertex of one of its
    // sides, the straight line stays on that side. A point where the
    // tangent planes of a curved sheet happen to meet is no corner: the
    // spokes to that sheet's vertices cut through the part.
    auto spokesOnSurface = [&](const glm::dvec3& x) {
        if (!(std::abs(field(x)) <= meshing_.featureTolerance)) return false;
        for (int i = 0; i < size; ++i)
            if (!(std::abs(field(0.5 * (x + points[i]))) <= meshing_.featureTolerance)) return false;
        return true;
    };
    // A corner up to a whole cell off: the cells around a corner of a turned
    // box may each see only two of its faces, and the one whose polygon sees
    // all three can lie a cell away (the corner was cut off 0.1 mm at 0.5 mm
    // cells, and the collapses cannot make a corner the lattice lacks).
    const Aabb cornerBox{cellBox.min - 2.0 * grow, cellBox.max + 2.0 * grow};
    auto inCornerBox = [&](const glm::dvec3& p) {
        return p.x > cornerBox.min.x && p.y > cornerBox.min.y && p.z > cornerBox.min.z && p.x < cornerBox.max.x &&
               p.y < cornerBox.max.y && p.z < cornerBox.max.z;
    };
    if (fit.rank == 3 && inCornerBox(fit.point) && spokesOnSurface(fit.point)) point = fit.point;
    if (!point) {
        int ia = 0, ib = 1;
        double smallest = 2.0;
        for (int i = 0; i < size; ++i)
            for (int j = i + 1; j < size; ++j)
                if (glm::dot(normals[i], normals[j]) < smallest) {
                    smallest = glm::dot(normals[i], normals[j]);
                    ia = i;
                    ib = j;
                }
        glm::dvec3 centre(0.0);
        for (int i = 0; i < size; ++i)
            centre += points[i];
        centre /= double(size);
        point = snapToCrease(tape, s.gradients, centre, normals[ia], normals[ib], lattice_.h,
                             meshing_.featureTolerance);
        // Missed from the centre: again from the polygon's own points on the two
        // sheets (CreaseSnap.hpp says when the centre misses), and then only
        // where the spokes lie on the surface (near a corner the first step can
        // settle on the line of two sheets past where they end: a door frame's
        // rail, stile and groove left triangles 0.023 mm off at 0.01 mm).
        if (!point || !inBox(*point)) {
            const std::pair onSheets{SurfacePoint{points[ia], normals[ia]}, SurfacePoint{points[ib], normals[ib]}};
            point = snapToCrease(tape, s.gradients, centre, normals[ia], normals[ib], lattice_.h,
                                 meshing_.featureTolerance, onSheets);
            if (point && !spokesOnSurface(*point)) point.reset();
        }
        if (!point || !inBox(*point)) return std::nullopt; // (snapped: on the edge, spokes or not)
    }
    // The fan must not turn over: each triangle (point, v_i, v_i+1) faces,
    // if not the way of both its polygon vertices' normals (across a sharp
    // edge it bends as the surface does), at least the way of their sum.
    for (int i = 0; i < size; ++i) {
        const int j = (i + 1) % size;
        const glm::dvec3 n = glm::cross(points[i] - *point, points[j] - *point);
        if (!(glm::dot(n, normals[i] + normals[j]) > 0.0)) return std::nullopt;
    }
    ++st.counters.featureVertices;
    st.vertices.push_back(*point);
    st.normals.push_back(glm::dvec3(0.0));
    return std::uint32_t(st.vertices.size() - 1);
}

// A seed cell whose corners agree in sign: does it hide something thin?
void TileMesher::lookForHiddenDetail(TileShare& st, const I3& localCell, bool cornersInside, TileScratch& s) const
{
    const I3 cell = st.tile * lattice_.n + localCell;
    const Tape& local = s.tapes.blockTape(lattice_.blockOf(cell)); // its closed box holds the cell
    ++st.counters.hiddenDetailSearches;
    const std::optional<HiddenDetailFound> found =
        findHiddenDetail(local, tape_, lattice_.box(cell, 1), cornersInside, meshing_.zeroBand, s.hidden);
    if (!found) return;
    ++st.counters.hiddenDetailCells;
    if (!st.counters.thinnestHidden || found->thickness < st.counters.thinnestHidden->thickness)
        st.counters.thinnestHidden = found;
}

void TileMesher::lookForHiddenDetail(TileShare& st, const std::vector<QuietCell>& cells, TileScratch& s) const
{
    if (!meshing_.findHiddenDetail) return;
    for (const QuietCell& q : cells) {
        const I3 cell = fromLocalKey(q.key);
        if (st.processed.contains(cell)) continue;
        lookForHiddenDetail(st, cell, q.inside, s);
    }
}

bool TileMesher::process(TileShare& st, const std::vector<std::uint64_t>& cells, TileScratch& s,
                         const Progress& work) const
{
    s.tapes.clear();
    s.roots.setMargin(meshing_.edgeMargin);
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
        if (work.cancelled()) return false;
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
                if (seed) {
                    ++counters.seedsNotMeshed;
                    if (meshing_.findHiddenDetail) lookForHiddenDetail(st, fromLocalKey(key), inside != 0, s);
                }
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

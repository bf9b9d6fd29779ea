#include "kerf/accuracy/SurfaceDistance.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/voxelizer/WorkerArena.hpp"

#include <glm/geometric.hpp>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace kerf {

namespace {

constexpr std::size_t kPacket = 64;   // points evaluated together: one evaluator block
constexpr int kMaxSteps = 64;         // a walk still going after this many steps is stuck: march instead
constexpr int kMaxMarchSteps = 400;   // per direction of the fallback march
constexpr double kConvergedMm = 1e-8; // |f| this small ends the walk
constexpr double kBracketMm = 1e-6;   // the sign change must show this close
constexpr std::size_t kVertexChunk = 4096;
constexpr std::size_t kTriangleChunk = 1024;

// Walks packets of points to the surface. Scratch memory only: one
// per thread.
class Marcher {
public:
    /// Fills out[0..n) for points p[0..n) (world coordinates) with `tape`,
    /// valid inside `valid` (world coordinates; null: everywhere). With a
    /// `valid` box, points the walk does not settle get needFull[i] = 1
    /// instead (to be redone with the full tape); with the full tape, they
    /// are settled by marching.
    void measure(const Tape& tape, const Aabb* valid, const glm::dvec3* p, std::size_t n, PointDistance* out,
                 std::uint8_t* needFull)
    {
        for (std::size_t first = 0; first < n; first += kPacket)
            packet(tape, valid, p + first, std::min(kPacket, n - first), out + first, needFull + first);
    }

private:
    void packet(const Tape& tape, const Aabb* valid, const glm::dvec3* p, std::size_t n, PointDistance* out,
                std::uint8_t* needFull)
    {
        const glm::dvec3 origin = tape.origin();
        std::size_t active = 0;
        for (std::size_t i = 0; i < n; ++i) {
            out[i] = {};
            needFull[i] = 0;
            q_[i] = p[i];
            steps_[i] = 0;
            active_[i] = true;
            converged_[i] = false;
            ++active;
        }
        // Steps from q along the unit gradient by |f(q)|, re-aimed at every
        // step: the ball of radius |f(q)| holds no surface point (the field
        // is 1-Lipschitz), so no step crosses the surface, and each lands
        // closer to it. Where the field is an exact distance, one step lands
        // on the nearest surface point.
        std::array<std::size_t, kPacket> which;
        bool first = true;
        while (active > 0) {
            std::size_t m = 0;
            for (std::size_t i = 0; i < n; ++i) {
                if (!active_[i]) continue;
                x_[m] = q_[i].x - origin.x;
                y_[m] = q_[i].y - origin.y;
                z_[m] = q_[i].z - origin.z;
                which[m++] = i;
            }
            gradients_.evaluate(tape, x_.data(), y_.data(), z_.data(), m, f_.data(), gx_.data(), gy_.data(),
                                gz_.data());
            for (std::size_t k = 0; k < m; ++k) {
                const std::size_t i = which[k];
                const double f = f_[k];
                const glm::dvec3 g(gx_[k], gy_[k], gz_[k]);
                const double len = glm::length(g);
                auto stop = [&] {
                    active_[i] = false;
                    --active;
                };
                if (first) out[i].lower = std::abs(f);
                if (f == 0.0) {
                    // Exactly on the surface (root-found vertices often are);
                    // the dual numbers may give no gradient there (sqrt at 0).
                    out[i].upper = glm::length(q_[i] - p[i]);
                    out[i].resolved = true;
                    stop();
                    continue;
                }
                if (!std::isfinite(f)) {
                    stop(); // no surface anywhere (an empty tape)
                    continue;
                }
                const bool hasNormal = len > 0.0 && std::isfinite(len);
                normal_[i] = hasNormal ? g / len : glm::dvec3(0.0);
                if (std::abs(f) <= kConvergedMm) {
                    stop();
                    converged_[i] = true;
                    continue;
                }
                if (!hasNormal) {
                    stop(); // no direction to go in
                    continue;
                }
                converged_[i] = false;
                const glm::dvec3 next = q_[i] - f * normal_[i];
                if (++steps_[i] > kMaxSteps || (valid && !valid->contains(next))) {
                    stop(); // finished below: with the full tape, then by marching
                    continue;
                }
                q_[i] = next;
            }
            first = false;
        }
        // A converged point is on the surface only if the field changes sign
        // near it: between q -+ kBracketMm along the normal or, where the
        // dual numbers gave no gradient, along the three axes. Two points of
        // opposite signs within kBracketMm of q have a surface point on the
        // segment between them, within kBracketMm of q too.
        std::size_t m = 0, brackets = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (needFull[i] || !converged_[i]) continue;
            const bool hasNormal = normal_[i] != glm::dvec3(0.0);
            const std::size_t directions = hasNormal ? 1 : 3;
            bracketFirst_[brackets] = m;
            for (std::size_t d = 0; d < directions; ++d) {
                glm::dvec3 axis(0.0);
                axis[int(d)] = 1.0;
                const glm::dvec3 along = hasNormal ? normal_[i] : axis;
                for (double side : {-1.0, 1.0}) {
                    const glm::dvec3 b = q_[i] + side * kBracketMm * along - origin;
                    x_[m] = b.x;
                    y_[m] = b.y;
                    z_[m] = b.z;
                    ++m;
                }
            }
            which[brackets++] = i;
        }
        if (m > 0) {
            bracketFirst_[brackets] = m;
            points_.evaluate(tape, x_.data(), y_.data(), z_.data(), m, f_.data());
            for (std::size_t k = 0; k < brackets; ++k) {
                bool inside = false, outside = false;
                for (std::size_t j = bracketFirst_[k]; j < bracketFirst_[k + 1]; ++j) {
                    inside |= f_[j] <= 0.0;
                    outside |= f_[j] >= 0.0;
                }
                if (inside && outside) {
                    const std::size_t i = which[k];
                    out[i].upper = glm::length(q_[i] - p[i]) + kBracketMm;
                    out[i].resolved = true;
                }
            }
        }
        // What the walk did not settle (it left the simplified tape's box,
        // got stuck between two surfaces of a field that is only a bound
        // there, or found no sign change) is redone with the full tape, and
        // failing that settled by straight marches.
        for (std::size_t i = 0; i < n; ++i) {
            if (out[i].resolved || !std::isfinite(out[i].lower)) continue;
            if (valid)
                needFull[i] = 1;
            else
                out[i].upper = march(tape, p[i], out[i].resolved);
        }
    }

    // Straight sphere-tracing marches from p along 26 directions (the
    // neighbours of a cube cell), each stepping by max(|f|, kBracketMm) until
    // f changes sign; the nearest crossing bounds the distance (the surface
    // lies on the last step). Slow, and needed only where the field is a
    // bound that the walk cannot follow (a point in a hole's mouth, between
    // the hole's bottom and the face it opens through).
    double march(const Tape& tape, const glm::dvec3& p, bool& resolved)
    {
        const glm::dvec3 at = p - tape.origin();
        const double f0 = points_.evaluate(tape, at.x, at.y, at.z);
        resolved = false;
        double best = HUGE_VAL;
        for (int k = 0; k < 27; ++k) {
            const glm::dvec3 d(k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1);
            if (d == glm::dvec3(0.0)) continue;
            const glm::dvec3 u = glm::normalize(d);
            double t = 0.0, f = f0;
            for (int step = 0; step < kMaxMarchSteps; ++step) {
                t += std::max(std::abs(f), kBracketMm);
                if (t >= best) break;
                const glm::dvec3 q = at + t * u;
                f = points_.evaluate(tape, q.x, q.y, q.z);
                if (!std::isfinite(f)) break;
                if (f0 > 0.0 ? f <= 0.0 : f >= 0.0) {
                    best = t;
                    resolved = true;
                    break;
                }
            }
        }
        return resolved ? best : 0.0;
    }

    PointEvaluator<double> points_;
    GradientEvaluator<double> gradients_;
    // 6 * kPacket: the bracket evaluates up to six points per sample.
    std::array<double, 6 * kPacket> x_{}, y_{}, z_{}, f_{};
    std::array<std::size_t, kPacket + 1> bracketFirst_{};
    std::array<double, kPacket> gx_{}, gy_{}, gz_{};
    std::array<glm::dvec3, kPacket> q_{}, normal_{};
    std::array<int, kPacket> steps_{};
    std::array<bool, kPacket> active_{}, converged_{};
};

struct Scratch {
    Marcher marcher;
    IntervalEvaluator intervals;
    Tape simplified;
    std::vector<glm::dvec3> points;
    std::vector<PointDistance> distances;
    std::vector<std::uint8_t> needFull;
};

// Measures `points` with the tape simplified for their bounding box grown by
// `margin`, then redoes with the full tape the walks that left that box.
void measureChunk(const Tape& tape, Scratch& s, double margin)
{
    const std::size_t n = s.points.size();
    s.distances.assign(n, {});
    s.needFull.assign(n, 0);
    if (n == 0) return;
    Aabb box;
    for (const glm::dvec3& p : s.points)
        box = box.merged({p, p});
    const glm::dvec3 extent = box.size();
    box = box.grown(std::max({margin, 1e-3, 0.25 * std::max({extent.x, extent.y, extent.z})}));
    const glm::dvec3 o = tape.origin();
    s.intervals.simplify(tape, {box.min - o, box.max - o}, s.simplified);
    s.marcher.measure(s.simplified, &box, s.points.data(), n, s.distances.data(), s.needFull.data());
    for (std::size_t i = 0; i < n; ++i) {
        if (!s.needFull[i]) continue;
        std::uint8_t again = 0;
        s.marcher.measure(tape, nullptr, &s.points[i], 1, &s.distances[i], &again);
    }
}

struct ChunkResult {
    std::uint64_t samples = 0, unresolved = 0;
    double max = 0.0, maxLower = 0.0, vertexMax = 0.0;
    glm::dvec3 maxAt{0.0};
    double weighted = 0.0, area = 0.0;
};

} // namespace

std::vector<PointDistance> distancesToSurface(const Tape& tape, const std::vector<glm::dvec3>& points)
{
    std::vector<PointDistance> out(points.size());
    std::vector<std::uint8_t> unused(points.size());
    Marcher marcher;
    marcher.measure(tape, nullptr, points.data(), points.size(), out.data(), unused.data());
    return out;
}

SurfaceDistance measureSurfaceDistance(const Mesh& mesh, const Tape& tape, int threads, const Progress& work)
{
    SurfaceDistance result;
    const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();
    std::vector<double> vertexDistance(nv, 0.0);
    std::vector<char> vertexResolved(nv, 0);
    const std::size_t vertexChunks = (nv + kVertexChunk - 1) / kVertexChunk;
    const std::size_t triangleChunks = (nt + kTriangleChunk - 1) / kTriangleChunk;
    std::vector<ChunkResult> vertexResults(vertexChunks), triangleResults(triangleChunks);
    tbb::enumerable_thread_specific<Scratch> scratch;
    tbb::task_arena arena = workerArena(threads);
    std::atomic<std::size_t> chunksDone{0};
    const double chunks = double(vertexChunks + triangleChunks);
    arena.execute([&] {
        // The vertices first: the triangles' quadrature needs their distances.
        tbb::parallel_for(std::size_t(0), vertexChunks, [&](std::size_t c) {
            if (work.cancelled()) return;
            Scratch& s = scratch.local();
            const std::size_t first = c * kVertexChunk, last = std::min(nv, first + kVertexChunk);
            s.points.assign(mesh.vertices.begin() + long(first), mesh.vertices.begin() + long(last));
            measureChunk(tape, s, 0.0);
            ChunkResult& r = vertexResults[c];
            for (std::size_t i = 0; i < s.points.size(); ++i) {
                const PointDistance& d = s.distances[i];
                ++r.samples;
                vertexResolved[first + i] = d.resolved;
                if (!d.resolved) {
                    ++r.unresolved;
                    continue;
                }
                vertexDistance[first + i] = d.upper;
                if (d.upper > r.max) r.maxAt = s.points[i];
                r.max = std::max(r.max, d.upper);
                r.vertexMax = std::max(r.vertexMax, d.upper);
                r.maxLower = std::max(r.maxLower, d.lower);
            }
            if (work.reporting()) work.report(double(++chunksDone) / chunks);
        });
        tbb::parallel_for(std::size_t(0), triangleChunks, [&](std::size_t c) {
            if (work.cancelled()) return;
            Scratch& s = scratch.local();
            const std::size_t first = c * kTriangleChunk, last = std::min(nt, first + kTriangleChunk);
            s.points.clear();
            double longestEdge = 0.0;
            for (std::size_t t = first; t < last; ++t) {
                const auto& tri = mesh.triangles[t];
                const glm::dvec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &d = mesh.vertices[tri[2]];
                longestEdge = std::max({longestEdge, glm::length(b - a), glm::length(d - b), glm::length(a - d)});
                s.points.push_back(0.5 * (a + b));
                s.points.push_back(0.5 * (b + d));
                s.points.push_back(0.5 * (d + a));
                s.points.push_back((a + b + d) / 3.0);
            }
            measureChunk(tape, s, 2.0 * longestEdge);
            ChunkResult& r = triangleResults[c];
            for (std::size_t t = first; t < last; ++t) {
                const auto& tri = mesh.triangles[t];
                const PointDistance* d = &s.distances[4 * (t - first)];
                bool resolved = vertexResolved[tri[0]] && vertexResolved[tri[1]] && vertexResolved[tri[2]];
                for (int k = 0; k < 4; ++k) {
                    ++r.samples;
                    if (!d[k].resolved) {
                        ++r.unresolved;
                        resolved = false;
                        continue;
                    }
                    if (d[k].upper > r.max) r.maxAt = s.points[4 * (t - first) + std::size_t(k)];
                    r.max = std::max(r.max, d[k].upper);
                    r.maxLower = std::max(r.maxLower, d[k].lower);
                }
                if (!resolved) continue;
                const glm::dvec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &e = mesh.vertices[tri[2]];
                const double area = 0.5 * glm::length(glm::cross(b - a, e - a));
                const double vertices = vertexDistance[tri[0]] + vertexDistance[tri[1]] + vertexDistance[tri[2]];
                const double midpoints = d[0].upper + d[1].upper + d[2].upper;
                r.weighted += area * (vertices / 20.0 + midpoints * 2.0 / 15.0 + d[3].upper * 9.0 / 20.0);
                r.area += area;
            }
            if (work.reporting()) work.report(double(++chunksDone) / chunks);
        });
    });
    result.complete = !work.cancelled();
    // Summed in chunk order: the same figures whatever the thread count.
    double weighted = 0.0;
    for (const auto* results : {&vertexResults, &triangleResults})
        for (const ChunkResult& r : *results) {
            result.samples += r.samples;
            result.unresolved += r.unresolved;
            if (r.max > result.max) result.maxAt = r.maxAt;
            result.max = std::max(result.max, r.max);
            result.maxLowerBound = std::max(result.maxLowerBound, r.maxLower);
            result.vertexMax = std::max(result.vertexMax, r.vertexMax);
            weighted += r.weighted;
            result.area += r.area;
        }
    result.mean = result.area > 0.0 ? weighted / result.area : 0.0;
    return result;
}

} // namespace kerf

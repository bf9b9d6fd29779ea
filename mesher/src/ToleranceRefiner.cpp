#include "ToleranceRefiner.hpp"

#include "CreaseSnap.hpp"
#include "CrossingGuard.hpp"
#include "RegionTapes.hpp"
#include "RimTriangulation.hpp"
#include "SampleDistance.hpp"
#include "TriangleClearance.hpp"
#include "TriangleSamples.hpp"
#include "TriangleTree.hpp"
#include "kerf/mesher/SelfIntersections.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/evaluator/PointEvaluator.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

namespace kerf::mesher {

namespace {

using Tri = std::array<std::uint32_t, 3>;

constexpr double kCreaseCosine = 0.8660254037844387; // 30 degrees

// No triangle (none found yet).
constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

// The point of a sharp edge of the part that edge (u, v) between triangles
// (u, v, w) and (v, u, x) runs along, in the plane across it through its
// midpoint: a surface point on each side, a quarter of the edge from the
// midpoint, and the crease where their tangent planes meet. Nothing where
// the triangles meet flatter than the crease angle, or where no crease is
// found there (a round, or sheets that do not meet).
std::optional<glm::dvec3> creaseAcross(const Tape& tape, GradientEvaluator<double>& gradients, const glm::dvec3& pu,
                                       const glm::dvec3& pv, const glm::dvec3& pw, const glm::dvec3& px,
                                       double tolerance)
{
    const glm::dvec3 c1 = glm::cross(pv - pu, pw - pu), c2 = glm::cross(pu - pv, px - pv);
    const double l1 = glm::length(c1), l2 = glm::length(c2), length = glm::length(pv - pu);
    if (!(l1 > 0.0) || !(l2 > 0.0) || !(length > 0.0)) return std::nullopt;
    const glm::dvec3 n1 = c1 / l1, n2 = c2 / l2;
    if (!(glm::dot(n1, n2) < kCreaseCosine)) return std::nullopt;
    const glm::dvec3 mid = 0.5 * (pu + pv), e = (pv - pu) / length;
    auto across = [&](const glm::dvec3& apex) {
        return glm::normalize(apex - (pu + e * glm::dot(apex - pu, e)));
    };
    auto onto = [&](glm::dvec3 q, const glm::dvec3& expected) -> std::optional<SurfacePoint> {
        return projectOntoSurface(tape, gradients, q, length, 1e-4 * tolerance, expected);
    };
    const auto s1 = onto(mid + 0.25 * length * across(pw), n1);
    const auto s2 = onto(mid + 0.25 * length * across(px), n2);
    if (!s1 || !s2) return std::nullopt;
    const auto c = snapToCrease(tape, gradients, mid, s1->n, s2->n, length, 0.25 * tolerance);
    if (!c || !(glm::length(*c - mid) < length)) return std::nullopt;
    return c;
}

struct Verdict {
    double worst = 0.0;         // largest distance at a sample (SampleDistance.hpp), mm
    std::array<int, 3> edges{}; // the edges to try splitting, best first (-1: none more)
    std::array<int, 3> others{-1, -1, -1}; // the edges that keep to it, longest first (-1: none more)
    double facing = 1.0;        // cosine between the normal and the field's gradient at the centroid
};

// A triangle whose normal points against the field's gradient at its
// centroid faces into the part: a fold (a flap turned over, a fin whose two
// triangles face apart). The mesh stays closed and free of crossings, so no
// reader's check sees it, but its normals are wrong and a fin's chord cuts
// across the part (the bookshelf side's 1 mm round corner at 1 mm cells:
// 0.24 mm).
bool folded(double facing) { return facing < 0.0; }

// A triangle leaning more than 75 degrees from the surface's normal: where
// splits are stuck next to one (its neighbours' new triangles must turn
// its way), flipping it upright lets them go on (RefineSettings::unfoldLeaning).
bool leans(double facing) { return facing < 0.25881904510252074; }

// The cosine between the normal of (a, b, c) and the gradient g (1 where
// either is zero: no judgement).
double facingCosine(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& g)
{
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double ln = glm::length(n), lg = glm::length(g);
    if (!(ln > 0.0) || !(lg > 0.0)) return 1.0;
    return glm::dot(n, g) / (ln * lg);
}

std::uint64_t halfedgeKey(std::uint32_t from, std::uint32_t to) { return std::uint64_t(from) << 32 | to; }

// Samples triangles on the exact field. One per thread.
class Sampler {
public:
    void judge(const Mesh& mesh, const Tape& tape, double tolerance, const std::uint32_t* triangles, std::size_t count,
               Verdict* verdicts)
    {
        points_.clear();
        normals_.clear();
        const glm::dvec3 origin = tape.origin();
        for (std::size_t i = 0; i < count; ++i) {
            const Tri& t = mesh.triangles[triangles[i]];
            appendTriangleSamples(mesh.vertices[t[0]] - origin, mesh.vertices[t[1]] - origin,
                                  mesh.vertices[t[2]] - origin, points_);
            const glm::dvec3 n =
                glm::cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]);
            const double length = glm::length(n);
            normals_.insert(normals_.end(), kTriangleSamples, length > 0.0 ? n / length : glm::dvec3(0.0));
        }
        const std::size_t n = points_.size();
        x_.resize(n);
        y_.resize(n);
        z_.resize(n);
        f_.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            x_[k] = points_[k].x;
            y_[k] = points_[k].y;
            z_[k] = points_[k].z;
        }
        // The tape simplified for the samples' box: a chunk of triangles
        // lies in a small part of the part, where most of the tape is
        // decided (and the simplified tape equals the full one there).
        glm::dvec3 lo(points_.empty() ? glm::dvec3(0.0) : points_[0]), hi(lo);
        for (const glm::dvec3& p : points_) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const glm::dvec3 reach(distances_.reach(tolerance));
        intervals_.simplify(tape, Aabb{lo - reach, hi + reach}, region_);
        distances_.measure(region_, x_.data(), y_.data(), z_.data(), n, tolerance, f_.data(), normals_.data());
        // The gradient at each centroid, for the facing (in the samples' box).
        cx_.resize(count);
        cy_.resize(count);
        cz_.resize(count);
        cd_.resize(count);
        gx_.resize(count);
        gy_.resize(count);
        gz_.resize(count);
        for (std::size_t i = 0; i < count; ++i) {
            const Tri& t = mesh.triangles[triangles[i]];
            const glm::dvec3 c = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0 - origin;
            cx_[i] = c.x;
            cy_[i] = c.y;
            cz_[i] = c.z;
        }
        gradients_.evaluate(region_, cx_.data(), cy_.data(), cz_.data(), count, cd_.data(), gx_.data(), gy_.data(),
                            gz_.data());
        for (std::size_t i = 0; i < count; ++i) {
            // The edges in the order of their worst sample (the one the
            // triangle strays most along); the inside samples count for the
            // longest edge.
            Verdict v;
            double edgeWorst[3] = {0.0, 0.0, 0.0};
            const Tri& t = mesh.triangles[triangles[i]];
            int longest = 0;
            double longestLength = -1.0;
            for (int e = 0; e < 3; ++e) {
                const double l =
                    glm::length(mesh.vertices[t[std::size_t(e)]] - mesh.vertices[t[std::size_t(e + 1) % 3]]);
                if (l > longestLength) {
                    longestLength = l;
                    longest = e;
                }
            }
            for (std::size_t s = 0; s < kTriangleSamples; ++s) {
                const double e = f_[i * kTriangleSamples + s];
                v.worst = std::max(v.worst, e);
                const int edge = kTriangleSamplePattern[s].edge >= 0 ? kTriangleSamplePattern[s].edge : longest;
                edgeWorst[edge] = std::max(edgeWorst[edge], e);
            }
            v.edges = {0, 1, 2};
            std::sort(v.edges.begin(), v.edges.end(), [&](int a, int b) {
                return edgeWorst[a] > edgeWorst[b] || (edgeWorst[a] == edgeWorst[b] && a < b);
            });
            // Splitting an edge that keeps to the tolerance does not help
            // by itself; such edges are tried, longest first, only where
            // none beyond it splits (RefineSettings::splitOtherEdges).
            int others = 0;
            for (int k = 0; k < 3; ++k)
                if (!(edgeWorst[v.edges[std::size_t(k)]] > tolerance)) {
                    v.others[std::size_t(others++)] = v.edges[std::size_t(k)];
                    v.edges[std::size_t(k)] = -1;
                }
            const auto edgeLength = [&](int e) {
                return glm::length(mesh.vertices[t[std::size_t(e)]] - mesh.vertices[t[std::size_t(e + 1) % 3]]);
            };
            std::sort(v.others.begin(), v.others.begin() + others, [&](int a, int b) {
                const double la = edgeLength(a), lb = edgeLength(b);
                return la > lb || (la == lb && a < b);
            });
            v.facing = facingCosine(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]],
                                    glm::dvec3(gx_[i], gy_[i], gz_[i]));
            verdicts[i] = v;
        }
    }

private:
    SampleDistance distances_{true}; // the final judgement
    IntervalEvaluator intervals_;
    GradientEvaluator<double> gradients_;
    Tape region_;
    std::vector<glm::dvec3> points_, normals_;
    std::vector<double> x_, y_, z_, f_;
    std::vector<double> cx_, cy_, cz_, cd_, gx_, gy_, gz_;
};

// Samples the given triangles in the arena, a chunk of them per task.
std::vector<Verdict> judgeAll(const Mesh& mesh, const Tape& tape, double tolerance,
                              const std::vector<std::uint32_t>& triangles,
                              tbb::enumerable_thread_specific<Sampler>& samplers, tbb::task_arena& arena)
{
    constexpr std::size_t kChunk = 256;
    std::vector<Verdict> verdicts(triangles.size());
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), (triangles.size() + kChunk - 1) / kChunk, [&](std::size_t c) {
            const std::size_t first = c * kChunk, count = std::min(kChunk, triangles.size() - first);
            samplers.local().judge(mesh, tape, tolerance, triangles.data() + first, count, verdicts.data() + first);
        });
    });
    return verdicts;
}

// The worst of the triangles' sampled errors, where it is, and how many
// exceed the tolerance.
ToleranceCheck worstOf(const Mesh& mesh, const std::vector<double>& worst, const std::vector<double>& facing,
                       double tolerance)
{
    ToleranceCheck check;
    for (std::size_t t = 0; t < worst.size(); ++t) {
        if (folded(facing[t])) ++check.foldedTriangles;
        if (worst[t] > check.worstSample) {
            check.worstSample = worst[t];
            const Tri& tri = mesh.triangles[t];
            check.worstAt = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
        }
        if (worst[t] > tolerance) {
            ++check.trianglesOverTolerance;
            const Tri& tri = mesh.triangles[t];
            check.areaOverTolerance += 0.5 * glm::length(glm::cross(mesh.vertices[tri[1]] - mesh.vertices[tri[0]],
                                                                    mesh.vertices[tri[2]] - mesh.vertices[tri[0]]));
        }
    }
    return check;
}

// Splits edges and places their new vertices. Sequential.
class Splitter {
public:
    Splitter(Mesh& mesh, std::vector<glm::dvec3>& normals, const Tape& tape, double tolerance, double minHeight,
             double clearance, double regionSize, bool thirdSheet)
        : mesh_(mesh), normals_(normals), regions_(tape, regionSize), tolerance_(tolerance), minHeight_(minHeight),
          clearance_(clearance), thirdSheet_(thirdSheet)
    {
        halfedges_.reserve(3 * mesh.triangles.size() * 2);
        for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
            add(t);
    }

    enum class Outcome { Split, Busy, Impossible };

    /// Splits one edge of triangle t1, trying them in the order given, with
    /// the new vertex on the surface; an edge whose split would fold a
    /// triangle is passed over (a vertex off the surface would never be
    /// fixed: vertices are not moved once placed). Busy when a triangle on the first edge was split this round
    /// (try again next round). The changed and new triangles go to `changed`.
    Outcome split(std::uint32_t t1, const std::array<int, 3>& edges, std::vector<std::uint8_t>& splitThisRound,
                  std::vector<std::uint32_t>& changed, RefineStats& stats)
    {
        if (splitThisRound[t1]) return Outcome::Busy;
        const Tri tri = mesh_.triangles[t1];
        for (int k = 0; k < 3; ++k) {
            const int e = edges[std::size_t(k)];
            if (e < 0) break;
            const std::uint32_t u = tri[std::size_t(e)], v = tri[std::size_t(e + 1) % 3],
                                w = tri[std::size_t(e + 2) % 3];
            const auto other = halfedges_.find(halfedgeKey(v, u));
            if (other == halfedges_.end()) continue; // not a closed edge: leave it
            const std::uint32_t t2 = other->second;
            if (splitThisRound[t2]) {
                if (k == 0) return Outcome::Busy;
                continue;
            }
            const Tri tri2 = mesh_.triangles[t2];
            std::uint32_t x = 0;
            for (int j = 0; j < 3; ++j)
                if (tri2[std::size_t(j)] != u && tri2[std::size_t(j)] != v) x = tri2[std::size_t(j)];
            bool crease = false;
            glm::dvec3 normal(0.0);
            const std::optional<glm::dvec3> p = place(t1, t2, u, v, w, x, crease, normal);
            if (!p) continue;
            applyEdgeSplit(t1, t2, u, v, w, x, *p, normal, splitThisRound, changed);
            ++stats.splits;
            if (crease) ++stats.creaseSplits;
            return Outcome::Split;
        }
        return Outcome::Impossible;
    }

    /// The triangle nearest to point p of the part's surface, where p lies
    /// further than the tolerance from every triangle, with its edges in
    /// the order to split them: the one p lies nearest first. Nothing where
    /// the mesh comes within the tolerance of p.
    std::optional<std::pair<std::uint32_t, std::array<int, 3>>> missing(const glm::dvec3& p) const
    {
        std::uint32_t nearest = kNoTriangle;
        double best = std::numeric_limits<double>::infinity();
        for (double r = tolerance_;; r *= 2.0) {
            grid_.query(p - glm::dvec3(r), p + glm::dvec3(r), [&](std::uint32_t t) {
                const Tri& tri = mesh_.triangles[t];
                const double d =
                    pointTriangleDistance(p, mesh_.vertices[tri[0]], mesh_.vertices[tri[1]], mesh_.vertices[tri[2]]);
                if (d < best || (d == best && t < nearest)) {
                    best = d;
                    nearest = t;
                }
            });
            if (best <= r || r > 1e6) break;
        }
        if (nearest == kNoTriangle || best <= tolerance_) return std::nullopt;
        const Tri& tri = mesh_.triangles[nearest];
        std::array<double, 3> fromEdge{};
        for (int e = 0; e < 3; ++e) {
            const glm::dvec3 a = mesh_.vertices[tri[std::size_t(e)]], b = mesh_.vertices[tri[std::size_t(e + 1) % 3]];
            const double t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
            fromEdge[std::size_t(e)] = glm::length(p - (a + t * (b - a)));
        }
        std::array<int, 3> order{0, 1, 2};
        std::sort(order.begin(), order.end(), [&](int a, int b) {
            return fromEdge[std::size_t(a)] < fromEdge[std::size_t(b)] ||
                   (fromEdge[std::size_t(a)] == fromEdge[std::size_t(b)] && a < b);
        });
        return std::make_pair(nearest, order);
    }

    /// Where no split helps (a triangle standing across the surface, a cap
    /// over a curved sharp edge): flips an edge of t1 (in the order given)
    /// whose flip lowers the worse sampled error of its two triangles.
    bool flip(std::uint32_t t1, const std::array<int, 3>& edges, std::vector<std::uint8_t>& splitThisRound,
              std::vector<std::uint32_t>& changed)
    {
        if (splitThisRound[t1]) return false;
        for (const int e : edges) {
            if (e < 0) break;
            const std::optional<Flip> f = flippable(t1, e, splitThisRound);
            if (!f) continue;
            const glm::dvec3 pu = mesh_.vertices[f->u], pv = mesh_.vertices[f->v], pw = mesh_.vertices[f->w],
                             px = mesh_.vertices[f->x];
            const glm::dvec3 before = glm::cross(pv - pu, pw - pu) + glm::cross(pu - pv, px - pv);
            const glm::dvec3 n1 = glm::cross(pu - pw, px - pw), n2 = glm::cross(pv - px, pw - px);
            if (!(glm::dot(n1, before) > 0.0 && glm::dot(n2, before) > 0.0)) continue;
            const auto [old, now] = flipErrors(*f);
            if (!(now < old)) continue;
            if (crosses(*f)) continue;
            apply(*f, splitThisRound, changed);
            ++flips;
            return true;
        }
        return false;
    }

    /// Unfolds triangle t1, which faces into the part: flips the edge of it
    /// whose flip leaves the pair facing the surface's way best, where that
    /// is better than the pair faces now, the new triangles stray no further
    /// than the pair did (or keep the tolerance) and cross nothing. The
    /// gradient judges, not the pair's summed normal as in flip(): a fin's
    /// two normals cancel.
    bool unfold(std::uint32_t t1, std::vector<std::uint8_t>& splitThisRound, std::vector<std::uint32_t>& changed)
    {
        if (splitThisRound[t1]) return false;
        std::optional<Flip> best;
        double bestFacing = 0.0;
        for (int e = 0; e < 3; ++e) {
            const std::optional<Flip> f = flippable(t1, e, splitThisRound);
            if (!f) continue;
            const glm::dvec3 pu = mesh_.vertices[f->u], pv = mesh_.vertices[f->v], pw = mesh_.vertices[f->w],
                             px = mesh_.vertices[f->x];
            const double before = std::min(facing(pu, pv, pw), facing(pv, pu, px));
            const double after = std::min(facing(pw, pu, px), facing(px, pv, pw));
            if (!(after > before) || (best && !(after > bestFacing))) continue;
            const auto [old, now] = flipErrors(*f);
            if (!(now <= std::max(tolerance_, old))) continue;
            if (crosses(*f)) continue;
            best = f;
            bestFacing = after;
        }
        if (!best) return false;
        apply(*best, splitThisRound, changed);
        ++unfolds;
        return true;
    }

    /// Where no split or flip of triangle t1 helps: the disk of triangles
    /// round it (it, then its neighbours, then theirs, each adding a corner
    /// to the disk's rim, none inside) triangulated anew on the rim's
    /// corners (RimTriangulation.hpp), where the new triangulation's worst
    /// sampled triangle is better than the disk's worst now; every new
    /// triangle keeps a height, stands upright to the surface, makes no
    /// edge the mesh has elsewhere and crosses nothing. Where two sharp
    /// edges of the part meet at a tangent (the turned leg's pommel on its
    /// cylinder), the cells' triangles reach from one face to the other
    /// across both edges, with vertices on each edge but no edge along
    /// either: no split's new vertex mends that, a new triangulation of the
    /// same vertices does.
    bool retriangulate(std::uint32_t t1, std::vector<std::uint8_t>& splitThisRound, std::vector<std::uint32_t>& changed)
    {
        if (splitThisRound[t1]) return false;
        std::vector<std::uint32_t> region{t1};
        const Tri& first = mesh_.triangles[t1];
        std::vector<std::uint32_t> rim(first.begin(), first.end()); // the disk's rim, in the triangles' winding
        for (int ring = 0; ring < kRetriangulationRings; ++ring) {
            // Each edge of the rim as it stands adds the triangle beyond it
            // where that triangle's third corner is not on the rim yet.
            const std::vector<std::uint32_t> before = rim;
            for (std::size_t e = 0; e < before.size() && rim.size() < kRetriangulationCorners; ++e) {
                const std::uint32_t u = before[e], v = before[(e + 1) % before.size()];
                const auto pos = std::find(rim.begin(), rim.end(), u);
                if (rim[std::size_t(pos - rim.begin() + 1) % rim.size()] != v) continue;
                const auto other = halfedges_.find(halfedgeKey(v, u));
                if (other == halfedges_.end() || splitThisRound[other->second]) continue;
                std::uint32_t x = 0;
                for (const std::uint32_t k : mesh_.triangles[other->second])
                    if (k != u && k != v) x = k;
                if (std::find(rim.begin(), rim.end(), x) != rim.end()) continue;
                region.push_back(other->second);
                rim.insert(pos + 1, x);
            }
            if (rim.size() > before.size() && triangulateAnew(region, rim, splitThisRound, changed)) return true;
        }
        return false;
    }

    std::uint64_t flips = 0;
    std::uint64_t unfolds = 0;
    std::uint64_t retriangulations = 0;

private:
    static constexpr int kRetriangulationRings = 4;
    static constexpr std::size_t kRetriangulationCorners = 32;

    // The disk `region` (its triangles' corners all on `rim`) triangulated
    // anew where that lowers its worst sampled triangle (retriangulate()).
    bool triangulateAnew(const std::vector<std::uint32_t>& region, const std::vector<std::uint32_t>& rim,
                         std::vector<std::uint8_t>& splitThisRound, std::vector<std::uint32_t>& changed)
    {
        const int n = int(rim.size());
        glm::dvec3 centre(0.0);
        for (const std::uint32_t v : rim)
            centre += mesh_.vertices[v];
        centre /= double(n);
        double radius = 0.0;
        for (const std::uint32_t v : rim)
            radius = std::max(radius, glm::length(mesh_.vertices[v] - centre));
        const Tape& tape = regions_.near(centre, radius + distances_.reach(tolerance_));
        double worstNow = 0.0;
        for (const std::uint32_t t : region) {
            const Tri& tri = mesh_.triangles[t];
            worstNow = std::max(
                worstNow, sampledError(tape, mesh_.vertices[tri[0]], mesh_.vertices[tri[1]], mesh_.vertices[tri[2]]));
        }
        const auto inRegion = [&](std::uint32_t t) {
            return std::find(region.begin(), region.end(), t) != region.end();
        };
        // An edge between corners i and j that the mesh has outside the disk.
        const auto edgeElsewhere = [&](int i, int j) {
            if ((j - i + n) % n == 1 || (i - j + n) % n == 1) return false; // the rim's own
            for (const std::uint64_t key : {halfedgeKey(rim[std::size_t(i)], rim[std::size_t(j)]),
                                            halfedgeKey(rim[std::size_t(j)], rim[std::size_t(i)])}) {
                const auto found = halfedges_.find(key);
                if (found != halfedges_.end() && !inRegion(found->second)) return true;
            }
            return false;
        };
        const auto triangulation = triangulateRim(n, [&](int i, int k, int j) {
            const glm::dvec3 a = mesh_.vertices[rim[std::size_t(i)]], b = mesh_.vertices[rim[std::size_t(k)]],
                             c = mesh_.vertices[rim[std::size_t(j)]];
            constexpr double kForbidden = std::numeric_limits<double>::infinity();
            const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
            if (!(glm::length(glm::cross(b - a, c - a)) > minHeight_ * longest)) return kForbidden;
            if (edgeElsewhere(i, k) || edgeElsewhere(k, j) || edgeElsewhere(i, j)) return kForbidden;
            if (leans(facing(a, b, c))) return kForbidden;
            return sampledError(tape, a, b, c);
        });
        if (!triangulation || !(triangulation->worst < worstNow)) return false;
        std::vector<Tri> added;
        for (const auto& [i, k, j] : triangulation->triangles)
            added.push_back({rim[std::size_t(i)], rim[std::size_t(k)], rim[std::size_t(j)]});
        std::vector<NewTriangle> made;
        for (const Tri& t : added)
            made.push_back({t, {mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]}});
        const bool crossing = anyCrossesInGrid(grid_, made.data(), made.size(), clearance_, inRegion,
                                               [&](std::uint32_t t, glm::dvec3(&q)[3]) {
                                                   const Tri& b = mesh_.triangles[t];
                                                   for (int k = 0; k < 3; ++k)
                                                       q[k] = mesh_.vertices[b[std::size_t(k)]];
                                                   return b;
                                               });
        if (crossing || newTrianglesTooClose(made.data(), made.size(), clearance_)) return false;
        for (const std::uint32_t t : region)
            remove(t);
        for (std::size_t i = 0; i < region.size(); ++i) {
            mesh_.triangles[region[i]] = added[i];
            add(region[i]);
            splitThisRound[region[i]] = 1;
            changed.push_back(region[i]);
        }
        ++retriangulations;
        return true;
    }

    // How triangle (a, b, c) faces the surface (facingCosine at its centroid).
    double facing(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
    {
        const glm::dvec3 centroid = (a + b + c) / 3.0;
        const Tape& tape = regions_.near(centroid, 0.0);
        const glm::dvec3 q = centroid - tape.origin();
        const Dual<double> g = gradients_.evaluate(tape, q.x, q.y, q.z);
        return facingCosine(a, b, c, glm::dvec3(g.d[0], g.d[1], g.d[2]));
    }

    // The flip of edge (u, v) between t1 = (u, v, w) and t2 = (v, u, x):
    // they become (w, u, x) and (x, v, w).
    struct Flip {
        std::uint32_t t1, t2, u, v, w, x;
    };
    // The flip of edge e of t1, where it makes two proper triangles: the
    // edge is closed, its other triangle not changed this round, (w, x) not
    // an edge already, and both new triangles keep a height.
    std::optional<Flip> flippable(std::uint32_t t1, int e, const std::vector<std::uint8_t>& splitThisRound) const
    {
        const Tri& tri = mesh_.triangles[t1];
        const std::uint32_t u = tri[std::size_t(e)], v = tri[std::size_t(e + 1) % 3], w = tri[std::size_t(e + 2) % 3];
        const auto other = halfedges_.find(halfedgeKey(v, u));
        if (other == halfedges_.end()) return std::nullopt;
        const std::uint32_t t2 = other->second;
        if (splitThisRound[t2]) return std::nullopt;
        std::uint32_t x = 0;
        for (const std::uint32_t k : mesh_.triangles[t2])
            if (k != u && k != v) x = k;
        if (w == x || halfedges_.count(halfedgeKey(w, x)) || halfedges_.count(halfedgeKey(x, w))) return std::nullopt;
        const glm::dvec3 pu = mesh_.vertices[u], pv = mesh_.vertices[v], pw = mesh_.vertices[w],
                         px = mesh_.vertices[x];
        const glm::dvec3 n1 = glm::cross(pu - pw, px - pw), n2 = glm::cross(pv - px, pw - px);
        const double longest1 = std::max({glm::length(pu - pw), glm::length(px - pu), glm::length(pw - px)});
        const double longest2 = std::max({glm::length(pv - px), glm::length(pw - pv), glm::length(px - pw)});
        if (!(glm::length(n1) > minHeight_ * longest1 && glm::length(n2) > minHeight_ * longest2)) return std::nullopt;
        return Flip{t1, t2, u, v, w, x};
    }
    // The worse sampled error of the pair before the flip and after it.
    std::pair<double, double> flipErrors(const Flip& f)
    {
        const glm::dvec3 pu = mesh_.vertices[f.u], pv = mesh_.vertices[f.v], pw = mesh_.vertices[f.w],
                         px = mesh_.vertices[f.x];
        const glm::dvec3 mid = 0.5 * (pu + pv);
        const Tape& tape = regions_.near(mid, std::max({glm::length(pu - mid), glm::length(pw - mid),
                                                        glm::length(px - mid)}) +
                                                  distances_.reach(tolerance_));
        return {std::max(sampledError(tape, pu, pv, pw), sampledError(tape, pv, pu, px)),
                std::max(sampledError(tape, pw, pu, px), sampledError(tape, px, pv, pw))};
    }
    bool crosses(const Flip& f) const
    {
        return wouldCross(std::array<Tri, 2>{Tri{f.w, f.u, f.x}, Tri{f.x, f.v, f.w}}, nullptr, f.t1, f.t2);
    }
    void apply(const Flip& f, std::vector<std::uint8_t>& splitThisRound, std::vector<std::uint32_t>& changed)
    {
        remove(f.t1);
        remove(f.t2);
        mesh_.triangles[f.t1] = {f.w, f.u, f.x};
        mesh_.triangles[f.t2] = {f.x, f.v, f.w};
        for (const std::uint32_t t : {f.t1, f.t2}) {
            add(t);
            splitThisRound[t] = 1;
            changed.push_back(t);
        }
    }

    double sampledError(const Tape& tape, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
    {
        samples_.clear();
        appendTriangleSamples(a, b, c, samples_);
        const glm::dvec3 origin = tape.origin();
        double x[kTriangleSamples], y[kTriangleSamples], z[kTriangleSamples], d[kTriangleSamples];
        for (std::size_t k = 0; k < kTriangleSamples; ++k) {
            x[k] = samples_[k].x - origin.x;
            y[k] = samples_[k].y - origin.y;
            z[k] = samples_[k].z - origin.z;
        }
        distances_.measure(tape, x, y, z, kTriangleSamples, tolerance_, d);
        return *std::max_element(d, d + kTriangleSamples);
    }

    void add(std::uint32_t t)
    {
        const Tri& tri = mesh_.triangles[t];
        for (int k = 0; k < 3; ++k)
            halfedges_[halfedgeKey(tri[std::size_t(k)], tri[std::size_t(k + 1) % 3])] = t;
        const auto [lo, hi] = boxOf(tri, nullptr);
        grid_.insert(t, lo, hi);
    }
    void remove(std::uint32_t t)
    {
        const Tri& tri = mesh_.triangles[t];
        for (int k = 0; k < 3; ++k)
            halfedges_.erase(halfedgeKey(tri[std::size_t(k)], tri[std::size_t(k + 1) % 3]));
        const auto [lo, hi] = boxOf(tri, nullptr);
        grid_.erase(t, lo, hi);
    }

    // The position of vertex i, where index vertices.size() is the vertex
    // about to be added at `pending`.
    glm::dvec3 at(std::uint32_t i, const glm::dvec3* pending) const
    {
        return i < mesh_.vertices.size() ? mesh_.vertices[i] : *pending;
    }
    std::pair<glm::dvec3, glm::dvec3> boxOf(const Tri& tri, const glm::dvec3* pending) const
    {
        glm::dvec3 lo(at(tri[0], pending)), hi(lo);
        for (int k = 1; k < 3; ++k) {
            lo = glm::min(lo, at(tri[std::size_t(k)], pending));
            hi = glm::max(hi, at(tri[std::size_t(k)], pending));
        }
        return {lo, hi};
    }

    // Whether any of the new triangles would cross a triangle of the mesh
    // other than the two they replace: a split vertex placed on the surface
    // or a flip can reach through a thin part or a neighbouring fold, and a
    // crossing mesh does not bound a solid.
    template <std::size_t N>
    bool wouldCross(const std::array<Tri, N>& added, const glm::dvec3* pending, std::uint32_t t1,
                    std::uint32_t t2) const
    {
        std::array<NewTriangle, N> made;
        for (std::size_t i = 0; i < N; ++i)
            made[i] = {added[i], {at(added[i][0], pending), at(added[i][1], pending), at(added[i][2], pending)}};
        const bool crossing = anyCrossesInGrid(
            grid_, made.data(), N, clearance_, [&](std::uint32_t t) { return t == t1 || t == t2; },
            [&](std::uint32_t t, glm::dvec3(&q)[3]) {
                const Tri& b = mesh_.triangles[t];
                for (int k = 0; k < 3; ++k)
                    q[k] = mesh_.vertices[b[std::size_t(k)]];
                return b;
            });
        return crossing || newTrianglesTooClose(made.data(), N, clearance_);
    }

    // p moved onto the surface (projectOntoSurface, CreaseSnap.hpp), and its
    // normal; false when the steps do not settle within `reach`.
    bool project(const Tape& tape, glm::dvec3& p, double reach, glm::dvec3* normal = nullptr,
                 const glm::dvec3& expected = glm::dvec3(0.0))
    {
        const auto s = projectOntoSurface(tape, gradients_, p, reach, 1e-4 * tolerance_, expected);
        if (!s) return false;
        p = s->p;
        if (normal) *normal = s->n;
        return true;
    }

    // Edge (u, v) between triangles t1 = (u, v, w) and t2 = (v, u, x)
    // split at p (normal: the new vertex's).
    void applyEdgeSplit(std::uint32_t t1, std::uint32_t t2, std::uint32_t u, std::uint32_t v, std::uint32_t w,
                        std::uint32_t x, const glm::dvec3& p, const glm::dvec3& normal,
                        std::vector<std::uint8_t>& splitThisRound, std::vector<std::uint32_t>& changed)
    {
        remove(t1);
        remove(t2);
        const std::uint32_t m = std::uint32_t(mesh_.vertices.size());
        mesh_.vertices.push_back(p);
        normals_.push_back(normal);
        const std::uint32_t t3 = std::uint32_t(mesh_.triangles.size()), t4 = t3 + 1;
        mesh_.triangles[t1] = {u, m, w};
        mesh_.triangles[t2] = {v, m, x};
        mesh_.triangles.push_back({m, v, w});
        mesh_.triangles.push_back({m, u, x});
        splitThisRound.resize(mesh_.triangles.size(), 0);
        for (const std::uint32_t t : {t1, t2, t3, t4}) {
            add(t);
            splitThisRound[t] = 1;
            changed.push_back(t);
        }
    }

    // Whether a new triangle (a, b, c) turns its parent's way (normal
    // `parent`) and keeps a height.
    bool fits(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& parent) const
    {
        const glm::dvec3 cr = glm::cross(b - a, c - a);
        const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        return glm::dot(cr, parent) > 0.0 && glm::length(cr) > minHeight_ * longest;
    }

    // The new vertex of edge (u, v) between triangles (u, v, w) and (v, u, x),
    // on the surface, and its normal (0 on a sharp edge); nothing when no such
    // point keeps the four triangles turning their parents' way.
    std::optional<glm::dvec3> place(std::uint32_t t1, std::uint32_t t2, std::uint32_t u, std::uint32_t v,
                                    std::uint32_t w, std::uint32_t x, bool& crease, glm::dvec3& normal)
    {
        const glm::dvec3 pu = mesh_.vertices[u], pv = mesh_.vertices[v], pw = mesh_.vertices[w],
                         px = mesh_.vertices[x];
        const glm::dvec3 mid = 0.5 * (pu + pv);
        const double length = glm::length(pv - pu);
        const glm::dvec3 n1 = glm::normalize(glm::cross(pv - pu, pw - pu));
        const glm::dvec3 n2 = glm::normalize(glm::cross(pu - pv, px - pv));
        std::array<std::pair<glm::dvec3, glm::dvec3>, 4> candidates; // (position, normal)
        int count = 0;
        // Every query below stays within about two edge lengths of the midpoint.
        const Tape& tape = regions_.near(mid, 4.0 * length);
        auto creasePoint = [&](const glm::dvec3&, const glm::dvec3& g1, const glm::dvec3&,
                               const glm::dvec3& g2) -> std::optional<glm::dvec3> {
            const auto c = snapToCrease(tape, gradients_, mid, g1, g2, length, 0.25 * tolerance_);
            if (!c || !(glm::length(*c - mid) < length)) return std::nullopt;
            return c;
        };
        // A sharp edge of the part between the edge's ends: their own
        // tangent planes (the marching cubes' Hermite data) locate it.
        if (normals_[u] != glm::dvec3(0.0) && normals_[v] != glm::dvec3(0.0))
            if (const auto c = creasePoint(pu, normals_[u], pv, normals_[v]))
                candidates[std::size_t(count++)] = {*c, glm::dvec3(0.0)};
        if (count == 0) // perhaps a sharp edge along the edge
            if (const auto c = creaseAcross(tape, gradients_, pu, pv, pw, px, tolerance_))
                candidates[std::size_t(count++)] = {*c, glm::dvec3(0.0)};
        glm::dvec3 p = mid, n(0.0);
        const bool projected = project(tape, p, length, &n, glm::normalize(n1 + n2));
        // A third sheet between the ends: the sharp edges it makes with
        // each end's sheet, before the point on it (RefineSettings::splitsOnThirdSheet).
        if (thirdSheet_ && projected && n != glm::dvec3(0.0))
            for (const std::uint32_t end : {u, v}) {
                const glm::dvec3 ne = normals_[end];
                if (ne == glm::dvec3(0.0) || !(glm::dot(ne, n) < kCreaseCosine)) continue;
                if (const auto c = creasePoint(mid, ne, mid, n))
                    candidates[std::size_t(count++)] = {*c, glm::dvec3(0.0)};
            }
        if (projected) candidates[std::size_t(count++)] = {p, n};
        // Each new triangle must turn its parent's way and keep a height.
        for (int i = 0; i < count; ++i) {
            const auto& [at, an] = candidates[std::size_t(i)];
            const std::uint32_t m = std::uint32_t(mesh_.vertices.size());
            if (fits(pu, at, pw, n1) && fits(at, pv, pw, n1) && fits(pv, at, px, n2) && fits(at, pu, px, n2) &&
                !wouldCross(std::array<Tri, 4>{Tri{u, m, w}, Tri{v, m, x}, Tri{m, v, w}, Tri{m, u, x}}, &at, t1, t2)) {
                crease = an == glm::dvec3(0.0);
                normal = an;
                return at;
            }
        }
        return std::nullopt;
    }

private:
    Mesh& mesh_;
    std::vector<glm::dvec3>& normals_;
    RegionTapes regions_;
    double tolerance_;
    double minHeight_;
    double clearance_;
    bool thirdSheet_;
    std::unordered_map<std::uint64_t, std::uint32_t> halfedges_;
    TriangleTree grid_;
    std::vector<glm::dvec3> samples_;
    GradientEvaluator<double> gradients_;
    SampleDistance distances_;
};

} // namespace

bool refineToTolerance(Mesh& mesh, std::vector<glm::dvec3>& normals, const Tape& tape, const RefineSettings& settings,
                       tbb::task_arena& arena, RefineStats& stats, const Progress& work)
{
    stats = {};
    if (mesh.triangles.empty()) return true;
    const double tolerance = settings.tolerance;
    std::vector<std::uint32_t> dirty(mesh.triangles.size());
    for (std::uint32_t t = 0; t < dirty.size(); ++t)
        dirty[t] = t;
    std::vector<double> worst(mesh.triangles.size(), 0.0), facing(mesh.triangles.size(), 1.0);
    tbb::enumerable_thread_specific<Sampler> samplers;
    Splitter splitter(mesh, normals, tape, tolerance, settings.minHeight, settings.clearance, settings.regionSize,
                      settings.splitsOnThirdSheet);
    auto turnsUpright = [&](double cosine) { return settings.unfoldLeaning ? leans(cosine) : folded(cosine); };
    std::vector<std::uint8_t> splitThisRound;
    std::vector<std::uint32_t> stuck;
    std::vector<std::uint8_t> touched; // vertices of this round's changed triangles
    int coveragePass = 0;
    std::vector<std::pair<double, std::uint32_t>> beyond;
    std::size_t fewestOver = std::numeric_limits<std::size_t>::max();
    int fewestOverRound = 0;
    // The part's points further than the tolerance from the mesh
    // (settings.partSamples), furthest first: the edge nearest each is
    // split where the mesh is still that far when its turn comes; the
    // triangles changed.
    auto splitWhereFarPoints = [&] {
        std::vector<std::uint32_t> changed;
        if (!settings.partSamples || coveragePass >= settings.coveragePasses) return changed;
        ++coveragePass;
        // The first pass measures every point; the later ones those the
        // pass before found beyond, and every point again once those all
        // keep to the tolerance (a split can take the mesh further from a
        // point it kept to, rarely).
        std::vector<std::uint32_t> stillBeyond;
        for (const auto& [distance, i] : beyond)
            stillBeyond.push_back(i);
        std::sort(stillBeyond.begin(), stillBeyond.end());
        const bool whole = coveragePass == 1 || stillBeyond.empty();
        const bool measured = coveragePass == 1 && settings.partSamplesBeyond && stats.splits == 0 &&
                              splitter.flips == 0 && splitter.unfolds == 0;
        if (measured) beyond = *settings.partSamplesBeyond;
        else measureCoverage(*settings.partSamples, mesh, tolerance, arena, &beyond, whole ? nullptr : &stillBeyond);
        // Those all kept to now: every point again, once.
        if (beyond.empty() && !whole) measureCoverage(*settings.partSamples, mesh, tolerance, arena, &beyond);
        splitThisRound.assign(mesh.triangles.size(), 0);
        const glm::dvec3 origin = settings.partSamples->origin;
        for (const auto& [distance, i] : beyond) {
            const auto miss = splitter.missing(origin + glm::dvec3(settings.partSamples->points[i]));
            if (!miss) continue;
            if (splitter.split(miss->first, miss->second, splitThisRound, changed, stats) == Splitter::Outcome::Split)
                ++stats.partPointSplits;
        }
        std::sort(changed.begin(), changed.end());
        changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
        // The splits answer points, not samples: the patience counts anew.
        fewestOver = std::numeric_limits<std::size_t>::max();
        fewestOverRound = stats.rounds;
        return changed;
    };
    for (stats.rounds = 0; !dirty.empty(); ++stats.rounds) {
        if (work.cancelled()) return false;
        // (Most refinements are done in a few rounds: the bar then jumps.)
        work.report(double(stats.rounds) / double(settings.maxRounds + 1));
        const std::vector<Verdict> verdicts = judgeAll(mesh, tape, tolerance, dirty, samplers, arena);
        stats.samples += dirty.size() * kTriangleSamples;
        worst.resize(mesh.triangles.size(), 0.0);
        facing.resize(mesh.triangles.size(), 1.0);
        std::vector<std::pair<double, std::uint32_t>> failing; // (-worst, index into dirty)
        for (std::size_t i = 0; i < dirty.size(); ++i) {
            worst[dirty[i]] = verdicts[i].worst;
            facing[dirty[i]] = verdicts[i].facing;
            if (verdicts[i].worst > tolerance || turnsUpright(verdicts[i].facing))
                failing.emplace_back(-verdicts[i].worst, std::uint32_t(i));
        }
        const auto over = std::size_t(std::count_if(worst.begin(), worst.end(), [&](double w) { return w > tolerance; }));
        if (over < fewestOver) {
            fewestOver = over;
            fewestOverRound = stats.rounds;
        }
        if (failing.empty()) {
            // Every triangle keeps to the tolerance; where the part's own
            // points lie further from the mesh, they go into it.
            std::vector<std::uint32_t> inserted = splitWhereFarPoints();
            if (inserted.empty()) break;
            dirty.swap(inserted);
            continue;
        }
        if (stats.rounds - fewestOverRound >= settings.patienceRounds && stats.rounds < settings.maxRounds &&
            mesh.triangles.size() < settings.maxTriangles) {
            // Out of patience with the samples' splits: the part's far
            // points may still go in, and the patience counts anew.
            std::vector<std::uint32_t> inserted = splitWhereFarPoints();
            if (!inserted.empty()) {
                dirty.swap(inserted);
                continue;
            }
        }
        if (stats.rounds >= settings.maxRounds || mesh.triangles.size() >= settings.maxTriangles ||
            stats.rounds - fewestOverRound >= settings.patienceRounds) {
            stats.gaveUp = true;
            break;
        }
        // Worst first: where two want the same edge, the worse one splits it.
        std::sort(failing.begin(), failing.end());
        splitThisRound.assign(mesh.triangles.size(), 0);
        std::vector<std::uint32_t> changed, busy;
        std::size_t tried = 0;
        for (const auto& [negative, i] : failing) {
            // A round over millions of triangles takes minutes: Ctrl+C is
            // asked here too, and the triangle limit holds within a round
            // (a sphere 200 km across at the default tolerance split on
            // past 5 GB, deaf to Ctrl+C).
            if ((++tried & 1023) == 0 && work.cancelled()) return false;
            if (mesh.triangles.size() >= settings.maxTriangles) break;
            // A fold first: a split of a folded triangle makes folded ones.
            if (turnsUpright(verdicts[i].facing)) {
                if (splitThisRound[dirty[i]]) {
                    busy.push_back(dirty[i]);
                    continue;
                }
                if (splitter.unfold(dirty[i], splitThisRound, changed)) continue;
                if (!(verdicts[i].worst > tolerance)) {
                    stuck.push_back(dirty[i]);
                    continue;
                }
            }
            const auto outcome = settings.splitEdges
                                     ? splitter.split(dirty[i], verdicts[i].edges, splitThisRound, changed, stats)
                                     : Splitter::Outcome::Impossible;
            if (outcome == Splitter::Outcome::Busy) busy.push_back(dirty[i]);
            if (outcome == Splitter::Outcome::Impossible &&
                !splitter.flip(dirty[i], verdicts[i].edges, splitThisRound, changed) &&
                (!settings.retriangulateStuck || !splitter.retriangulate(dirty[i], splitThisRound, changed)) &&
                (!settings.splitOtherEdges || verdicts[i].others[0] < 0 ||
                 splitter.split(dirty[i], verdicts[i].others, splitThisRound, changed, stats) !=
                     Splitter::Outcome::Split))
                stuck.push_back(dirty[i]);
        }
        if (changed.empty()) {
            // Nothing could be split: the part's far points may still go in.
            std::vector<std::uint32_t> inserted = splitWhereFarPoints();
            if (inserted.empty()) break;
            dirty.swap(inserted);
            continue;
        }
        // A triangle that waited for a neighbour's split is judged again
        // (it may have been changed by that split, or not), and so is one
        // that could not be split when a split or flip touched one of its
        // corners this round: a neighbour's new vertex can make its split
        // possible. One left alone by this round stays as it is (trying it
        // again would find the same; it counts as over the tolerance).
        touched.assign(mesh.vertices.size(), 0);
        for (const std::uint32_t t : changed)
            for (const std::uint32_t v : mesh.triangles[t])
                touched[v] = 1;
        changed.insert(changed.end(), busy.begin(), busy.end());
        for (const std::uint32_t t : stuck) {
            const Tri& tri = mesh.triangles[t];
            if (touched[tri[0]] || touched[tri[1]] || touched[tri[2]]) changed.push_back(t);
        }
        stuck.clear();
        std::sort(changed.begin(), changed.end());
        changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
        dirty.swap(changed);
    }
    const ToleranceCheck left = worstOf(mesh, worst, facing, tolerance);
    stats.unfolds = splitter.unfolds;
    stats.retriangulations = splitter.retriangulations;
    stats.foldedTriangles = left.foldedTriangles;
    stats.worstSample = left.worstSample;
    stats.worstAt = left.worstAt;
    stats.trianglesOverTolerance = left.trianglesOverTolerance;
    stats.areaOverTolerance = left.areaOverTolerance;
    return true;
}

ToleranceCheck checkTolerance(const Mesh& mesh, const Tape& tape, double tolerance, tbb::task_arena& arena)
{
    std::vector<std::uint32_t> all(mesh.triangles.size());
    for (std::uint32_t t = 0; t < all.size(); ++t)
        all[t] = t;
    tbb::enumerable_thread_specific<Sampler> samplers;
    const std::vector<Verdict> verdicts = judgeAll(mesh, tape, tolerance, all, samplers, arena);
    std::vector<double> worst(all.size()), facing(all.size());
    for (std::size_t t = 0; t < all.size(); ++t) {
        worst[t] = verdicts[t].worst;
        facing[t] = verdicts[t].facing;
    }
    return worstOf(mesh, worst, facing, tolerance);
}

} // namespace kerf::mesher

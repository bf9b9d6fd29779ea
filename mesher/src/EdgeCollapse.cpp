#include "EdgeCollapse.hpp"

#include "CrossingGuard.hpp"
#include "SymmetricEigen.hpp"
#include "TriangleClearance.hpp"
#include "TriangleTree.hpp"
#include "TriangleSamples.hpp"
#include "kerf/mesher/SelfIntersections.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <unordered_map>
#include <cmath>
#include <limits>

namespace kerf::mesher {

std::size_t CollapseMesh::liveTriangles() const
{
    return std::size_t(std::count_if(triangles.begin(), triangles.end(),
                                     [](const Triangle& t) { return t[0] != kRemoved; }));
}

void CollapseMesh::dropRemoved()
{
    constexpr std::uint32_t kUnused = 0xFFFFFFFFu;
    std::vector<std::uint32_t> index(positions.size(), kUnused);
    for (const Triangle& t : triangles)
        if (t[0] != kRemoved)
            for (const std::uint32_t v : t)
                index[v] = 0;
    std::uint32_t kept = 0;
    for (std::size_t v = 0; v < positions.size(); ++v) {
        if (index[v] == kUnused) continue;
        index[v] = kept;
        positions[kept] = positions[v];
        quadrics[kept] = quadrics[v];
        normals[kept] = normals[v];
        held[kept] = held[v];
        removed[kept] = removed[v];
        ++kept;
    }
    for (auto* array : {&held, &removed})
        array->resize(kept);
    positions.resize(kept);
    quadrics.resize(kept);
    normals.resize(kept);
    std::size_t live = 0;
    for (const Triangle& t : triangles)
        if (t[0] != kRemoved) triangles[live++] = {index[t[0]], index[t[1]], index[t[2]]};
    triangles.resize(live);
    for (auto* array : {&positions, &normals})
        array->shrink_to_fit();
    quadrics.shrink_to_fit();
    triangles.shrink_to_fit();
    held.shrink_to_fit();
    removed.shrink_to_fit();
}

namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;
constexpr std::uint32_t kWithinAlready = 0xFFFFFFFEu; // a sample known within the tolerance (withinTolerance)
constexpr double kCreaseCosine = 0.8660254037844387; // 30 degrees

// What Collapser::addSamples relies on: the pattern's first nine samples
// are edge 0's, 1's and 2's, three each, going away from the edge's first
// vertex in the same steps on every edge; the rest are inside.
constexpr bool edgeSamplesComeInThrees()
{
    for (std::size_t k = 0; k < kTriangleSamples; ++k) {
        const TriangleSample& s = kTriangleSamplePattern[k];
        if (k >= 9) {
            if (s.edge != -1) return false;
            continue;
        }
        const int e = int(k / 3);
        if (s.edge != e || s.w[e] != kTriangleSamplePattern[k % 3].w[0] ||
            s.w[(e + 1) % 3] != kTriangleSamplePattern[k % 3].w[1] || s.w[(e + 2) % 3] != 0.0)
            return false;
    }
    // ... and the same points from either end (slot j from one is 2 - j from the other).
    for (std::size_t j = 0; j < 3; ++j)
        if (kTriangleSamplePattern[j].w[0] != kTriangleSamplePattern[2 - j].w[1]) return false;
    return true;
}
static_assert(edgeSamplesComeInThrees());

// The sequential simplifier. Each vertex keeps the list of its triangle
// corners (corner 3t + i is slot i of triangle t), linked through `next_`;
// removed triangles are unlinked lazily, when a list is walked.
class Collapser {
public:
    Collapser(CollapseMesh& mesh, const CollapseLimits& limits, SurfaceQueries& surface)
        : m_(mesh), limits_(limits), surface_(surface)
    {
        const std::size_t n = m_.positions.size();
        head_.assign(n, kNone);
        next_.assign(3 * m_.triangles.size(), kNone);
        for (std::uint32_t t = 0; t < m_.triangles.size(); ++t) {
            if (removed(t)) continue;
            for (std::uint32_t i = 0; i < 3; ++i) {
                const std::uint32_t v = m_.triangles[t][i];
                next_[3 * t + i] = head_[v];
                head_[v] = 3 * t + i;
            }
            if (!guarded_) continue;
            const auto [lo, hi] = boxOf(m_.triangles[t], kNone, glm::dvec3(0.0));
            grid_.insert(t, lo, hi);
        }
        // Obstacles after the triangles: tree entries from triangleCount_ on.
        triangleCount_ = std::uint32_t(m_.triangles.size());
        for (std::uint32_t i = 0; guarded_ && i < m_.obstacles.size(); ++i) {
            const auto& c = m_.obstacleCorners[i];
            grid_.insert(triangleCount_ + i, glm::min(c[0], glm::min(c[1], c[2])), glm::max(c[0], glm::max(c[1], c[2])));
        }
        stamp_.assign(n, 0);
        common_.assign(n, 0);
        touched_.assign(n, 0);
        dirty_.assign(n, 1);
    }

    std::size_t run(const Progress& work)
    {
        std::size_t total = 0;
        std::vector<Candidate> candidates;
        std::vector<std::uint32_t> touchedList, changedList;
        for (int pass = 0;; ++pass) {
            if (work.cancelled()) break;
            propose(candidates);
            if (candidates.empty()) break;
            std::sort(candidates.begin(), candidates.end());
            std::size_t made = 0;
            for (Candidate& c : candidates) {
                if (touched_[c.a] || touched_[c.b] || m_.removed[c.a] || m_.removed[c.b]) continue;
                // Two vertices of one sharp edge: b already has its place on
                // the edge between them (proposed so), and stays a feature vertex.
                glm::dvec3 normal(0.0);
                if (!c.onCrease) {
                    if (c.moves && !(std::abs(fieldAt(c.at)) <= limits_.placement)) {
                        // Off the surface (a curved patch, where the planes meet
                        // outside it): keep b where it is, if that is cheap enough.
                        c.at = m_.positions[c.b];
                        c.moves = false;
                        if (!(cost(c.a, c.b, c.at) <= limits_.maxMeanSquaredError)) continue;
                    }
                    normal = c.moves ? mergedNormal(c.a, c.b) : m_.normals[c.b];
                    if (c.moves && normal == glm::dvec3(0.0)) {
                        // Where the planes of two sheets meet: the vertex becomes
                        // a feature vertex only on the sharp edge itself (a point
                        // merely on the surface near it would stay off the edge).
                        const glm::dvec3 &na = m_.normals[c.a], &nb = m_.normals[c.b];
                        // (A vertex already on an edge or corner is not moved: its
                        // planes and a curved sheet's meet off the edge, at a
                        // point of the surface that is no corner.)
                        std::optional<glm::dvec3> onEdge;
                        if (na != glm::dvec3(0.0) && nb != glm::dvec3(0.0))
                            onEdge = surface_.snapToCrease(c.at, na, nb, glm::length(m_.positions[c.a] - m_.positions[c.b]));
                        if (onEdge && glm::length(*onEdge - c.at) <= limits_.placement) {
                            c.at = *onEdge;
                        } else {
                            c.at = m_.positions[c.b];
                            c.moves = false;
                            normal = m_.normals[c.b];
                            if (!(cost(c.a, c.b, c.at) <= limits_.maxMeanSquaredError)) continue;
                        }
                    }
                }
                if (!legal(c.a, c.b, c.at, normal, c.second)) continue;
                collapse(c.a, c.b, c.at, normal);
                if (!errors_.empty())
                    for (const auto& [t, e] : pending_)
                        errors_[t] = e;
                ++made;
                // Stale now: the proposals from or into a (gone) and b (its
                // quadric, place and normal changed). Every other proposal
                // of the pass keeps its cost and place (they depend on its
                // two vertices only), and legal() judges it on the mesh as
                // it is when its turn comes. (Skipping b's whole ring, as
                // before, threw away nine in ten proposals of a pass to be
                // made again, at the same cost, in the next.)
                // Where the collapse left a triangle beyond the tolerance
                // (allowed no further than the worst it replaced, where the
                // marching cubes are over it), the ring waits for the next
                // pass as before: taking its proposals in this pass's order
                // grew such triangles where the refinement could not mend
                // them (a thin shell at 1 mm cells kept 4 over 0.01 mm).
                const std::size_t from = changedList.size();
                markChanged(c.b, changedList);
                // (pending_ holds this collapse's triangles only where the
                // tolerance was checked; without a tolerance, as before.)
                bool over = !(limits_.tolerance > 0.0 && limits_.checkGeometry);
                for (const auto& [t, e] : pending_)
                    over = over || e > limits_.tolerance;
                auto touch = [&](std::uint32_t v) {
                    if (!touched_[v]) {
                        touched_[v] = 1;
                        touchedList.push_back(v);
                    }
                };
                touch(c.a);
                touch(c.b);
                if (over)
                    for (std::size_t k = from; k < changedList.size(); ++k)
                        touch(changedList[k]);
            }
            for (const std::uint32_t v : touchedList)
                touched_[v] = 0;
            for (const std::uint32_t v : changedList)
                dirty_[v] = 1; // its neighbourhood changed: propose again
            touchedList.clear();
            changedList.clear();
            total += made;
            if (made == 0) break;
        }
        return total;
    }

private:
    struct Candidate {
        double cost;
        std::uint32_t a, b;
        glm::dvec3 at; // b's position after the collapse
        bool moves;    // at differs from b's position
        bool second = false; // not a's cheapest: made only if it keeps its triangles within the tolerance
        bool onCrease = false; // a and b on one sharp edge, b moved along it (alongCrease)
        bool operator<(const Candidate& o) const { return cost < o.cost || (cost == o.cost && a < o.a); }
    };

    bool removed(std::uint32_t t) const { return m_.triangles[t][0] == kRemoved; }

    double fieldAt(const glm::dvec3& p) const
    {
        double f = 0.0;
        surface_.field(&p, 1, &f);
        return f;
    }

    // v's live triangles into `out`, unlinking removed ones from its list.
    void gather(std::uint32_t v, std::vector<std::uint32_t>& out)
    {
        out.clear();
        std::uint32_t* link = &head_[v];
        while (*link != kNone) {
            const std::uint32_t c = *link;
            if (removed(c / 3)) {
                *link = next_[c];
                continue;
            }
            out.push_back(c / 3);
            link = &next_[c];
        }
    }

    double cost(std::uint32_t a, std::uint32_t b, const glm::dvec3& p) const
    {
        return std::max(m_.quadrics[a].mean(p), m_.quadrics[b].mean(p));
    }

    // The normal of b after it moved to where a's and b's planes meet: none
    // (a feature) where they disagree.
    glm::dvec3 mergedNormal(std::uint32_t a, std::uint32_t b) const
    {
        const glm::dvec3 &na = m_.normals[a], &nb = m_.normals[b];
        if (na == glm::dvec3(0.0) || nb == glm::dvec3(0.0) || glm::dot(na, nb) < kCreaseCosine) return glm::dvec3(0.0);
        return glm::normalize(na + nb);
    }

    void propose(std::vector<Candidate>& out)
    {
        out.clear();
        for (std::uint32_t a = 0; a < m_.positions.size(); ++a) {
            if (!dirty_[a] || m_.removed[a] || m_.held[a]) continue;
            dirty_[a] = 0;
            gather(a, trisA_);
            neighbours_.clear();
            for (const std::uint32_t t : trisA_)
                for (const std::uint32_t u : m_.triangles[t])
                    if (u != a && !m_.held[u]) neighbours_.push_back(u);
            std::sort(neighbours_.begin(), neighbours_.end());
            neighbours_.erase(std::unique(neighbours_.begin(), neighbours_.end()), neighbours_.end());
            // Every half-edge collapse of a within the limit, and where the
            // planes of a and a neighbour meet (on a sharp edge between
            // them) unless a half-edge collapse is free (a flat).
            options_.clear();
            double cheapest = std::numeric_limits<double>::infinity();
            for (const std::uint32_t u : neighbours_) {
                if (limits_.maxEdgeLength > 0.0 && !(glm::length(m_.positions[u] - m_.positions[a]) < limits_.maxEdgeLength))
                    continue;
                const double c = cost(a, u, m_.positions[u]);
                cheapest = std::min(cheapest, c);
                if (c <= limits_.maxMeanSquaredError) options_.push_back({c, a, u, m_.positions[u], false});
            }
            const bool free = cheapest <= 1e-9 * limits_.maxMeanSquaredError;
            if (!free && limits_.placement > 0.0 && !(limits_.maxEdgeLength > 0.0)) {
                for (const std::uint32_t u : neighbours_) {
                    // Not between two points of one smooth sheet (normals
                    // within 30 degrees): their tangent planes meet off the
                    // sheet, where run() moves the vertex back to u, so the
                    // proposal only took one of a's four places from a
                    // half-edge collapse that could be made (the side
                    // chair: 7 % fewer triangles; docs/benchmarks.md).
                    if (mergedNormal(a, u) != glm::dvec3(0.0)) continue;
                    Quadric q = m_.quadrics[a];
                    q += m_.quadrics[u];
                    const glm::dvec3 mid = 0.5 * (m_.positions[a] + m_.positions[u]);
                    const glm::dvec3 x = q.minimizer(mid);
                    if (glm::length(x - mid) > glm::length(m_.positions[a] - m_.positions[u])) continue; // not local
                    const double c = cost(a, u, x);
                    if (c <= limits_.maxMeanSquaredError) options_.push_back({c, a, u, x, true});
                }
            }
            // Along a sharp edge: both vertices on it (no normal), b moved to
            // the edge between them. Half-edge collapses alone cannot thin
            // out evenly spaced vertices of a curved edge (the rim of a
            // hole): removing one doubles a gap, moving its neighbour
            // halfway makes two gaps of one and a half.
            if (m_.normals[a] == glm::dvec3(0.0) && limits_.placement > 0.0 && !(limits_.maxEdgeLength > 0.0))
                for (const std::uint32_t u : neighbours_) {
                    if (m_.normals[u] != glm::dvec3(0.0)) continue;
                    const std::optional<glm::dvec3> p = alongCrease(a, u);
                    if (!p) continue;
                    const double c = cost(a, u, *p);
                    if (c <= limits_.maxMeanSquaredError) {
                        Candidate along{c, a, u, *p, true};
                        along.onCrease = true;
                        along.second = true; // within the tolerance, always: it moves a sharp edge's vertex
                        options_.push_back(along);
                    }
                }
            // The cheapest, and up to three more in the same pass: a vertex
            // whose first proposal is refused (a fold, a crossing, a new
            // triangle off the surface) would otherwise wait until a
            // neighbour changes, and may never (a board at 0.1 mm cells kept
            // 5,362 triangles, 468 with these on flats; the walls of shelf-pin
            // holes kept columns of vertices whose cheapest collapse crossed
            // the curvature while one along the wall was free;
            // docs/benchmarks.md).
            const std::size_t keep = std::min<std::size_t>(options_.size(), 4);
            std::partial_sort(options_.begin(), options_.begin() + long(keep), options_.end(),
                              [](const Candidate& x, const Candidate& y) { return x.cost < y.cost; });
            // (The others only where they keep the tolerance: where the
            // marching cubes are over it, more collapses than the cheapest
            // left shapes the refinement could not split without folds.)
            for (std::size_t i = 1; i < keep; ++i)
                options_[i].second = true;
            out.insert(out.end(), options_.begin(), options_.begin() + long(keep));
        }
    }

    // The point of the sharp edge through a and b (a's star gathered in
    // trisA_) near their midpoint: the edge between the two sheets of a's
    // star whose normals differ most (more than 30 degrees).
    std::optional<glm::dvec3> alongCrease(std::uint32_t a, std::uint32_t b)
    {
        glm::dvec3 n1(0.0), n2(0.0);
        double smallest = kCreaseCosine;
        for (const std::uint32_t t : trisA_)
            for (const std::uint32_t v : m_.triangles[t]) {
                const glm::dvec3& nv = m_.normals[v];
                if (nv == glm::dvec3(0.0)) continue;
                for (const std::uint32_t s : trisA_)
                    for (const std::uint32_t w : m_.triangles[s]) {
                        const glm::dvec3& nw = m_.normals[w];
                        if (nw == glm::dvec3(0.0) || !(glm::dot(nv, nw) < smallest)) continue;
                        smallest = glm::dot(nv, nw);
                        n1 = nv;
                        n2 = nw;
                    }
            }
        if (n1 == glm::dvec3(0.0)) return std::nullopt;
        const glm::dvec3 mid = 0.5 * (m_.positions[a] + m_.positions[b]);
        const double length = glm::length(m_.positions[a] - m_.positions[b]);
        const std::optional<glm::dvec3> p = surface_.snapToCrease(mid, n1, n2, length);
        if (!p || !(glm::length(*p - mid) <= 0.5 * length)) return std::nullopt;
        return p;
    }

    // How well a triangle faces the way the surface does at its vertices:
    // the smallest cosine between its normal and theirs (1 when none has one).
    double facing(const glm::dvec3& normal, double length, const glm::dvec3* vertexNormals) const
    {
        double worst = 1.0;
        for (int k = 0; k < 3; ++k)
            if (vertexNormals[k] != glm::dvec3(0.0))
                worst = std::min(worst, glm::dot(normal, vertexNormals[k]) / length);
        return worst;
    }

    // Whether triangle `tri`, with vertex `moved` taking position `to` and
    // normal `toNormal`, stays a proper approximation: it turns by less than
    // the limit, keeps a height, and faces the way the surface does at its
    // vertices (or at least no worse than before, for a triangle that
    // already leaned: collapses that mend a cut-off sharp edge must pass).
    bool keepsShape(const Triangle& tri, std::uint32_t moved, const glm::dvec3& to, const glm::dvec3& toNormal) const
    {
        glm::dvec3 q[3] = {m_.positions[tri[0]], m_.positions[tri[1]], m_.positions[tri[2]]};
        glm::dvec3 n[3] = {m_.normals[tri[0]], m_.normals[tri[1]], m_.normals[tri[2]]};
        const glm::dvec3 before = glm::cross(q[1] - q[0], q[2] - q[0]);
        const double lengthBefore = glm::length(before);
        const double facingBefore = facing(before, lengthBefore, n);
        for (int k = 0; k < 3; ++k)
            if (tri[std::size_t(k)] == moved) {
                q[k] = to;
                n[k] = toNormal;
            }
        const glm::dvec3 after = glm::cross(q[1] - q[0], q[2] - q[0]);
        const double lengthAfter = glm::length(after);
        if (!(glm::dot(before, after) >= limits_.minNormalCosine * lengthBefore * lengthAfter)) return false;
        const double longest =
            std::max({glm::length(q[1] - q[0]), glm::length(q[2] - q[1]), glm::length(q[0] - q[2])});
        if (!(lengthAfter > limits_.minHeight * longest)) return false; // twice the area over the longest edge
        const double facingAfter = facing(after, lengthAfter, n);
        return facingAfter >= std::min(limits_.minSurfaceCosine, facingBefore);
    }

    // Vertex positions with `moved` at `to`.
    glm::dvec3 position(std::uint32_t v, std::uint32_t moved, const glm::dvec3& to) const
    {
        return v == moved ? to : m_.positions[v];
    }
    std::pair<glm::dvec3, glm::dvec3> boxOf(const Triangle& tri, std::uint32_t moved, const glm::dvec3& to) const
    {
        glm::dvec3 lo = position(tri[0], moved, to), hi = lo;
        for (int k = 1; k < 3; ++k) {
            lo = glm::min(lo, position(tri[std::size_t(k)], moved, to));
            hi = glm::max(hi, position(tri[std::size_t(k)], moved, to));
        }
        return {lo, hi};
    }

    // Whether a triangle the collapse leaves (a's become b's, b at `at`)
    // would cross one that is not around a or b: on a thin part or in a
    // narrow gap a collapse can push a triangle through the other side, and
    // a crossing mesh does not bound a solid.
    bool wouldCross(std::uint32_t a, std::uint32_t b, const glm::dvec3& at)
    {
        changed_.clear();
        for (const std::uint32_t t : trisA_) {
            Triangle tri = m_.triangles[t];
            if (tri[0] == b || tri[1] == b || tri[2] == b) continue;
            for (std::uint32_t& u : tri)
                if (u == a) u = b;
            changed_.push_back(tri);
        }
        if (at != m_.positions[b])
            for (const std::uint32_t t : trisB_) {
                const Triangle& tri = m_.triangles[t];
                if (tri[0] != a && tri[1] != a && tri[2] != a) changed_.push_back(tri);
            }
        const bool moves = at != m_.positions[b];
        added_.clear();
        for (const Triangle& tri : changed_)
            added_.push_back({tri, {position(tri[0], b, at), position(tri[1], b, at), position(tri[2], b, at)}});
        const bool crossing = anyCrossesInGrid(
            grid_, added_.data(), added_.size(), limits_.clearance,
            [&](std::uint32_t t) {
                if (t < triangleCount_ && removed(t)) return true;
                const Triangle& other = t < triangleCount_ ? m_.triangles[t] : m_.obstacles[t - triangleCount_];
                auto has = [&](std::uint32_t v) { return other[0] == v || other[1] == v || other[2] == v; };
                // a's triangles are replaced by changed_; b's are too
                // when b moves. b's that stay put are checked: a new
                // triangle of b's fan can fold over one of them.
                return has(a) || (moves && has(b));
            },
            [&](std::uint32_t t, glm::dvec3(&q)[3]) {
                if (t >= triangleCount_) {
                    const auto& c = m_.obstacleCorners[t - triangleCount_];
                    for (int k = 0; k < 3; ++k)
                        q[k] = c[std::size_t(k)];
                    return m_.obstacles[t - triangleCount_];
                }
                const Triangle& other = m_.triangles[t];
                for (int k = 0; k < 3; ++k)
                    q[k] = m_.positions[other[std::size_t(k)]];
                return other;
            });
        return crossing || newTrianglesTooClose(added_.data(), added_.size(), limits_.clearance);
    }

    bool legal(std::uint32_t a, std::uint32_t b, const glm::dvec3& at, const glm::dvec3& normal, bool strict)
    {
        gather(a, trisA_);
        // The edge's two triangles and their third vertices.
        int shared = 0;
        std::uint32_t c = kNone, d = kNone;
        for (const std::uint32_t t : trisA_) {
            const Triangle& tri = m_.triangles[t];
            if (tri[0] != b && tri[1] != b && tri[2] != b) continue;
            ++shared;
            for (const std::uint32_t u : tri)
                if (u != a && u != b) (c == kNone ? c : d) = u;
        }
        if (shared != 2 || c == kNone || d == kNone || c == d) return false;
        // Link condition: a and b share exactly the neighbours c and d.
        if (++clock_ == 0) { // the clock wrapped: clear the stamps
            std::fill(stamp_.begin(), stamp_.end(), 0);
            std::fill(common_.begin(), common_.end(), 0);
            clock_ = 1;
        }
        for (const std::uint32_t t : trisA_)
            for (const std::uint32_t u : m_.triangles[t])
                if (u != a) stamp_[u] = clock_;
        gather(b, trisB_);
        int common = 0;
        for (const std::uint32_t t : trisB_)
            for (const std::uint32_t u : m_.triangles[t])
                if (u != a && u != b && stamp_[u] == clock_ && common_[u] != clock_) {
                    common_[u] = clock_;
                    ++common;
                }
        if (common != 2) return false;
        // c and d each lose a triangle: they must keep three.
        gather(c, trisC_);
        if (trisC_.size() <= 3) return false;
        gather(d, trisC_);
        if (trisC_.size() <= 3) return false;
        if (limits_.maxEdgeAfter > 0.0) {
            // Edges at b's new place: a's (now b's), and b's own when b moves.
            auto tooLong = [&](const std::vector<std::uint32_t>& tris) {
                for (const std::uint32_t t : tris)
                    for (const std::uint32_t u : m_.triangles[t])
                        if (u != a && u != b && !(glm::length(m_.positions[u] - at) <= limits_.maxEdgeAfter))
                            return true;
                return false;
            };
            if (tooLong(trisA_) || (at != m_.positions[b] && tooLong(trisB_))) return false;
        }
        if (!limits_.checkGeometry) return true;
        // Geometry of every triangle that stays: a's become b's at `at`, and
        // b's own move with b.
        for (const std::uint32_t t : trisA_) {
            const Triangle& tri = m_.triangles[t];
            if (tri[0] == b || tri[1] == b || tri[2] == b) continue;
            if (!keepsShape(tri, a, at, normal)) return false;
        }
        const bool moves = at != m_.positions[b];
        if (moves) {
            for (const std::uint32_t t : trisB_) {
                const Triangle& tri = m_.triangles[t];
                if (tri[0] == a || tri[1] == a || tri[2] == a) continue;
                if (!keepsShape(tri, b, at, normal)) return false;
            }
        }
        if (limits_.tolerance > 0.0 && !withinTolerance(a, b, at, normal, moves, strict)) return false;
        if (!guarded_) return true;
        return (!moves && retilesItsPlane(a, b)) || !wouldCross(a, b, at);
    }

    // Whether the half-edge collapse of a into b only re-tiles a flat
    // polygon: a's star lies in one plane (every vertex on a's plane, with
    // a's normal) and every triangle of b's new fan faces the same way. The
    // fan then covers exactly the polygon a's star covered (the loop around
    // it winds once about each of its points and every fan triangle counts
    // +1), so no triangle elsewhere is crossed or approached that was not
    // before, and the crossing and clearance tests (half of all the
    // simplifier's time on board faces) have nothing to find.
    bool retilesItsPlane(std::uint32_t a, std::uint32_t b) const
    {
        constexpr double kOffPlane = 1e-9; // mm
        const glm::dvec3 n = m_.normals[a];
        if (n == glm::dvec3(0.0)) return false;
        const glm::dvec3 origin = m_.positions[a];
        for (const std::uint32_t t : trisA_) {
            const Triangle& tri = m_.triangles[t];
            for (const std::uint32_t v : tri)
                if (v != a && (!(glm::dot(m_.normals[v], n) > 1.0 - 1e-12) ||
                               !(std::abs(glm::dot(m_.positions[v] - origin, n)) <= kOffPlane)))
                    return false;
            if (tri[0] == b || tri[1] == b || tri[2] == b) continue;
            const glm::dvec3 q[3] = {position(tri[0], a, m_.positions[b]), position(tri[1], a, m_.positions[b]),
                                     position(tri[2], a, m_.positions[b])};
            if (!(glm::dot(glm::cross(q[1] - q[0], q[2] - q[0]), n) > 0.0)) return false;
        }
        return true;
    }

    // The sample points of a new triangle (corners q; vertex ids id, as
    // they will be after the collapse) go to samples_, the index of each of
    // its kTriangleSamples to sampleIndex_. Two savings that leave every
    // decision as sampling each triangle whole would:
    //  - an edge two new triangles share (a spoke of b's new fan) is
    //    sampled once: the pattern's points on an edge are the same points
    //    from either end (weights 1/4, 1/2, 3/4), bit for bit;
    //  - edge `withinAlready` (>= 0) is the edge that stayed where it was
    //    of a triangle sampled within the tolerance: its points are within
    //    it and get kWithinAlready. The new triangle's recorded error is then
    //    the worst of its other samples, which says the same as the whole
    //    worst wherever it is used (against the tolerance, or as the
    //    largest of it and the tolerance).
    void addSamples(const glm::dvec3 (&q)[3], const std::uint32_t (&id)[3], int withinAlready)
    {
        for (std::size_t k = 0; k < kTriangleSamples; ++k) {
            const TriangleSample& s = kTriangleSamplePattern[k];
            if (s.edge >= 0 && s.edge == withinAlready) {
                sampleIndex_.push_back(kWithinAlready);
                continue;
            }
            if (s.edge < 0) {
                sampleIndex_.push_back(std::uint32_t(samples_.size()));
                samples_.push_back(s.w[0] * q[0] + s.w[1] * q[1] + s.w[2] * q[2]);
                continue;
            }
            // Edge e's three samples, counted from its lower vertex id.
            const std::uint32_t from = id[s.edge], to = id[(s.edge + 1) % 3];
            const std::uint64_t key = std::uint64_t(std::min(from, to)) << 32 | std::max(from, to);
            const std::size_t along = k % 3; // 0, 1, 2 from vertex e
            const std::size_t slot = from < to ? along : 2 - along;
            std::uint32_t first = kNone;
            for (const auto& [edge, index] : sampledEdges_)
                if (edge == key) first = index;
            if (first == kNone) {
                // This edge's first triangle: its points in the canonical order.
                first = std::uint32_t(samples_.size());
                sampledEdges_.push_back({key, first});
                const glm::dvec3 lo = from < to ? q[s.edge] : q[(s.edge + 1) % 3];
                const glm::dvec3 hi = from < to ? q[(s.edge + 1) % 3] : q[s.edge];
                for (std::size_t j = 0; j < 3; ++j) // edge 0's three, vertex 0 as lo
                    samples_.push_back(kTriangleSamplePattern[j].w[0] * lo + kTriangleSamplePattern[j].w[1] * hi);
            }
            sampleIndex_.push_back(first + std::uint32_t(slot));
        }
    }

    // Whether every triangle the collapse makes lies within the tolerance of
    // the exact surface at its samples, or, where the mesh is over the
    // tolerance already (a marching-cubes mesh coarser than the curvature
    // asks), no further from it than the triangles it replaces (a sliver
    // goes) and, off a smooth patch, no longer than the longest of them
    // over the tolerance (a cut-off edge does not spread); `strict`: within
    // the tolerance, whatever was there. Inside a plane nothing is sampled.
    // The new triangles' errors are kept for the commit (pending_).
    // Whether v is a corner of the part: a feature vertex whose triangles
    // face three independent ways (a box's corner; not a vertex of an edge
    // between two sheets, nor of a hole's rim, whose wall turns little
    // from one triangle to the next).
    bool isCorner(std::uint32_t v)
    {
        if (m_.normals[v] != glm::dvec3(0.0)) return false;
        gather(v, cornerTris_);
        double a[3][3] = {};
        for (const std::uint32_t t : cornerTris_) {
            const Triangle& tri = m_.triangles[t];
            const glm::dvec3 n = glm::cross(m_.positions[tri[1]] - m_.positions[tri[0]],
                                            m_.positions[tri[2]] - m_.positions[tri[0]]);
            const double length = glm::length(n);
            if (!(length > 0.0)) continue;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    a[r][c] += n[r] * n[c] / (length * length);
        }
        double w[3], vectors[3][3];
        symmetricEigen(a, w, vectors);
        const double largest = std::max({w[0], w[1], w[2]}), smallest = std::min({w[0], w[1], w[2]});
        return smallest > 0.2 * largest;
    }

    // Whether the triangles made (made3_) pass within the tolerance of a
    // corner's place (any other vertex: true). Only corners: held to this,
    // every vertex of an edge or a rim kept collapses from the places the
    // refinement mends, and a flush hole's rim was left 0.085 mm off.
    bool keepsCorner(std::uint32_t v)
    {
        if (!isCorner(v)) return true;
        const glm::dvec3 p = m_.positions[v];
        for (const auto& tri : made3_)
            if (pointTriangleDistance(p, tri[0], tri[1], tri[2]) <= limits_.tolerance) return true;
        return false;
    }

    bool withinTolerance(std::uint32_t a, std::uint32_t b, const glm::dvec3& at, const glm::dvec3& normal, bool moves,
                         bool strict)
    {
        const glm::dvec3 n = m_.normals[a];
        bool planar = n != glm::dvec3(0.0) && normal != glm::dvec3(0.0) && glm::dot(n, normal) > 1.0 - 1e-12;
        samples_.clear();
        sampleIndex_.clear();
        sampledEdges_.clear();
        pending_.clear();
        made_.clear();
        made3_.clear();
        replaced_.clear();
        auto add = [&](std::uint32_t t, std::uint32_t moved) {
            const Triangle& tri = m_.triangles[t];
            glm::dvec3 q[3];
            std::uint32_t id[3]; // after the collapse: a is b
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = tri[std::size_t(k)];
                q[k] = v == moved ? at : m_.positions[v];
                id[k] = v == a ? b : v;
                if (planar && v != moved && !(glm::dot(m_.normals[v], n) > 1.0 - 1e-12)) planar = false;
            }
            // The edge away from the moved vertex stays where it was: if t's
            // samples were all within the tolerance, so are that edge's.
            int kept = -1;
            if (!errors_.empty() && errors_[t] >= 0.0 && errors_[t] <= limits_.tolerance)
                for (int e = 0; e < 3; ++e)
                    if (tri[std::size_t(e)] != moved && tri[std::size_t(e + 1) % 3] != moved) kept = e;
            addSamples(q, id, kept);
            made3_.push_back({q[0], q[1], q[2]});
            pending_.push_back({t, 0.0});
            replaced_.push_back(t);
            // Whether the new triangle lies on a smooth patch: every two of
            // its vertices' normals within 30 degrees.
            bool smooth = true;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = tri[std::size_t(k)], w = tri[std::size_t(k + 1) % 3];
                const glm::dvec3 nv = v == moved ? normal : m_.normals[v], nw = w == moved ? normal : m_.normals[w];
                if (nv == glm::dvec3(0.0) || !(glm::dot(nv, nw) >= kCreaseCosine)) smooth = false;
            }
            made_.push_back({longestEdge(q[0], q[1], q[2]), smooth});
        };
        for (const std::uint32_t t : trisA_) {
            const Triangle& tri = m_.triangles[t];
            if (tri[0] != b && tri[1] != b && tri[2] != b) add(t, a);
            else replaced_.push_back(t);
        }
        if (moves)
            for (const std::uint32_t t : trisB_) {
                const Triangle& tri = m_.triangles[t];
                if (tri[0] != a && tri[1] != a && tri[2] != a) add(t, b);
            }
        if (planar) {
            for (auto& p : pending_)
                p.second = -1.0; // unknown, and no worse than before
            return true;
        }
        // A corner of the part, gone (a) or moved (b): the new triangles must
        // pass within the tolerance of where it was. The samples over the
        // triangles measure the other way only, and let a box's corner slide
        // 0.06 mm down its edge at 0.05 mm (every sample of the tilted top
        // within 0.046 mm).
        if (!keepsCorner(a) || (moves && !keepsCorner(b))) return false;
        values_.resize(samples_.size());
        surface_.distances(samples_.data(), samples_.size(), limits_.tolerance, values_.data());
        // Beyond the tolerance, no further than the worst triangle replaced
        // (unless strict): found only when a sample is beyond it, since the
        // replaced triangles' errors cost as many samples as the new ones.
        double before = -1.0;
        auto allows = [&](double v) {
            if (v <= limits_.tolerance) return true;
            if (strict) return false;
            if (before < 0.0) {
                before = 0.0;
                for (const std::uint32_t t : replaced_)
                    before = std::max(before, error(t));
            }
            return v <= before;
        };
        // The longest edge of the triangles around a and b over the
        // tolerance, found when first needed (few collapses need it).
        double longestOver = -1.0;
        auto longestOverTolerance = [&] {
            if (longestOver >= 0.0) return longestOver;
            longestOver = 0.0;
            for (const auto* list : {&trisA_, &trisB_})
                for (const std::uint32_t t : *list)
                    if (error(t) > limits_.tolerance) {
                        const Triangle& tri = m_.triangles[t];
                        longestOver = std::max(longestOver, longestEdge(m_.positions[tri[0]], m_.positions[tri[1]],
                                                                        m_.positions[tri[2]]));
                    }
            return longestOver;
        };
        for (std::size_t i = 0; i < pending_.size(); ++i) {
            double worst = 0.0;
            for (std::size_t k = 0; k < kTriangleSamples; ++k) {
                const std::uint32_t sample = sampleIndex_[i * kTriangleSamples + k];
                if (sample == kWithinAlready) continue;
                const double v = std::abs(values_[sample]);
                if (!allows(v)) return false;
                worst = std::max(worst, v);
            }
            // Beyond the tolerance, a triangle off a smooth patch does not
            // grow: the refinement mends a long triangle on a smooth patch by
            // splits across it, but a cut-off sharp edge that grows becomes
            // a fan from a vertex off the edge to the far face that no split
            // mends without folding a neighbour (a board 18 x 100 x 100 at
            // 1 mm cells: 11 triangles 0.22 mm off at 0.01 mm; with this
            // rule none, docs/benchmarks.md).
            if (worst > limits_.tolerance && !made_[i].smooth && !(made_[i].longest <= longestOverTolerance()))
                return false;
            pending_[i].second = worst;
        }
        return true;
    }

    static double longestEdge(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
    {
        return std::sqrt(std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)}));
    }

    // The sampled error of triangle t as it is now, computed when first asked.
    double error(std::uint32_t t)
    {
        if (errors_.empty()) errors_.assign(m_.triangles.size(), -1.0);
        if (errors_[t] >= 0.0) return errors_[t];
        const Triangle& tri = m_.triangles[t];
        errorSamples_.clear();
        appendTriangleSamples(m_.positions[tri[0]], m_.positions[tri[1]], m_.positions[tri[2]], errorSamples_);
        double values[kTriangleSamples];
        surface_.distances(errorSamples_.data(), kTriangleSamples, limits_.tolerance, values);
        double worst = 0.0;
        for (const double v : values)
            worst = std::max(worst, std::isfinite(v) ? std::abs(v) : 1e300);
        return errors_[t] = worst;
    }

    void collapse(std::uint32_t a, std::uint32_t b, const glm::dvec3& at, const glm::dvec3& normal)
    {
        gather(a, trisA_);
        gather(b, trisB_);
        // Every triangle around a or b leaves the grid; those that stay come
        // back at their new place.
        for (const auto* list : {&trisA_, &trisB_})
            for (const std::uint32_t t : *list) {
                if (!guarded_) break;
                const auto [lo, hi] = boxOf(m_.triangles[t], kNone, glm::dvec3(0.0));
                grid_.erase(t, lo, hi);
            }
        for (const std::uint32_t t : trisA_) {
            Triangle& tri = m_.triangles[t];
            if (tri[0] == b || tri[1] == b || tri[2] == b) {
                tri[0] = kRemoved;
                continue;
            }
            for (std::uint32_t& u : tri)
                if (u == a) u = b;
        }
        // a's live corners now hold b: move them to b's list.
        for (std::uint32_t c = head_[a]; c != kNone;) {
            const std::uint32_t following = next_[c];
            if (!removed(c / 3)) {
                next_[c] = head_[b];
                head_[b] = c;
            }
            c = following;
        }
        head_[a] = kNone;
        m_.quadrics[b] += m_.quadrics[a];
        m_.positions[b] = at;
        m_.normals[b] = normal;
        m_.removed[a] = 1;
        gather(b, trisB_);
        for (const std::uint32_t t : trisB_) {
            if (!guarded_) break;
            const auto [lo, hi] = boxOf(m_.triangles[t], kNone, glm::dvec3(0.0));
            grid_.insert(t, lo, hi);
        }
    }

    // b and its ring (a's old ring is in it after the collapse) to `list`.
    void markChanged(std::uint32_t b, std::vector<std::uint32_t>& list)
    {
        gather(b, trisB_);
        for (const std::uint32_t t : trisB_)
            for (const std::uint32_t u : m_.triangles[t])
                list.push_back(u);
    }

    CollapseMesh& m_;
    CollapseLimits limits_;
    SurfaceQueries& surface_;
    std::vector<std::uint32_t> head_, next_;
    std::vector<std::uint32_t> stamp_, common_;
    std::uint32_t clock_ = 0;
    std::vector<std::uint8_t> touched_, dirty_;
    std::vector<std::uint32_t> trisA_, trisB_, trisC_, neighbours_;
    std::vector<Candidate> options_; // one vertex's collapses within the limit (propose)
    // The triangles' tree, for the crossing guard: only where the geometry
    // is checked (the micro passes, which check none, would otherwise build
    // one of every marching-cubes triangle: 2.5 GB of the side chair's
    // 4.1 GB peak at 0.5 mm).
    bool guarded_ = limits_.checkGeometry && limits_.guardCrossings;
    TriangleTree grid_;
    std::uint32_t triangleCount_ = 0; // tree entries from here on are obstacles
    std::vector<Triangle> changed_;
    std::vector<NewTriangle> added_; // changed_ with their corners, for the crossing guard
    std::vector<glm::dvec3> samples_, errorSamples_;
    std::vector<std::uint32_t> sampleIndex_;                        // per new triangle, its 13 samples in samples_
    std::vector<std::pair<std::uint64_t, std::uint32_t>> sampledEdges_; // (edge's vertex ids, its first sample)
    std::vector<std::uint32_t> replaced_;                           // the triangles the collapse removes or remakes
    std::vector<double> values_;
    std::vector<double> errors_;                              // per triangle: sampled error, -1 unknown
    std::vector<std::pair<std::uint32_t, double>> pending_; // the checked collapse's triangles and their errors
    struct Made {
        double longest; // mm: its longest edge
        bool smooth;    // every two of its vertices' normals within 30 degrees
    };
    std::vector<Made> made_;
    std::vector<std::array<glm::dvec3, 3>> made3_; // the checked collapse's new triangles, where they are
    std::vector<std::uint32_t> cornerTris_;
};

} // namespace

std::size_t collapseEdges(CollapseMesh& mesh, const CollapseLimits& limits, SurfaceQueries& surface,
                          const Progress& work)
{
    if (mesh.removed.size() != mesh.positions.size()) mesh.removed.assign(mesh.positions.size(), 0);
    if (mesh.held.size() != mesh.positions.size()) mesh.held.assign(mesh.positions.size(), 0);
    return Collapser(mesh, limits, surface).run(work);
}

namespace {

// Whether a live triangle of `mesh` crosses or comes within `clearance` of
// another live triangle or of an obstacle (TriangleClearance.hpp's rule,
// which the guard applies to every triangle a collapse makes). Only pairs
// with a triangle that `changed` marks are tested (all where it is empty):
// a pair of triangles both as they were before the collapses was there for
// the guard too, which keeps new triangles clear of old ones and cannot
// undo such a pair. (After the first pass most of the mesh is untouched:
// testing its flat neighbours again was most of the check.)
bool anyTrianglesTooClose(const CollapseMesh& mesh, double clearance, const std::vector<std::uint8_t>& changed = {})
{
    const std::uint32_t n = std::uint32_t(mesh.triangles.size());
    auto corners = [&](std::uint32_t t, glm::dvec3 (&q)[3]) -> const Triangle& {
        if (t >= n) {
            for (int k = 0; k < 3; ++k)
                q[k] = mesh.obstacleCorners[t - n][std::size_t(k)];
            return mesh.obstacles[t - n];
        }
        for (int k = 0; k < 3; ++k)
            q[k] = mesh.positions[mesh.triangles[t][std::size_t(k)]];
        return mesh.triangles[t];
    };
    auto boxOf = [&](std::uint32_t t) {
        glm::dvec3 q[3];
        corners(t, q);
        return std::pair{glm::min(q[0], glm::min(q[1], q[2])) - glm::dvec3(clearance),
                         glm::max(q[0], glm::max(q[1], q[2])) + glm::dvec3(clearance)};
    };
    TriangleTree tree;
    for (std::uint32_t t = 0; t < n + mesh.obstacles.size(); ++t) {
        if (t < n && mesh.triangles[t][0] == kRemoved) continue;
        const auto [lo, hi] = boxOf(t);
        tree.insert(t, lo, hi);
    }
    auto tested = [&](std::uint32_t t) { return changed.empty() || (t < n && changed[t]); };
    for (std::uint32_t t = 0; t < n; ++t) {
        if (mesh.triangles[t][0] == kRemoved || !tested(t)) continue;
        glm::dvec3 a[3];
        const Triangle& A = corners(t, a);
        const auto [lo, hi] = boxOf(t);
        bool found = false;
        tree.query(lo, hi, [&](std::uint32_t u) {
            if (found || u == t || (u < t && tested(u))) return; // each pair once; obstacles come after every triangle
            glm::dvec3 b[3];
            const Triangle& B = corners(u, b);
            found = trianglesTooClose(A, a, B, b, clearance);
        });
        if (found) return true;
    }
    return false;
}

} // namespace

std::size_t collapseEdgesCheckedAfter(CollapseMesh& mesh, const CollapseLimits& limits, SurfaceQueries& surface,
                                      const Progress& work, CrossingChecks* checks)
{
    if (!limits.checkGeometry || !limits.guardCrossings) return collapseEdges(mesh, limits, surface, work);
    CollapseMesh attempt = mesh;
    CollapseLimits unguarded = limits;
    unguarded.guardCrossings = false;
    const std::size_t made = collapseEdges(attempt, unguarded, surface, work);
    if (work.cancelled()) return 0;
    if (checks) ++checks->checked;
    std::vector<std::uint8_t> changed(attempt.triangles.size(), 0);
    for (std::size_t t = 0; t < changed.size(); ++t) {
        const Triangle& now = attempt.triangles[t];
        if (now[0] == kRemoved) continue;
        changed[t] = now != mesh.triangles[t] || attempt.positions[now[0]] != mesh.positions[now[0]] ||
                     attempt.positions[now[1]] != mesh.positions[now[1]] ||
                     attempt.positions[now[2]] != mesh.positions[now[2]];
    }
    if (!anyTrianglesTooClose(attempt, limits.clearance, changed)) {
        mesh = std::move(attempt);
        return made;
    }
    if (checks) ++checks->redone;
    return collapseEdges(mesh, limits, surface, work);
}

std::size_t collapsePartitioned(CollapseMesh& mesh, const CollapseLimits& limits, double cube, const glm::dvec3& shift,
                                tbb::task_arena& arena, SurfaceQueries& surface, const Progress& work,
                                CrossingChecks* checks, const CollapseLimits* beforehand)
{
    const std::size_t vertexCount = mesh.positions.size();
    if (mesh.removed.size() != vertexCount) mesh.removed.assign(vertexCount, 0);
    if (mesh.held.size() != vertexCount) mesh.held.assign(vertexCount, 0);
    // Each live triangle goes to the cube of its centroid.
    struct Keyed {
        std::uint64_t cube;
        std::uint32_t triangle;
        bool operator<(const Keyed& o) const { return cube < o.cube || (cube == o.cube && triangle < o.triangle); }
    };
    // Keyed and sorted on the arena's threads (the first pass sorts the
    // whole marching-cubes mesh: 9.5 M triangles for the side chair at
    // 0.5 mm, 1.2 s on one thread). Removed triangles get a key above any
    // cube's and are cut off the end; the keys are unique, so the order is
    // the one a sequential sort gives.
    constexpr std::uint64_t kRemovedKey = ~std::uint64_t(0);
    std::vector<Keyed> order(mesh.triangles.size());
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(mesh.triangles.size()), 4096),
                          [&](const tbb::blocked_range<std::uint32_t>& r) {
            for (std::uint32_t t = r.begin(); t != r.end(); ++t) {
                const Triangle& tri = mesh.triangles[t];
                if (tri[0] == kRemoved) {
                    order[t] = {kRemovedKey, t};
                    continue;
                }
                const glm::dvec3 centroid =
                    (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
                const glm::dvec3 q = glm::floor((centroid - shift) / cube);
                // 21 bits per axis (cubes are large against any part): wrap-around only merges far cubes, which is harmless.
                auto bits = [](double v) { return std::uint64_t(std::int64_t(v) & 0x1FFFFF); };
                order[t] = {bits(q.x) | bits(q.y) << 21 | bits(q.z) << 42, t};
            }
        });
    });
    // A vertex whose triangles lie in two cubes is held still by both.
    constexpr std::uint64_t kUnset = ~std::uint64_t(0);
    std::vector<std::uint64_t> cubeOf(vertexCount, kUnset);
    std::vector<std::uint8_t> straddles(vertexCount, 0);
    arena.execute([&] { tbb::parallel_sort(order.begin(), order.end()); });
    while (!order.empty() && order.back().cube == kRemovedKey)
        order.pop_back();
    for (const Keyed& k : order)
        for (const std::uint32_t v : mesh.triangles[k.triangle]) {
            if (cubeOf[v] == kUnset)
                cubeOf[v] = k.cube;
            else if (cubeOf[v] != k.cube)
                straddles[v] = 1;
        }
    std::vector<std::pair<std::size_t, std::size_t>> groups;
    for (std::size_t first = 0; first < order.size();) {
        std::size_t last = first;
        while (last < order.size() && order[last].cube == order[first].cube)
            ++last;
        groups.emplace_back(first, last);
        first = last;
    }
    // Cubes side by side are never simplified together: eight phases, by
    // the parity of the cube's coordinates, and each cube's collapses kept
    // from crossing its 26 neighbours' triangles (which stand still while
    // it works: they are of other phases). Without them a collapse at a
    // cube's face could push a triangle through a thin board's other side
    // lying in the next cube.
    constexpr std::uint64_t kAxis = 0x1FFFFF;
    auto colour = [](std::uint64_t key) {
        return int((key & 1) | ((key >> 21) & 1) << 1 | ((key >> 42) & 1) << 2);
    };
    std::unordered_map<std::uint64_t, std::size_t> groupOf;
    for (std::size_t g = 0; g < groups.size(); ++g)
        groupOf[order[groups[g].first].cube] = g;
    auto neighbour = [](std::uint64_t key, int dx, int dy, int dz) {
        auto axis = [&](int bit, int d) { return ((((key >> bit) & kAxis) + std::uint64_t(std::int64_t(d))) & kAxis) << bit; };
        return axis(0, dx) | axis(21, dy) | axis(42, dz);
    };
    std::vector<std::vector<std::size_t>> phases(8);
    for (std::size_t g = 0; g < groups.size(); ++g)
        phases[std::size_t(colour(order[groups[g].first].cube))].push_back(g);
    CollapseLimits cubeLimits = limits;
    cubeLimits.maxEdgeAfter = 0.25 * cube;
    std::atomic<std::size_t> total{0};
    std::atomic<std::size_t> checked{0}, redone{0};
    // Progress: the share of the triangles whose cube is done (cubes are
    // small against the mesh, so the fraction moves steadily).
    std::atomic<std::size_t> trianglesDone{0};
    // Each thread's map from the mesh's vertex numbers to its cube's (kNone
    // where the cube has no such vertex; set back after each cube).
    constexpr std::uint32_t kNone = ~std::uint32_t(0);
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> localMaps;
    const bool needsObstacles = limits.checkGeometry && limits.guardCrossings;
    for (const std::vector<std::size_t>& phase : phases)
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), phase.size(), [&](std::size_t member) {
            if (work.cancelled()) return;
            const std::size_t g = phase[member];
            const auto [first, last] = groups[g];
            // The cube's vertices, numbered locally in the mesh's order (the
            // collapser breaks ties by index).
            std::vector<std::uint32_t>& localOf = localMaps.local();
            if (localOf.size() != vertexCount) localOf.assign(vertexCount, kNone);
            std::vector<std::uint32_t> global;
            for (std::size_t k = first; k < last; ++k)
                for (const std::uint32_t v : mesh.triangles[order[k].triangle])
                    if (localOf[v] == kNone) {
                        localOf[v] = 0;
                        global.push_back(v);
                    }
            std::sort(global.begin(), global.end());
            for (std::uint32_t l = 0; l < global.size(); ++l)
                localOf[global[l]] = l;
            auto local = [&](std::uint32_t v) { return localOf[v]; };
            CollapseMesh part;
            part.positions.reserve(global.size());
            part.quadrics.reserve(global.size());
            part.normals.reserve(global.size());
            part.held.reserve(global.size());
            for (const std::uint32_t v : global) {
                part.positions.push_back(mesh.positions[v]);
                part.quadrics.push_back(mesh.quadrics[v]);
                part.normals.push_back(mesh.normals[v]);
                part.held.push_back(std::uint8_t(mesh.held[v] || straddles[v]));
            }
            part.removed.assign(global.size(), 0);
            part.triangles.reserve(last - first);
            for (std::size_t k = first; k < last; ++k) {
                const Triangle& t = mesh.triangles[order[k].triangle];
                part.triangles.push_back({local(t[0]), local(t[1]), local(t[2])});
            }
            glm::dvec3 lo = part.positions[0], hi = part.positions[0];
            for (const glm::dvec3& p : part.positions) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
            const glm::dvec3 margin(1e-6 * (1.0 + glm::length(hi - lo)));
            // The neighbours' triangles near this cube's, as obstacles.
            const std::uint64_t key = order[first].cube;
            std::uint32_t outside = kObstacleVertex;
            for (int dz = -1; dz <= 1 && needsObstacles; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        if (!dx && !dy && !dz) continue;
                        const auto it = groupOf.find(neighbour(key, dx, dy, dz));
                        if (it == groupOf.end()) continue;
                        const auto [nFirst, nLast] = groups[it->second];
                        for (std::size_t k = nFirst; k < nLast; ++k) {
                            const Triangle& t = mesh.triangles[order[k].triangle];
                            if (t[0] == kRemoved) continue;
                            const std::array<glm::dvec3, 3> c = {mesh.positions[t[0]], mesh.positions[t[1]],
                                                                 mesh.positions[t[2]]};
                            if (glm::any(glm::lessThan(hi + margin, glm::min(c[0], glm::min(c[1], c[2])))) ||
                                glm::any(glm::greaterThan(lo - margin, glm::max(c[0], glm::max(c[1], c[2])))))
                                continue;
                            Triangle o;
                            for (int j = 0; j < 3; ++j) {
                                const std::uint32_t l = localOf[t[std::size_t(j)]];
                                o[std::size_t(j)] = l != kNone ? l : outside++;
                            }
                            part.obstacles.push_back(o);
                            part.obstacleCorners.push_back(c);
                        }
                    }
            for (const std::uint32_t v : global)
                localOf[v] = kNone;
            SurfaceQueries cubeSurface = surface.region(lo - margin, hi + margin);
            CrossingChecks cubeChecks;
            if (beforehand) total += collapseEdges(part, *beforehand, cubeSurface, work);
            total += cubeLimits.checkAfterwards ? collapseEdgesCheckedAfter(part, cubeLimits, cubeSurface, work, &cubeChecks)
                                                : collapseEdges(part, cubeLimits, cubeSurface, work);
            checked += cubeChecks.checked;
            redone += cubeChecks.redone;
            // Back: this cube alone owns its triangles and its vertices that
            // were not held, so the writes of different cubes never meet.
            for (std::size_t k = first; k < last; ++k) {
                const Triangle& t = part.triangles[k - first];
                Triangle& out = mesh.triangles[order[k].triangle];
                if (t[0] == kRemoved)
                    out[0] = kRemoved;
                else
                    out = {global[t[0]], global[t[1]], global[t[2]]};
            }
            for (std::size_t l = 0; l < global.size(); ++l) {
                if (part.held[l]) continue;
                mesh.removed[global[l]] = part.removed[l];
                mesh.quadrics[global[l]] = part.quadrics[l];
                mesh.positions[global[l]] = part.positions[l];
                mesh.normals[global[l]] = part.normals[l];
            }
            work.report(double(trianglesDone += last - first) / double(order.size()));
        });
    });
    if (checks) {
        checks->checked += checked;
        checks->redone += redone;
    }
    return total;
}

} // namespace kerf::mesher

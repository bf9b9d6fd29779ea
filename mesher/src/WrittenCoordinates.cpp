#include "kerf/mesher/WrittenCoordinates.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <charconv>
#include <compare>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace kerf {

namespace {

using Triangle = std::array<std::uint32_t, 3>;
constexpr std::uint32_t kGone = std::numeric_limits<std::uint32_t>::max();

glm::dvec3 written(const glm::dvec3& p, WrittenFormat format, const glm::dvec3& offset)
{
    const glm::dvec3 local = p - offset;
    return {writtenCoordinate(local.x, format), writtenCoordinate(local.y, format), writtenCoordinate(local.z, format)};
}

// The written value next to w (a written value), towards `up` or down.
double nextWritten(double w, bool up, WrittenFormat format)
{
    const float f = float(w);
    float g = std::nextafter(f, up ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity());
    double candidate = writtenCoordinate(double(g), format);
    // Six decimals are coarser than float32 below 8 mm: step on until the
    // printed value changes.
    for (int i = 0; i < 64 && candidate == w; ++i) {
        g = std::nextafter(g, up ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity());
        candidate = writtenCoordinate(double(g), format);
    }
    return candidate;
}

struct Bits {
    std::uint64_t x, y, z;
    auto operator<=>(const Bits&) const = default;
};
struct BitsHash {
    std::size_t operator()(const Bits& b) const
    {
        return std::size_t(b.x * 0x9E3779B97F4A7C15ull ^ b.y * 0xC2B2AE3D27D4EB4Full ^ b.z * 0x165667B19E3779F9ull);
    }
};
Bits bitsOf(const glm::dvec3& q)
{
    Bits b;
    std::memcpy(&b.x, &q.x, 8);
    std::memcpy(&b.y, &q.y, 8);
    std::memcpy(&b.z, &q.z, 8);
    return b;
}

// Every vertex's written point (file coordinates), on the arena's threads.
std::vector<glm::dvec3> writtenPoints(const Mesh& mesh, WrittenFormat format, const glm::dvec3& offset)
{
    std::vector<glm::dvec3> q(mesh.vertices.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, q.size(), std::size_t(1) << 14),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v)
            q[v] = written(mesh.vertices[v], format, offset);
    });
    return q;
}

// For each vertex that `counts` (all where it is empty), the lowest-numbered
// counted vertex written to the same point (bit for bit, as a reader's
// weld compares): itself where it is the first. A sort, not a hash table:
// the marching-cubes mesh of the side chair at 0.5 mm has 4.7 M vertices,
// which a std::unordered_map took 7 s to weld on one thread; sorted on the
// arena's threads, a fraction of that. Uncounted vertices map to kGone.
std::vector<std::uint32_t> firstAtSamePoint(const std::vector<glm::dvec3>& q, const std::vector<std::uint8_t>& counts)
{
    // Sorted by (hash of the point, vertex): equal points are in one run of
    // equal hashes. A run longer than one (points written to one place, or
    // a collision) is sorted again by (point, vertex), so that each point's
    // vertices stand together, lowest first: a part whose vertices float32
    // rounds to a few points (far from the origin) costs a sort, not the
    // square of the run.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
    keyed.reserve(q.size());
    for (std::uint32_t v = 0; v < q.size(); ++v)
        if (counts.empty() || counts[v]) keyed.emplace_back(BitsHash()(bitsOf(q[v])), v);
    tbb::parallel_sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> first(q.size(), kGone);
    for (std::size_t begin = 0, end = 0; begin < keyed.size(); begin = end) {
        while (end < keyed.size() && keyed[end].first == keyed[begin].first)
            ++end;
        if (end - begin > 1)
            std::sort(keyed.begin() + std::ptrdiff_t(begin), keyed.begin() + std::ptrdiff_t(end),
                      [&](const auto& a, const auto& b) {
                return std::pair(bitsOf(q[a.second]), a.second) < std::pair(bitsOf(q[b.second]), b.second);
            });
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint32_t v = keyed[i].second;
            const bool samePoint = i > begin && bitsOf(q[keyed[i - 1].second]) == bitsOf(q[v]);
            first[v] = samePoint ? first[keyed[i - 1].second] : v;
        }
    }
    return first;
}

// Whether a triangle has no area, or the other way round from the double
// triangle, once its corners are written (`q`).
bool turnedByWriting(const Mesh& mesh, const std::vector<glm::dvec3>& q, const Triangle& tri)
{
    const glm::dvec3 written = glm::cross(q[tri[1]] - q[tri[0]], q[tri[2]] - q[tri[0]]);
    const glm::dvec3 exact = glm::cross(mesh.vertices[tri[1]] - mesh.vertices[tri[0]],
                                        mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
    return !(glm::dot(written, exact) > 0.0);
}

// Keeps the vertices the triangles use, numbered in the order the
// triangles first use them, and drops removed triangles (kGone in [0]).
void keepUsedVertices(Mesh& mesh)
{
    std::vector<std::uint32_t> index(mesh.vertices.size(), kGone);
    Mesh out;
    for (const Triangle& t : mesh.triangles) {
        if (t[0] == kGone) continue;
        Triangle g;
        for (int k = 0; k < 3; ++k) {
            std::uint32_t& i = index[t[std::size_t(k)]];
            if (i == kGone) {
                i = std::uint32_t(out.vertices.size());
                out.vertices.push_back(mesh.vertices[t[std::size_t(k)]]);
            }
            g[std::size_t(k)] = i;
        }
        out.triangles.push_back(g);
    }
    mesh = std::move(out);
}

// The furthest any vertex lies from its written point (mm).
double largestRounding(const Mesh& mesh, const std::vector<glm::dvec3>& q, const glm::dvec3& offset)
{
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, q.size(), std::size_t(1) << 14), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double largest) {
            for (std::size_t v = r.begin(); v != r.end(); ++v)
                largest = std::max(largest, glm::length(q[v] + offset - mesh.vertices[v]));
            return largest;
        },
        [](double a, double b) { return std::max(a, b); });
}

// Whether writing breaks nothing: no two vertices that triangles use
// written to one point, no triangle without area or turned over. Most
// meshes (every bundled example) need no repair; the Fitter, whose
// per-vertex lists and hash tables took 10 s on the side chair's 9.5 M
// marching-cubes triangles, runs only where this finds something.
bool writingBreaksNothing(const Mesh& mesh, const std::vector<glm::dvec3>& q)
{
    std::vector<std::uint8_t> used(mesh.vertices.size(), 0);
    for (const Triangle& t : mesh.triangles)
        for (const std::uint32_t v : t)
            used[v] = 1;
    const std::vector<std::uint32_t> first = firstAtSamePoint(q, used);
    for (std::uint32_t v = 0; v < first.size(); ++v)
        if (used[v] && first[v] != v) return false;
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), std::size_t(1) << 14), true,
        [&](const tbb::blocked_range<std::size_t>& r, bool fine) {
            for (std::size_t t = r.begin(); t != r.end() && fine; ++t)
                fine = !turnedByWriting(mesh, q, mesh.triangles[t]);
            return fine;
        },
        std::logical_and<bool>());
}

// Repairs in written coordinates. Vertex -> triangles adjacency, kept
// through collapses.
class Fitter {
public:
    Fitter(Mesh& mesh, WrittenFormat format, const glm::dvec3& offset, std::vector<glm::dvec3> written)
        : mesh_(mesh), format_(format), offset_(offset), q_(std::move(written))
    {
        around_.resize(mesh.vertices.size());
        for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
            for (const std::uint32_t v : mesh.triangles[t])
                around_[v].push_back(t);
    }

    /// `fit.largestMove` comes in as the rounding's.
    WrittenFit run(WrittenFit fit)
    {
        for (int round = 0; round < 16; ++round) {
            std::size_t problems = 0;
            // Vertices that round to one point.
            std::unordered_map<Bits, std::uint32_t, BitsHash> at;
            at.reserve(mesh_.vertices.size());
            for (std::uint32_t v = 0; v < mesh_.vertices.size(); ++v) {
                if (around_[v].empty()) continue;
                const auto [it, added] = at.emplace(bitsOf(q_[v]), v);
                if (added) continue;
                ++problems;
                const std::uint32_t u = it->second;
                if (!(adjacent(u, v) && collapse(v, u, fit)) && !(adjacent(u, v) && collapse(u, v, fit))) nudge(v, u, fit);
                it->second = v; // (one of them may be gone; the next round looks again)
            }
            // Triangles without area, or turned over, once rounded.
            for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t) {
                if (mesh_.triangles[t][0] == kGone || !bad(t)) continue;
                ++problems;
                mend(t, fit);
            }
            if (problems == 0) break;
        }
        // What is still wrong.
        std::unordered_map<Bits, std::uint32_t, BitsHash> at;
        for (std::uint32_t v = 0; v < mesh_.vertices.size(); ++v)
            if (!around_[v].empty() && !at.emplace(bitsOf(q_[v]), v).second) ++fit.unresolved;
        for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t)
            if (mesh_.triangles[t][0] != kGone && bad(t)) ++fit.unresolved;
        keepUsedVertices(mesh_);
        return fit;
    }

private:
    bool adjacent(std::uint32_t a, std::uint32_t b) const
    {
        for (const std::uint32_t t : around_[a])
            for (const std::uint32_t v : mesh_.triangles[t])
                if (v == b) return true;
        return false;
    }

    bool bad(std::uint32_t t) const { return turnedByWriting(mesh_, q_, mesh_.triangles[t]); }

    // Collapses a into b if the topology allows (the edge's two triangles
    // are all a and b share) and no triangle of a goes bad.
    bool collapse(std::uint32_t a, std::uint32_t b, WrittenFit& fit)
    {
        std::vector<std::uint32_t> shared, neighboursA, neighboursB;
        for (const std::uint32_t t : around_[a]) {
            bool hasB = false;
            for (const std::uint32_t v : mesh_.triangles[t]) {
                if (v == b) hasB = true;
                if (v != a) neighboursA.push_back(v);
            }
            if (hasB) shared.push_back(t);
        }
        if (shared.size() != 2) return false;
        for (const std::uint32_t t : around_[b])
            for (const std::uint32_t v : mesh_.triangles[t])
                if (v != b && v != a) neighboursB.push_back(v);
        std::sort(neighboursA.begin(), neighboursA.end());
        neighboursA.erase(std::unique(neighboursA.begin(), neighboursA.end()), neighboursA.end());
        std::sort(neighboursB.begin(), neighboursB.end());
        neighboursB.erase(std::unique(neighboursB.begin(), neighboursB.end()), neighboursB.end());
        std::vector<std::uint32_t> common;
        std::set_intersection(neighboursA.begin(), neighboursA.end(), neighboursB.begin(), neighboursB.end(),
                              std::back_inserter(common));
        if (common.size() != 2) return false;
        for (const std::uint32_t c : common) {
            std::size_t live = 0;
            for (const std::uint32_t t : around_[c])
                live += mesh_.triangles[t][0] != kGone;
            if (live <= 3) return false;
        }
        // Every triangle of a that stays must keep its area and side once a
        // is replaced by b.
        for (const std::uint32_t t : around_[a]) {
            if (std::find(shared.begin(), shared.end(), t) != shared.end()) continue;
            Triangle tri = mesh_.triangles[t];
            glm::dvec3 w[3], e[3];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = tri[std::size_t(k)] == a ? b : tri[std::size_t(k)];
                w[k] = q_[v];
                e[k] = mesh_.vertices[tri[std::size_t(k)]];
            }
            if (!(glm::dot(glm::cross(w[1] - w[0], w[2] - w[0]), glm::cross(e[1] - e[0], e[2] - e[0])) > 0.0))
                return false;
        }
        for (const std::uint32_t t : shared) {
            for (const std::uint32_t v : mesh_.triangles[t])
                if (v != a) std::erase(around_[v], t);
            mesh_.triangles[t][0] = kGone;
        }
        for (const std::uint32_t t : around_[a]) {
            if (mesh_.triangles[t][0] == kGone) continue;
            for (std::uint32_t& v : mesh_.triangles[t])
                if (v == a) v = b;
            around_[b].push_back(t);
        }
        around_[a].clear();
        fit.largestMove = std::max(fit.largestMove, glm::length(mesh_.vertices[a] - mesh_.vertices[b]));
        ++fit.collapses;
        return true;
    }

    // Moves v by one written step, along the axis where it lies furthest
    // from `from`, away from it. Two vertices at one point (where two
    // boards touch along an edge, the marching cubes put a vertex of each
    // board's surface on the line) have no such axis: v then moves towards
    // the middle of its own triangles, into its own board's corner and away
    // from the other's. (Moved along +x whatever the boards, one board's
    // corner went into the other's and the file crossed itself: random
    // joinery, ExportedJoinery.)
    void nudge(std::uint32_t v, std::uint32_t from, WrittenFit& fit)
    {
        glm::dvec3 d = mesh_.vertices[v] - mesh_.vertices[from];
        if (d == glm::dvec3(0.0)) d = towardsOwnTriangles(v, from);
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (std::abs(d[k]) > std::abs(d[axis])) axis = k;
        const bool up = d[axis] > 0.0 || (d[axis] == 0.0 && v > from);
        const double before = mesh_.vertices[v][axis];
        q_[v][axis] = nextWritten(q_[v][axis], up, format_);
        mesh_.vertices[v][axis] = q_[v][axis] + offset_[axis];
        fit.largestMove = std::max(fit.largestMove, std::abs(mesh_.vertices[v][axis] - before));
        ++fit.nudges;
    }

    // From v towards the middle of the vertices of its triangles other than
    // `other` (0 when they are all at v).
    glm::dvec3 towardsOwnTriangles(std::uint32_t v, std::uint32_t other) const
    {
        glm::dvec3 sum(0.0);
        int count = 0;
        for (const std::uint32_t t : around_[v]) {
            if (mesh_.triangles[t][0] == kGone) continue;
            for (const std::uint32_t w : mesh_.triangles[t])
                if (w != v && w != other) {
                    sum += mesh_.vertices[w];
                    ++count;
                }
        }
        return count ? sum / double(count) - mesh_.vertices[v] : glm::dvec3(0.0);
    }

    // A triangle without area (or turned over) once written: collapse its
    // shortest edge, else move its vertex furthest from the opposite edge's
    // line a step further from it.
    void mend(std::uint32_t t, WrittenFit& fit)
    {
        const Triangle tri = mesh_.triangles[t];
        int shortest = 0;
        double length = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
            const double l = glm::length(q_[tri[std::size_t(k)]] - q_[tri[std::size_t(k + 1) % 3]]);
            if (l < length) {
                length = l;
                shortest = k;
            }
        }
        const std::uint32_t a = tri[std::size_t(shortest)], b = tri[std::size_t(shortest + 1) % 3];
        if (collapse(a, b, fit) || collapse(b, a, fit)) return;
        const std::uint32_t apex = tri[std::size_t(shortest + 2) % 3];
        nudge(apex, a, fit);
    }

    Mesh& mesh_;
    WrittenFormat format_;
    glm::dvec3 offset_;
    std::vector<std::vector<std::uint32_t>> around_;
    std::vector<glm::dvec3> q_;
};

} // namespace

double writtenCoordinate(double x, WrittenFormat format)
{
    const float f = float(x);
    if (format == WrittenFormat::Float32) return double(f);
    // What lib3mf's "%f" prints, read back as a reader parses it: to_chars
    // with a precision is printf's conversion in the C locale, and
    // from_chars rounds correctly as strtod does; both without locale or
    // format-string work, about ten times faster on the millions of
    // coordinates of a large export.
    char text[64];
    const auto printed = std::to_chars(text, text + sizeof text, double(f), std::chars_format::fixed, 6);
    double value = 0.0;
    std::from_chars(text, printed.ptr, value);
    return value;
}

WrittenFit fitToWritten(Mesh& mesh, WrittenFormat format, const glm::dvec3& offset)
{
    if (mesh.triangles.empty()) return {};
    std::vector<glm::dvec3> q = writtenPoints(mesh, format, offset);
    WrittenFit fit;
    fit.largestMove = largestRounding(mesh, q, offset);
    if (writingBreaksNothing(mesh, q)) {
        keepUsedVertices(mesh); // as after a repair: the same mesh either way
        return fit;
    }
    return Fitter(mesh, format, offset, std::move(q)).run(fit);
}

Mesh readBack(const Mesh& mesh, WrittenFormat format, bool weld, const glm::dvec3& offset)
{
    const std::vector<glm::dvec3> q = writtenPoints(mesh, format, offset);
    Mesh out;
    std::vector<std::uint32_t> index(mesh.vertices.size());
    // Numbered in the order of the vertices (with a weld, of the first
    // vertex at each point), as a reader that meets them in that order does.
    const std::vector<std::uint32_t> first = weld ? firstAtSamePoint(q, {}) : std::vector<std::uint32_t>();
    for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
        if (weld && first[v] != v) {
            index[v] = index[first[v]]; // first[v] < v: numbered already
            continue;
        }
        index[v] = std::uint32_t(out.vertices.size());
        out.vertices.push_back(q[v] + offset);
    }
    out.triangles.resize(mesh.triangles.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), std::size_t(1) << 14),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t t = r.begin(); t != r.end(); ++t) {
            const Triangle& g = mesh.triangles[t];
            out.triangles[t] = {index[g[0]], index[g[1]], index[g[2]]};
        }
    });
    return out;
}

} // namespace kerf

#include "kerf/mesher/CellPolygons.hpp"

#include <stdexcept>
#include <vector>

namespace kerf::cell {

namespace {

// The two axes other than `a`, in increasing order.
constexpr int otherAxis(int a, int k) { return a == 0 ? 1 + k : (a == 1 ? 2 * k : k); }

struct Face {
    std::array<int, 4> corner; // (iu, iv) = (0,0), (1,0), (0,1), (1,1)
    std::array<int, 4> edge;   // u-edge at iv = 0, u-edge at iv = 1, v-edge at iu = 0, v-edge at iu = 1
    int sigma = 1;             // +1 when (u, v) look counter-clockwise from outside the cell
};

// Doubled face coordinates of the four face edges' midpoints and of the
// corners, for the orientation test.
constexpr int kMidU[4] = {1, 1, 0, 2};
constexpr int kMidV[4] = {0, 2, 1, 1};

std::array<Face, kFaces> makeFaces()
{
    std::array<Face, kFaces> faces{};
    for (int f = 0; f < kFaces; ++f) {
        const int n = f >> 1, s = f & 1;
        const int u = otherAxis(n, 0), v = otherAxis(n, 1);
        Face& face = faces[std::size_t(f)];
        for (int c = 0; c < 4; ++c)
            face.corner[std::size_t(c)] = (s << n) | ((c & 1) << u) | ((c >> 1) << v);
        face.edge[0] = edgeFrom(face.corner[0], u);
        face.edge[1] = edgeFrom(face.corner[2], u);
        face.edge[2] = edgeFrom(face.corner[0], v);
        face.edge[3] = edgeFrom(face.corner[1], v);
        // e_u x e_v is +e_n for (n, u, v) = (x, y, z) and (z, x, y), -e_n for (y, x, z);
        // the outward normal is +e_n on side 1.
        face.sigma = (s ? 1 : -1) * (n == 1 ? -1 : 1);
    }
    return faces;
}

const std::array<Face, kFaces>& faces()
{
    static const std::array<Face, kFaces> table = makeFaces();
    return table;
}

// Face edge k's two corners (face corner indices), lower first.
constexpr int kEdgeCornerA[4] = {0, 2, 0, 1};
constexpr int kEdgeCornerB[4] = {1, 3, 2, 3};

// Builds the cycles from the face rules (see the header for why they close).
CellCycles assemble(std::uint8_t insideMask, std::uint8_t connectInside)
{
    std::array<int, kEdges> next;
    next.fill(-1);
    for (int f = 0; f < kFaces; ++f) {
        const Face& face = faces()[std::size_t(f)];
        int inside[4];
        for (int c = 0; c < 4; ++c)
            inside[c] = insideMask >> face.corner[std::size_t(c)] & 1;
        int crossing[4], count = 0;
        for (int k = 0; k < 4; ++k)
            if (inside[kEdgeCornerA[k]] != inside[kEdgeCornerB[k]]) crossing[count++] = k;
        if (count == 0) continue;
        std::array<std::array<int, 2>, 2> segments{};
        int segmentCount = 0;
        if (count == 2) {
            segments[0] = {crossing[0], crossing[1]};
            segmentCount = 1;
        } else {
            // Ambiguous: diagonal corners share a side. Cut off each corner of
            // the side that is not connected through the face.
            const bool connect = connectInside >> f & 1;
            for (int c = 0; c < 4; ++c) {
                if (bool(inside[c]) == connect) continue; // this corner's side is connected: not cut off
                const int iu = c & 1, iv = c >> 1;
                segments[std::size_t(segmentCount++)] = {iv, 2 + iu}; // its u-edge and its v-edge
            }
        }
        for (int k = 0; k < segmentCount; ++k) {
            const int p = segments[std::size_t(k)][0], q = segments[std::size_t(k)][1];
            // The inside end of p's edge, in doubled face coordinates.
            const int a = inside[kEdgeCornerA[p]] ? kEdgeCornerA[p] : kEdgeCornerB[p];
            const int au = 2 * (a & 1), av = 2 * (a >> 1);
            const int dx = kMidU[q] - kMidU[p], dy = kMidV[q] - kMidV[p];
            const int cross = dx * (av - kMidV[p]) - dy * (au - kMidU[p]);
            // Inside on the right seen from outside: cross * sigma < 0 means p -> q.
            const bool forward = cross * face.sigma < 0;
            const int from = face.edge[std::size_t(forward ? p : q)];
            const int to = face.edge[std::size_t(forward ? q : p)];
            if (next[std::size_t(from)] != -1) throw std::logic_error("cell polygons: two segments leave one edge");
            next[std::size_t(from)] = to;
        }
    }
    CellCycles out;
    std::array<bool, kEdges> seen{};
    int written = 0;
    for (int e = 0; e < kEdges; ++e) {
        if (next[std::size_t(e)] < 0 || seen[std::size_t(e)]) continue;
        int size = 0;
        for (int x = e; !seen[std::size_t(x)]; x = next[std::size_t(x)]) {
            if (next[std::size_t(x)] < 0) throw std::logic_error("cell polygons: open chain");
            seen[std::size_t(x)] = true;
            out.edges[std::size_t(written + size++)] = std::uint8_t(x);
        }
        out.size[std::size_t(out.count++)] = std::uint8_t(size);
        written += size;
    }
    return out;
}

// Which faces are ambiguous for each inside mask.
std::uint8_t ambiguousFaces(std::uint8_t insideMask)
{
    std::uint8_t m = 0;
    for (int f = 0; f < kFaces; ++f) {
        const Face& face = faces()[std::size_t(f)];
        const int b0 = insideMask >> face.corner[0] & 1, b1 = insideMask >> face.corner[1] & 1;
        const int b2 = insideMask >> face.corner[2] & 1, b3 = insideMask >> face.corner[3] & 1;
        if (b0 == b3 && b1 == b2 && b0 != b1) m |= std::uint8_t(1 << f);
    }
    return m;
}

// Every (inside mask, connection bits) pair, built once from the face rules.
struct Table {
    std::vector<CellCycles> cycles = std::vector<CellCycles>(256 * 64);
    std::array<std::uint8_t, 256> ambiguous{};
    std::array<std::uint8_t, 256> crossed{};
    Table()
    {
        for (int m = 0; m < 256; ++m) {
            ambiguous[std::size_t(m)] = ambiguousFaces(std::uint8_t(m));
            for (int c = 0; c < 64; ++c)
                if ((c & ~ambiguous[std::size_t(m)]) == 0)
                    cycles[std::size_t(m * 64 + c)] = assemble(std::uint8_t(m), std::uint8_t(c));
            std::uint8_t x = 0;
            for (int f = 0; f < kFaces; ++f) {
                int n = 0;
                for (int c = 0; c < 4; ++c)
                    n += m >> faces()[std::size_t(f)].corner[std::size_t(c)] & 1;
                if (n != 0 && n != 4) x |= std::uint8_t(1 << f);
            }
            crossed[std::size_t(m)] = x;
        }
    }
};

const Table& table()
{
    static const Table t;
    return t;
}

} // namespace

int edgeLowerCorner(int e)
{
    const int a = e >> 2, j = e & 3;
    return ((j & 1) << otherAxis(a, 0)) | ((j >> 1) << otherAxis(a, 1));
}

std::uint8_t edgeFaceMask(int e)
{
    const int a = e >> 2, j = e & 3;
    return std::uint8_t(1 << (2 * otherAxis(a, 0) + (j & 1)) | 1 << (2 * otherAxis(a, 1) + (j >> 1)));
}

int edgeFrom(int q, int axis)
{
    return 4 * axis + ((q >> otherAxis(axis, 0) & 1) | (q >> otherAxis(axis, 1) & 1) << 1);
}

bool insideConnected(double v00, double v10, double v01, double v11)
{
    // With inside pair (a, d) and outside pair (b, c), the denominator of the
    // saddle value has the sign of the inside pair, so S < 0 iff
    // a * d > b * c. Products of the same arguments in the same order: both
    // cells sharing the face get the same answer.
    const bool mainDiagonalInside = v00 < 0.0;
    const double insideProduct = mainDiagonalInside ? v00 * v11 : v10 * v01;
    const double outsideProduct = mainDiagonalInside ? v10 * v01 : v00 * v11;
    return insideProduct > outsideProduct;
}

CellCycles cellCycles(std::uint8_t insideMask, std::uint8_t connectInside)
{
    const Table& t = table();
    return t.cycles[std::size_t(insideMask) * 64 + (connectInside & t.ambiguous[insideMask])];
}

CellCycles cellCycles(const double* values)
{
    std::uint8_t mask = 0;
    for (int q = 0; q < kCorners; ++q)
        mask |= std::uint8_t((values[q] < 0.0) << q);
    const Table& t = table();
    std::uint8_t connect = 0;
    const std::uint8_t ambiguous = t.ambiguous[mask];
    if (ambiguous) {
        for (int f = 0; f < kFaces; ++f) {
            if (!(ambiguous >> f & 1)) continue;
            const auto& c = faces()[std::size_t(f)].corner;
            if (insideConnected(values[c[0]], values[c[1]], values[c[2]], values[c[3]]))
                connect |= std::uint8_t(1 << f);
        }
    }
    return t.cycles[std::size_t(mask) * 64 + connect];
}

std::uint8_t crossedFaces(std::uint8_t insideMask) { return table().crossed[insideMask]; }

} // namespace kerf::cell

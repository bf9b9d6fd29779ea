#include "kerf/voxelizer/TileTape.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <bit>
#include <map>

// evaluateTileTape() and evaluateTileTapeGradient() are written to be ported
// to GLSL line by line (shaders/trace.comp): glm types stand for GLSL's,
// plain loops, no containers. The stack is kept top first and shifted on
// every push and pop, as the shader keeps it in eight named registers (st[j]
// here is its s<j>).

namespace kerf::voxel {

static_assert(std::uint32_t(Op::Primitive) == KERF_TAPE_PRIMITIVE && std::uint32_t(Op::Min) == KERF_TAPE_MIN &&
              std::uint32_t(Op::Max) == KERF_TAPE_MAX && std::uint32_t(Op::SmoothMin) == KERF_TAPE_SMOOTH_MIN &&
              std::uint32_t(Op::SmoothMax) == KERF_TAPE_SMOOTH_MAX && std::uint32_t(Op::Negate) == KERF_TAPE_NEGATE &&
              std::uint32_t(Op::Offset) == KERF_TAPE_OFFSET && std::uint32_t(Op::Shell) == KERF_TAPE_SHELL);
static_assert(std::uint32_t(ShapeKind::Box) == KERF_SHAPE_BOX &&
              std::uint32_t(ShapeKind::Sphere) == KERF_SHAPE_SPHERE &&
              std::uint32_t(ShapeKind::Cylinder) == KERF_SHAPE_CYLINDER &&
              std::uint32_t(ShapeKind::Cone) == KERF_SHAPE_CONE &&
              std::uint32_t(ShapeKind::Torus) == KERF_SHAPE_TORUS &&
              std::uint32_t(ShapeKind::Extrude) == KERF_SHAPE_EXTRUDE &&
              std::uint32_t(ShapeKind::Halfspace) == KERF_SHAPE_HALFSPACE);

std::vector<std::uint32_t> encodeTileTape(const Tape& tape)
{
    if (tape.empty() || tape.maxStack() > std::uint32_t(KERF_TAPE_MAX_STACK) ||
        tape.size() > KERF_TAPE_MAX_INSTRUCTIONS)
        return {};
    const auto& code = tape.code();
    const auto& shapes = tape.shapes();
    std::vector<std::uint32_t> w;
    const std::size_t shapesAt = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * code.size();
    w.reserve(shapesAt + KERF_TAPE_SHAPE_WORDS * shapes.size());
    w.push_back(std::uint32_t(code.size()));
    w.push_back(std::uint32_t(shapes.size()));
    for (const Instruction& ins : code) {
        w.push_back(std::uint32_t(ins.op) | (ins.op == Op::Primitive ? ins.shape << 8 : 0u));
        w.push_back(std::bit_cast<std::uint32_t>(float(ins.k)));
    }
    // Shapes, then the extrusions' polygons, each once however many copies use it.
    std::map<const Polygon*, std::uint32_t> polygonAt;
    std::vector<const Polygon*> polygons;
    std::uint32_t polygonWords = std::uint32_t(shapesAt + KERF_TAPE_SHAPE_WORDS * shapes.size());
    for (const ShapeInstance& s : shapes) {
        w.push_back(std::uint32_t(s.kind));
        w.push_back(s.feature);
        for (float f : s.frameF)
            w.push_back(std::bit_cast<std::uint32_t>(f));
        std::array<std::uint32_t, 6> param;
        for (std::size_t i = 0; i < 6; ++i)
            param[i] = std::bit_cast<std::uint32_t>(s.paramF[i]);
        if (s.kind == ShapeKind::Extrude) {
            const Polygon* poly = s.polygon.get();
            auto [it, added] = polygonAt.emplace(poly, polygonWords);
            if (added) {
                polygons.push_back(poly);
                polygonWords += std::uint32_t(2 * poly->pointsF.size());
            }
            param[1] = it->second;
            param[2] = std::uint32_t(poly->pointsF.size());
        }
        w.insert(w.end(), param.begin(), param.end());
    }
    for (const Polygon* poly : polygons)
        for (const glm::vec2& v : poly->pointsF) {
            w.push_back(std::bit_cast<std::uint32_t>(v.x));
            w.push_back(std::bit_cast<std::uint32_t>(v.y));
        }
    return w;
}

namespace {

float word(const std::uint32_t* t, std::uint32_t i) { return std::bit_cast<float>(t[i]); }

float sq(float v) { return v * v; }

// The exact distances of Primitives.hpp (sdf::), for float, in the same
// order of operations.
float boxDistance(const glm::vec3& l, float bx, float by, float bz, float round)
{
    const float qx = glm::abs(l.x) - bx, qy = glm::abs(l.y) - by, qz = glm::abs(l.z) - bz;
    const float outside = glm::sqrt(sq(glm::max(qx, 0.0f)) + sq(glm::max(qy, 0.0f)) + sq(glm::max(qz, 0.0f)));
    const float inside = glm::min(glm::max(qx, glm::max(qy, qz)), 0.0f);
    return outside + inside - round;
}

float cylinderDistance(const glm::vec3& l, float radius, float halfHeight)
{
    const float dr = glm::sqrt(sq(l.x) + sq(l.y)) - radius;
    const float dz = glm::abs(l.z) - halfHeight;
    return glm::min(glm::max(dr, dz), 0.0f) + glm::sqrt(sq(glm::max(dr, 0.0f)) + sq(glm::max(dz, 0.0f)));
}

float coneDistance(const glm::vec3& l, float r1, float r2, float h, float k2x, float k2y, float invK2)
{
    const float qx = glm::sqrt(sq(l.x) + sq(l.y));
    const float qy = l.z;
    const float rr = qy < 0.0f ? r1 : r2;
    const float cax = qx - glm::min(qx, rr);
    const float cay = glm::abs(qy) - h;
    const float t = glm::clamp(((r2 - qx) * k2x + (h - qy) * k2y) * invK2, 0.0f, 1.0f);
    const float cbx = qx - r2 + k2x * t;
    const float cby = qy - h + k2y * t;
    const float s = (cbx < 0.0f && cay < 0.0f) ? -1.0f : 1.0f;
    return s * glm::sqrt(glm::min(sq(cax) + sq(cay), sq(cbx) + sq(cby)));
}

// Signed distance to the polygon of `count` points at word `first` (sdf::polygon2d).
float polygonDistance(const std::uint32_t* t, std::uint32_t first, std::uint32_t count, float x, float y)
{
    float d = sq(x - word(t, first)) + sq(y - word(t, first + 1u));
    bool inside = false;
    for (std::uint32_t i = 0u, j = count - 1u; i < count; j = i++) {
        const float vix = word(t, first + 2u * i), viy = word(t, first + 2u * i + 1u);
        const float vjx = word(t, first + 2u * j), vjy = word(t, first + 2u * j + 1u);
        const float ex = vjx - vix, ey = vjy - viy;
        const float wx = x - vix, wy = y - viy;
        const float s = glm::clamp((wx * ex + wy * ey) / (ex * ex + ey * ey), 0.0f, 1.0f);
        d = glm::min(d, sq(wx - ex * s) + sq(wy - ey * s));
        const bool c1 = y >= viy, c2 = y<vjy, c3 = ex * wy> ey * wx;
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    }
    const float dist = glm::sqrt(d);
    return inside ? -dist : dist;
}

// Local coordinate `row` of tile-relative point p, by the frame at word f.
float localCoordinate(const std::uint32_t* t, std::uint32_t f, std::uint32_t row, const glm::vec3& p)
{
    const std::uint32_t r = f + 3u * row;
    return word(t, r) * p.x + word(t, r + 1u) * p.y + word(t, r + 2u) * p.z + word(t, f + 9u + row);
}

float shapeDistance(const std::uint32_t* t, std::uint32_t s, const glm::vec3& p)
{
    const std::uint32_t f = s + KERF_TAPE_SHAPE_FRAME;
    const glm::vec3 l(localCoordinate(t, f, 0u, p), localCoordinate(t, f, 1u, p), localCoordinate(t, f, 2u, p));
    const std::uint32_t a = s + KERF_TAPE_SHAPE_PARAMS;
    const std::uint32_t kind = t[s];
    if (kind == KERF_SHAPE_BOX) return boxDistance(l, word(t, a), word(t, a + 1u), word(t, a + 2u), word(t, a + 3u));
    if (kind == KERF_SHAPE_SPHERE) return glm::sqrt(sq(l.x) + sq(l.y) + sq(l.z)) - word(t, a);
    if (kind == KERF_SHAPE_CYLINDER) return cylinderDistance(l, word(t, a), word(t, a + 1u));
    if (kind == KERF_SHAPE_CONE)
        return coneDistance(l, word(t, a), word(t, a + 1u), word(t, a + 2u), word(t, a + 3u), word(t, a + 4u),
                            word(t, a + 5u));
    if (kind == KERF_SHAPE_TORUS) {
        const float q = glm::sqrt(sq(l.x) + sq(l.y)) - word(t, a);
        return glm::sqrt(sq(q) + sq(l.z)) - word(t, a + 1u);
    }
    if (kind == KERF_SHAPE_EXTRUDE) {
        // sdf::extrusion of the profile's distance.
        const float d2 = polygonDistance(t, t[a + 1u], t[a + 2u], l.x, l.y);
        const float wz = glm::abs(l.z) - word(t, a);
        return glm::min(glm::max(d2, wz), 0.0f) + glm::sqrt(sq(glm::max(d2, 0.0f)) + sq(glm::max(wz, 0.0f)));
    }
    return word(t, a) * l.x + word(t, a + 1u) * l.y + word(t, a + 2u) * l.z - word(t, a + 3u); // halfspace
}

// Dual numbers as vec4: x the value, yzw the gradient (Dual.hpp's rules).
glm::vec4 dConst(float c) { return glm::vec4(c, 0.0f, 0.0f, 0.0f); }
glm::vec4 dMul(const glm::vec4& a, const glm::vec4& b)
{
    return glm::vec4(a.x * b.x, a.y * b.x + a.x * b.y, a.z * b.x + a.x * b.z, a.w * b.x + a.x * b.w);
}
glm::vec4 dSq(const glm::vec4& a) { return dMul(a, a); }
glm::vec4 dSqrt(const glm::vec4& a)
{
    const float s = glm::sqrt(a.x);
    const float k = s > 0.0f ? 0.5f / s : 0.0f;
    return glm::vec4(s, a.y * k, a.z * k, a.w * k);
}
glm::vec4 dAbs(const glm::vec4& a) { return a.x < 0.0f ? -a : a; }
glm::vec4 dMin(const glm::vec4& a, const glm::vec4& b) { return b.x < a.x ? b : a; }
glm::vec4 dMax(const glm::vec4& a, const glm::vec4& b) { return a.x < b.x ? b : a; }

glm::vec4 boxGradient(const glm::vec4& lx, const glm::vec4& ly, const glm::vec4& lz, float bx, float by, float bz,
                      float round)
{
    const glm::vec4 qx = dAbs(lx) - dConst(bx), qy = dAbs(ly) - dConst(by), qz = dAbs(lz) - dConst(bz);
    const glm::vec4 outside =
        dSqrt(dSq(dMax(qx, dConst(0.0f))) + dSq(dMax(qy, dConst(0.0f))) + dSq(dMax(qz, dConst(0.0f))));
    const glm::vec4 inside = dMin(dMax(qx, dMax(qy, qz)), dConst(0.0f));
    return outside + inside - dConst(round);
}

glm::vec4 cylinderGradient(const glm::vec4& lx, const glm::vec4& ly, const glm::vec4& lz, float radius,
                           float halfHeight)
{
    const glm::vec4 dr = dSqrt(dSq(lx) + dSq(ly)) - dConst(radius);
    const glm::vec4 dz = dAbs(lz) - dConst(halfHeight);
    return dMin(dMax(dr, dz), dConst(0.0f)) + dSqrt(dSq(dMax(dr, dConst(0.0f))) + dSq(dMax(dz, dConst(0.0f))));
}

glm::vec4 coneGradient(const glm::vec4& lx, const glm::vec4& ly, const glm::vec4& lz, float r1, float r2, float h,
                       float k2x, float k2y, float invK2)
{
    const glm::vec4 qx = dSqrt(dSq(lx) + dSq(ly));
    const glm::vec4 qy = lz;
    const float rr = qy.x < 0.0f ? r1 : r2;
    const glm::vec4 cax = qx - dMin(qx, dConst(rr));
    const glm::vec4 cay = dAbs(qy) - dConst(h);
    const glm::vec4 t =
        dMin(dMax(((dConst(r2) - qx) * k2x + (dConst(h) - qy) * k2y) * invK2, dConst(0.0f)), dConst(1.0f));
    const glm::vec4 cbx = qx - dConst(r2) + t * k2x;
    const glm::vec4 cby = qy - dConst(h) + t * k2y;
    const float s = (cbx.x < 0.0f && cay.x < 0.0f) ? -1.0f : 1.0f;
    return dSqrt(dMin(dSq(cax) + dSq(cay), dSq(cbx) + dSq(cby))) * s;
}

glm::vec4 polygonGradient(const std::uint32_t* t, std::uint32_t first, std::uint32_t count, const glm::vec4& x,
                          const glm::vec4& y)
{
    glm::vec4 d = dSq(x - dConst(word(t, first))) + dSq(y - dConst(word(t, first + 1u)));
    bool inside = false;
    for (std::uint32_t i = 0u, j = count - 1u; i < count; j = i++) {
        const float vix = word(t, first + 2u * i), viy = word(t, first + 2u * i + 1u);
        const float vjx = word(t, first + 2u * j), vjy = word(t, first + 2u * j + 1u);
        const float ex = vjx - vix, ey = vjy - viy;
        const glm::vec4 wx = x - dConst(vix), wy = y - dConst(viy);
        const glm::vec4 s = dMin(dMax((wx * ex + wy * ey) * (1.0f / (ex * ex + ey * ey)), dConst(0.0f)), dConst(1.0f));
        d = dMin(d, dSq(wx - s * ex) + dSq(wy - s * ey));
        const bool c1 = y.x >= viy, c2 = y.x<vjy, c3 = ex * wy.x> ey * wx.x;
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    }
    const glm::vec4 dist = dSqrt(d);
    return inside ? -dist : dist;
}

glm::vec4 shapeGradient(const std::uint32_t* t, std::uint32_t s, const glm::vec3& p)
{
    // Each local coordinate's gradient is its row of the frame.
    const std::uint32_t f = s + KERF_TAPE_SHAPE_FRAME;
    const glm::vec4 lx(localCoordinate(t, f, 0u, p), word(t, f), word(t, f + 1u), word(t, f + 2u));
    const glm::vec4 ly(localCoordinate(t, f, 1u, p), word(t, f + 3u), word(t, f + 4u), word(t, f + 5u));
    const glm::vec4 lz(localCoordinate(t, f, 2u, p), word(t, f + 6u), word(t, f + 7u), word(t, f + 8u));
    const std::uint32_t a = s + KERF_TAPE_SHAPE_PARAMS;
    const std::uint32_t kind = t[s];
    if (kind == KERF_SHAPE_BOX)
        return boxGradient(lx, ly, lz, word(t, a), word(t, a + 1u), word(t, a + 2u), word(t, a + 3u));
    if (kind == KERF_SHAPE_SPHERE) return dSqrt(dSq(lx) + dSq(ly) + dSq(lz)) - dConst(word(t, a));
    if (kind == KERF_SHAPE_CYLINDER) return cylinderGradient(lx, ly, lz, word(t, a), word(t, a + 1u));
    if (kind == KERF_SHAPE_CONE)
        return coneGradient(lx, ly, lz, word(t, a), word(t, a + 1u), word(t, a + 2u), word(t, a + 3u), word(t, a + 4u),
                            word(t, a + 5u));
    if (kind == KERF_SHAPE_TORUS) {
        const glm::vec4 q = dSqrt(dSq(lx) + dSq(ly)) - dConst(word(t, a));
        return dSqrt(dSq(q) + dSq(lz)) - dConst(word(t, a + 1u));
    }
    if (kind == KERF_SHAPE_EXTRUDE) {
        const glm::vec4 d2 = polygonGradient(t, t[a + 1u], t[a + 2u], lx, ly);
        const glm::vec4 wz = dAbs(lz) - dConst(word(t, a));
        return dMin(dMax(d2, wz), dConst(0.0f)) + dSqrt(dSq(dMax(d2, dConst(0.0f))) + dSq(dMax(wz, dConst(0.0f))));
    }
    return lx * word(t, a) + ly * word(t, a + 1u) + lz * word(t, a + 2u) - dConst(word(t, a + 3u));
}

} // namespace

glm::vec4 evaluateTileTapeGradient(const std::uint32_t* t, const glm::vec3& p, std::uint32_t& feature)
{
    const std::uint32_t count = t[0];
    const std::uint32_t shapes = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * count;
    glm::vec4 st[KERF_TAPE_MAX_STACK] = {};
    std::uint32_t fs[KERF_TAPE_MAX_STACK] = {};
    for (std::uint32_t i = 0u; i < count; ++i) {
        const std::uint32_t code = t[KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i];
        const float k = word(t, KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i + 1u);
        const std::uint32_t op = code & 0xFFu;
        if (op == KERF_TAPE_PRIMITIVE) {
            const std::uint32_t s = shapes + (code >> 8) * KERF_TAPE_SHAPE_WORDS;
            for (int j = KERF_TAPE_MAX_STACK - 1; j > 0; --j) {
                st[j] = st[j - 1];
                fs[j] = fs[j - 1];
            }
            st[0] = shapeGradient(t, s, p);
            fs[0] = t[s + 1u];
        } else if (op <= KERF_TAPE_SMOOTH_MAX) {
            const glm::vec4 b = st[0], a = st[1];
            // The deciding feature: the operand the exact min/max would pick.
            const bool isMin = op == KERF_TAPE_MIN || op == KERF_TAPE_SMOOTH_MIN;
            const std::uint32_t f = (isMin ? b.x < a.x : a.x < b.x) ? fs[0] : fs[1];
            glm::vec4 r;
            if (op == KERF_TAPE_MIN) {
                r = dMin(a, b);
            } else if (op == KERF_TAPE_MAX) {
                r = dMax(a, b);
            } else {
                const glm::vec4 h = dMax(dConst(k) - dAbs(a - b), dConst(0.0f)) * (1.0f / k);
                r = op == KERF_TAPE_SMOOTH_MIN ? dMin(a, b) - dSq(h) * (k * 0.25f) : dMax(a, b) + dSq(h) * (k * 0.25f);
            }
            st[0] = r;
            fs[0] = f;
            for (int j = 1; j < KERF_TAPE_MAX_STACK - 1; ++j) {
                st[j] = st[j + 1];
                fs[j] = fs[j + 1];
            }
        } else if (op == KERF_TAPE_NEGATE) {
            st[0] = -st[0];
        } else if (op == KERF_TAPE_OFFSET) {
            st[0] = st[0] - dConst(k);
        } else {
            st[0] = dMax(st[0], -(st[0] + dConst(k)));
        }
    }
    feature = fs[0];
    return st[0];
}

float evaluateTileTape(const std::uint32_t* t, const glm::vec3& p)
{
    const std::uint32_t count = t[0];
    const std::uint32_t shapes = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * count;
    float st[KERF_TAPE_MAX_STACK] = {};
    for (std::uint32_t i = 0u; i < count; ++i) {
        const std::uint32_t code = t[KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i];
        const float k = word(t, KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i + 1u);
        const std::uint32_t op = code & 0xFFu;
        if (op == KERF_TAPE_PRIMITIVE) {
            for (int j = KERF_TAPE_MAX_STACK - 1; j > 0; --j)
                st[j] = st[j - 1];
            st[0] = shapeDistance(t, shapes + (code >> 8) * KERF_TAPE_SHAPE_WORDS, p);
        } else if (op <= KERF_TAPE_SMOOTH_MAX) {
            const float b = st[0], a = st[1];
            float r;
            if (op == KERF_TAPE_MIN) {
                r = glm::min(a, b);
            } else if (op == KERF_TAPE_MAX) {
                r = glm::max(a, b);
            } else {
                // The spec's polynomial smooth minimum (Combine.hpp), or its mirror.
                const float h = glm::max(k - glm::abs(a - b), 0.0f) * (1.0f / k);
                r = op == KERF_TAPE_SMOOTH_MIN ? glm::min(a, b) - h * h * (k * 0.25f)
                                               : glm::max(a, b) + h * h * (k * 0.25f);
            }
            st[0] = r;
            for (int j = 1; j < KERF_TAPE_MAX_STACK - 1; ++j)
                st[j] = st[j + 1];
        } else if (op == KERF_TAPE_NEGATE) {
            st[0] = -st[0];
        } else if (op == KERF_TAPE_OFFSET) {
            st[0] = st[0] - k;
        } else { // shell
            st[0] = glm::max(st[0], -(st[0] + k));
        }
    }
    return st[0];
}

} // namespace kerf::voxel

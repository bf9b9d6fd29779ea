#include "kerf/voxelizer/TileTape.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <bit>
#include <map>

// evaluateTileTape() is written to be ported to GLSL line by line
// (shaders/trace.comp, tapeDistance): glm types stand for GLSL's, plain
// loops, a fixed-size stack, no containers.

namespace kerf::voxel {

static_assert(std::uint32_t(Op::Primitive) == KERF_TAPE_PRIMITIVE && std::uint32_t(Op::Min) == KERF_TAPE_MIN &&
              std::uint32_t(Op::Max) == KERF_TAPE_MAX && std::uint32_t(Op::SmoothMin) == KERF_TAPE_SMOOTH_MIN &&
              std::uint32_t(Op::SmoothMax) == KERF_TAPE_SMOOTH_MAX && std::uint32_t(Op::Negate) == KERF_TAPE_NEGATE &&
              std::uint32_t(Op::Offset) == KERF_TAPE_OFFSET && std::uint32_t(Op::Shell) == KERF_TAPE_SHELL);
static_assert(std::uint32_t(ShapeKind::Box) == KERF_SHAPE_BOX && std::uint32_t(ShapeKind::Sphere) == KERF_SHAPE_SPHERE &&
              std::uint32_t(ShapeKind::Cylinder) == KERF_SHAPE_CYLINDER &&
              std::uint32_t(ShapeKind::Cone) == KERF_SHAPE_CONE && std::uint32_t(ShapeKind::Torus) == KERF_SHAPE_TORUS &&
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
        for (float f : s.frameF) w.push_back(std::bit_cast<std::uint32_t>(f));
        std::array<std::uint32_t, 6> param;
        for (std::size_t i = 0; i < 6; ++i) param[i] = std::bit_cast<std::uint32_t>(s.paramF[i]);
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
    const float outside =
        glm::sqrt(sq(glm::max(qx, 0.0f)) + sq(glm::max(qy, 0.0f)) + sq(glm::max(qz, 0.0f)));
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
        const bool c1 = y >= viy, c2 = y < vjy, c3 = ex * wy > ey * wx;
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    }
    const float dist = glm::sqrt(d);
    return inside ? -dist : dist;
}

float shapeDistance(const std::uint32_t* t, std::uint32_t s, const glm::vec3& p)
{
    const std::uint32_t f = s + KERF_TAPE_SHAPE_FRAME;
    const glm::vec3 l(word(t, f) * p.x + word(t, f + 1u) * p.y + word(t, f + 2u) * p.z + word(t, f + 9u),
                      word(t, f + 3u) * p.x + word(t, f + 4u) * p.y + word(t, f + 5u) * p.z + word(t, f + 10u),
                      word(t, f + 6u) * p.x + word(t, f + 7u) * p.y + word(t, f + 8u) * p.z + word(t, f + 11u));
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

} // namespace

float evaluateTileTape(const std::uint32_t* t, const glm::vec3& p, std::uint32_t& feature)
{
    const std::uint32_t count = t[0];
    const std::uint32_t shapes = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * count;
    float stack[KERF_TAPE_MAX_STACK];
    std::uint32_t features[KERF_TAPE_MAX_STACK];
    int sp = 0;
    for (std::uint32_t i = 0u; i < count; ++i) {
        const std::uint32_t code = t[KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i];
        const float k = word(t, KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i + 1u);
        const std::uint32_t op = code & 0xFFu;
        if (op == KERF_TAPE_PRIMITIVE) {
            const std::uint32_t s = shapes + (code >> 8) * KERF_TAPE_SHAPE_WORDS;
            stack[sp] = shapeDistance(t, s, p);
            features[sp] = t[s + 1u];
            ++sp;
        } else if (op <= KERF_TAPE_SMOOTH_MAX) {
            const float b = stack[sp - 1], a = stack[sp - 2];
            // The deciding feature: the operand the exact min/max would pick.
            const bool isMin = op == KERF_TAPE_MIN || op == KERF_TAPE_SMOOTH_MIN;
            if (isMin ? b < a : a < b) features[sp - 2] = features[sp - 1];
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
            stack[sp - 2] = r;
            --sp;
        } else if (op == KERF_TAPE_NEGATE) {
            stack[sp - 1] = -stack[sp - 1];
        } else if (op == KERF_TAPE_OFFSET) {
            stack[sp - 1] = stack[sp - 1] - k;
        } else { // shell
            stack[sp - 1] = glm::max(stack[sp - 1], -(stack[sp - 1] + k));
        }
    }
    feature = features[0];
    return stack[0];
}

} // namespace kerf::voxel

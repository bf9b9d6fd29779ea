#include "kerf/voxelizer/TileTape.hpp"

#include "kerf/evaluator/FeatureTie.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "kerf/evaluator/Combine.hpp"
#include "kerf/evaluator/Primitives.hpp"

#include <bit>
#include <cmath>
#include <limits>
#include <map>

// evaluateTileTape() and evaluateTileTapeGradient() evaluate the encoded tape
// through the same sdf:: templates and combine:: rules as the document's
// evaluators; the GLSL tape library (shaders/tape.glsl) is their port, and
// TapeLanguagesTest holds the two to the same values. The stack is kept top
// first and shifted on every push and pop, as the shader keeps it.

namespace kerf::voxel {

static_assert(std::uint32_t(Op::Primitive) == KERF_TAPE_PRIMITIVE && std::uint32_t(Op::Min) == KERF_TAPE_MIN &&
              std::uint32_t(Op::Max) == KERF_TAPE_MAX && std::uint32_t(Op::SmoothMin) == KERF_TAPE_SMOOTH_MIN &&
              std::uint32_t(Op::SmoothMax) == KERF_TAPE_SMOOTH_MAX && std::uint32_t(Op::Negate) == KERF_TAPE_NEGATE &&
              std::uint32_t(Op::Offset) == KERF_TAPE_OFFSET && std::uint32_t(Op::Shell) == KERF_TAPE_SHELL);

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
    // Shapes, then the profiles (extrude, revolve), each once however many copies use it.
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
        if (s.polygon) {
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

// A profile where the encoder put it: `count` points (x, y
// pairs of floats) from word `first`, read as sdf::polygon2d's point list.
struct ProfileWords {
    const std::uint32_t* t;
    std::uint32_t first, count;
    std::size_t size() const { return count; }
    glm::vec2 operator[](std::size_t i) const
    {
        const std::uint32_t at = first + 2u * std::uint32_t(i);
        return {word(t, at), word(t, at + 1u)};
    }
};

// The shape at word `s` at tile-relative point p: the same sdf:: templates
// as every other evaluator (Primitives.hpp), for float or Dual<float>. Its
// local coordinates come from the frame's rows; as duals, each carries its
// row as its gradient.
template <class T> T shapeAt(const std::uint32_t* t, std::uint32_t s, const glm::vec3& p)
{
    const std::uint32_t f = s + KERF_TAPE_SHAPE_FRAME;
    T l[3];
    for (std::uint32_t row = 0; row < 3u; ++row) {
        const std::uint32_t r = f + 3u * row;
        const float v = word(t, r) * p.x + word(t, r + 1u) * p.y + word(t, r + 2u) * p.z + word(t, f + 9u + row);
        if constexpr (std::is_same_v<T, float>)
            l[row] = v;
        else
            l[row] = T(v, word(t, r), word(t, r + 1u), word(t, r + 2u));
    }
    const std::uint32_t a = s + KERF_TAPE_SHAPE_PARAMS;
    // A kind word beyond ShapeKind's range would wrap in the uint8 cast: NaN first.
    if (t[s] > 0xFFu) return T(std::numeric_limits<float>::quiet_NaN());
    const ProfileWords profile{t, t[a + 1u], t[a + 2u]}; // read only by profile kinds
    return primitiveDistance(ShapeKind(t[s]), l[0], l[1], l[2], [&](int i) { return T(word(t, a + std::uint32_t(i))); },
                             profile);
}

float valueOf(float v) { return v; }
float valueOf(const Dual<float>& v) { return v.v; }

// The tape's stack machine, once for values and once for values with
// gradients (and the deciding feature). A primitive that gives NaN (a kind
// this build does not know) makes the whole result NaN: a min or max could
// otherwise pass over it and show the rest of the part as if nothing were
// missing.
template <class T> T evaluate(const std::uint32_t* t, const glm::vec3& p, std::uint32_t* feature)
{
    const std::uint32_t count = t[0];
    const std::uint32_t shapes = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * count;
    T st[KERF_TAPE_MAX_STACK] = {};
    std::uint32_t fs[KERF_TAPE_MAX_STACK] = {};
    bool unknown = false;
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
            st[0] = shapeAt<T>(t, s, p);
            fs[0] = t[s + 1u];
            unknown = unknown || std::isnan(valueOf(st[0]));
        } else if (op <= KERF_TAPE_SMOOTH_MAX) {
            const T b = st[0], a = st[1];
            // The deciding feature: the operand the exact min/max would pick.
            const bool isMin = op == KERF_TAPE_MIN || op == KERF_TAPE_SMOOTH_MIN;
            // Within the tie band the left operand keeps it (FeatureTie.h).
            const double tie = KERF_FEATURE_TIE;
            const std::uint32_t f =
                (isMin ? valueOf(b) + tie < valueOf(a) : valueOf(a) + tie < valueOf(b)) ? fs[0] : fs[1];
            using std::max;
            using std::min;
            if (op == KERF_TAPE_MIN) st[0] = min(a, b);
            else if (op == KERF_TAPE_MAX) st[0] = max(a, b);
            else if (op == KERF_TAPE_SMOOTH_MIN) st[0] = combine::smoothMin(a, b, k);
            else st[0] = combine::smoothMax(a, b, k);
            fs[0] = f;
            for (int j = 1; j < KERF_TAPE_MAX_STACK - 1; ++j) {
                st[j] = st[j + 1];
                fs[j] = fs[j + 1];
            }
        } else if (op == KERF_TAPE_NEGATE) {
            st[0] = -st[0];
        } else if (op == KERF_TAPE_OFFSET) {
            st[0] = st[0] - T(k);
        } else {
            st[0] = combine::shell(st[0], k);
        }
    }
    if (feature) *feature = fs[0];
    return unknown ? T(std::numeric_limits<float>::quiet_NaN()) : st[0];
}

} // namespace

glm::vec4 evaluateTileTapeGradient(const std::uint32_t* t, const glm::vec3& p, std::uint32_t& feature)
{
    const Dual<float> d = evaluate<Dual<float>>(t, p, &feature);
    return {d.v, d.d[0], d.d[1], d.d[2]};
}

float evaluateTileTape(const std::uint32_t* t, const glm::vec3& p) { return evaluate<float>(t, p, nullptr); }

} // namespace kerf::voxel

#include "kerf/evaluator/Tape.hpp"

#include <stdexcept>

namespace kerf {

bool isBinary(Op op) { return op == Op::Min || op == Op::Max || op == Op::SmoothMin || op == Op::SmoothMax; }

Tape Tape::assemble(std::vector<Instruction> code, std::vector<ShapeInstance> shapes,
                    std::shared_ptr<const std::vector<Feature>> features, const glm::dvec3& origin,
                    const Aabb& bounds)
{
    Tape t;
    // Recompute spans and the stack depth with one pass of the stack machine.
    std::vector<std::uint32_t> spans;
    std::uint32_t deepest = 0;
    for (auto& ins : code) {
        if (ins.op == Op::Primitive) {
            if (ins.shape >= shapes.size()) throw std::logic_error("tape: shape index out of range");
            ins.span = 1;
        } else if (isBinary(ins.op)) {
            if (spans.size() < 2) throw std::logic_error("tape: binary operation without two operands");
            const auto r = spans.back();
            spans.pop_back();
            const auto l = spans.back();
            spans.pop_back();
            ins.rightSpan = r;
            ins.span = 1 + l + r;
        } else {
            if (spans.empty()) throw std::logic_error("tape: unary operation without an operand");
            ins.span = 1 + spans.back();
            spans.pop_back();
        }
        spans.push_back(ins.span);
        deepest = std::max<std::uint32_t>(deepest, static_cast<std::uint32_t>(spans.size()));
    }
    if (!code.empty() && spans.size() != 1) throw std::logic_error("tape: does not reduce to one value");
    t.code_ = std::move(code);
    t.shapes_ = std::move(shapes);
    if (features) t.features_ = std::move(features);
    t.maxStack_ = deepest;
    t.origin_ = origin;
    t.bounds_ = bounds;
    t.computeFrames();
    return t;
}

Tape Tape::rebased(const glm::dvec3& origin) const
{
    Tape t = *this;
    t.origin_ = origin;
    t.computeFrames();
    return t;
}

void Tape::computeFrames()
{
    // local = W * (origin + p) + w = W * p + (W * origin + w), all in double;
    // only the final, small numbers are rounded to float.
    for (auto& s : shapes_) {
        const auto& m = s.worldToLocal.linear;
        const glm::dvec3 t = s.worldToLocal.apply(origin_);
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) s.frame[static_cast<std::size_t>(r * 3 + c)] = m[c][r];
            s.frame[static_cast<std::size_t>(9 + r)] = t[r];
        }
        for (std::size_t i = 0; i < 12; ++i) s.frameF[i] = static_cast<float>(s.frame[i]);
    }
}

} // namespace kerf

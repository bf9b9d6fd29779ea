#include "kerf/evaluator/IntervalEvaluator.hpp"

#include "kerf/evaluator/Primitives.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <limits>

namespace kerf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Monotone smooth minimum in double; the interval image of a monotone
// function is given by its values at the ends.
double smin(double a, double b, double k)
{
    const double h = std::max(k - std::fabs(a - b), 0.0) / k;
    return std::min(a, b) - h * h * k * 0.25;
}
double smax(double a, double b, double k) { return -smin(-a, -b, k); }

// Widens a value computed with a few roundings by a relative margin far
// above their accumulated error (a handful of ulps).
double down(double v, double scale) { return v - (std::fabs(v) + scale) * 1e-14; }
double up(double v, double scale) { return v + (std::fabs(v) + scale) * 1e-14; }

} // namespace

Interval shapeInterval(const ShapeInstance& s, const Aabb& box)
{
    const auto& f = s.frame;
    const glm::dvec3 c = box.center();
    const glm::dvec3 half = 0.5 * box.size();

    // Lipschitz enclosure around the centre. The double evaluation of the
    // centre carries rounding error proportional to the magnitudes involved;
    // the margin covers it many times over.
    const double cx = f[0] * c.x + f[1] * c.y + f[2] * c.z + f[9];
    const double cy = f[3] * c.x + f[4] * c.y + f[5] * c.z + f[10];
    const double cz = f[6] * c.x + f[7] * c.y + f[8] * c.z + f[11];
    const double fc = shapeDistanceLocal<double>(s, cx, cy, cz);
    double scale = std::fabs(cx) + std::fabs(cy) + std::fabs(cz) + std::fabs(c.x) + std::fabs(c.y) + std::fabs(c.z);
    for (double p : s.param) scale += std::fabs(p);
    if (s.polygon)
        scale += std::max({std::fabs(s.polygon->min.x), std::fabs(s.polygon->min.y), std::fabs(s.polygon->max.x),
                           std::fabs(s.polygon->max.y)});
    const double radius = std::nextafter(glm::length(half), kInf);
    const double margin = (scale + 1.0) * 1e-12;
    Interval result{fc - radius - margin, fc + radius + margin};

    // The box mapped into the shape's local frame, as intervals per axis.
    const Interval X{box.min.x, box.max.x}, Y{box.min.y, box.max.y}, Z{box.min.z, box.max.z};
    const Interval lx = Interval(f[0]) * X + Interval(f[1]) * Y + Interval(f[2]) * Z + Interval(f[9]);
    const Interval ly = Interval(f[3]) * X + Interval(f[4]) * Y + Interval(f[5]) * Z + Interval(f[10]);
    const Interval lz = Interval(f[6]) * X + Interval(f[7]) * Y + Interval(f[8]) * Z + Interval(f[11]);
    return intersect(result, primitiveEnclosure(s, lx, ly, lz));
}

void IntervalEvaluator::run(const Tape& tape, const Aabb& box)
{
    const auto& code = tape.code();
    values_.resize(code.size());
    keep_.resize(code.size());
    stack_.clear();
    for (std::size_t i = 0; i < code.size(); ++i) {
        const Instruction& ins = code[i];
        Keep keep = Keep::Both;
        Interval v;
        if (ins.op == Op::Primitive) {
            v = shapeInterval(tape.shapes()[ins.shape], box);
        } else if (isBinary(ins.op)) {
            const Interval b = values_[stack_.back()];
            stack_.pop_back();
            const Interval a = values_[stack_.back()];
            stack_.pop_back();
            const double k = ins.k;
            switch (ins.op) {
            case Op::Min:
                v = min(a, b);
                if (a.hi < b.lo) keep = Keep::Left;
                else if (b.hi < a.lo) keep = Keep::Right;
                break;
            case Op::Max:
                v = max(a, b);
                if (a.lo > b.hi) keep = Keep::Left;
                else if (b.lo > a.hi) keep = Keep::Right;
                break;
            case Op::SmoothMin:
                v = {down(smin(a.lo, b.lo, k), k), up(smin(a.hi, b.hi, k), k)};
                // h = 0 wherever the operands stay at least k apart.
                if (a.hi + k < b.lo) keep = Keep::Left;
                else if (b.hi + k < a.lo) keep = Keep::Right;
                break;
            default:
                v = {down(smax(a.lo, b.lo, k), k), up(smax(a.hi, b.hi, k), k)};
                if (a.lo > b.hi + k) keep = Keep::Left;
                else if (b.lo > a.hi + k) keep = Keep::Right;
                break;
            }
        } else {
            const Interval a = values_[stack_.back()];
            stack_.pop_back();
            switch (ins.op) {
            case Op::Negate: v = -a; break;
            case Op::Offset: v = a - Interval(ins.k); break;
            default: {
                // max(d, -(d + t)) is convex in d with its minimum -t/2 at d = -t/2.
                const double t = ins.k;
                auto f = [t](double d) { return std::max(d, -(d + t)); };
                const double dmin = std::clamp(-0.5 * t, a.lo, a.hi);
                v = {down(f(dmin), t), up(std::max(f(a.lo), f(a.hi)), t)};
                break;
            }
            }
        }
        values_[i] = v;
        keep_[i] = keep;
        stack_.push_back(static_cast<std::uint32_t>(i));
    }
}

Interval IntervalEvaluator::evaluate(const Tape& tape, const Aabb& box)
{
    if (tape.empty()) return {kInf, kInf};
    run(tape, box);
    return values_.back();
}

Interval IntervalEvaluator::simplify(const Tape& tape, const Aabb& box, Tape& out)
{
    if (tape.empty()) {
        out = tape;
        return {kInf, kInf};
    }
    run(tape, box);
    const auto& code = tape.code();
    const std::size_t n = code.size();
    // live_: 0 dropped, 1 emitted, 2 passed through (a binary op that keeps
    // only one operand is replaced by that operand).
    live_.assign(n, 0);
    live_[n - 1] = 1;
    for (std::size_t i = n; i-- > 0;) {
        if (!live_[i]) continue;
        const Instruction& ins = code[i];
        if (ins.op == Op::Primitive) continue;
        if (isBinary(ins.op)) {
            const std::size_t right = i - 1, left = i - 1 - ins.rightSpan;
            switch (keep_[i]) {
            case Keep::Both: live_[left] = live_[right] = 1; break;
            case Keep::Left: live_[left] = 1; live_[i] = 2; break;
            case Keep::Right: live_[right] = 1; live_[i] = 2; break;
            }
        } else {
            live_[i - 1] = 1;
        }
    }
    std::vector<Instruction> newCode;
    std::vector<ShapeInstance> newShapes;
    newCode.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (live_[i] != 1) continue;
        Instruction ins = code[i];
        if (ins.op == Op::Primitive) {
            newShapes.push_back(tape.shapes()[ins.shape]);
            ins.shape = static_cast<std::uint32_t>(newShapes.size() - 1);
        }
        newCode.push_back(ins);
    }
    // A dropped subtree's instructions are never marked live, because only a
    // live parent marks its children: the emitted sequence is a valid post-order.
    out = Tape::assemble(std::move(newCode), std::move(newShapes), tape.sharedFeatures(), tape.origin(), tape.bounds());
    return values_[n - 1];
}

} // namespace kerf

#pragma once
// Closed intervals of doubles with outward rounding: every arithmetic result
// is widened by one ulp on each side, so that the true real-valued result of
// the operation on any points of the operand intervals lies inside, whatever
// the rounding of the hardware did (IEEE 754 rounds +, -, *, /, sqrt to
// within half an ulp). Comparisons (min, max, abs, negation) are exact and
// need no widening.

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>

namespace kerf {

struct Interval {
    double lo = 0.0;
    double hi = 0.0;

    constexpr Interval() = default;
    constexpr Interval(double v) : lo(v), hi(v) {}
    constexpr Interval(double l, double h) : lo(l), hi(h) {}

    bool contains(double v) const { return lo <= v && v <= hi; }
    double width() const { return hi - lo; }
    double mid() const { return 0.5 * (lo + hi); }
    bool positive() const { return lo > 0.0; }
    bool negative() const { return hi < 0.0; }
};

namespace interval_detail {
// The neighbouring doubles, by stepping the bit pattern (what nextafter does,
// inlined: this is the interval evaluator's innermost operation). Infinities
// and NaN are returned unchanged.
inline double up(double v)
{
    if (!(v < std::numeric_limits<double>::infinity())) return v; // +inf, NaN
    if (v == 0.0) return std::numeric_limits<double>::denorm_min();
    const auto bits = std::bit_cast<std::uint64_t>(v);
    return std::bit_cast<double>(v > 0.0 ? bits + 1 : bits - 1);
}
inline double down(double v) { return -up(-v); }
inline Interval widened(double lo, double hi) { return {down(lo), up(hi)}; }
} // namespace interval_detail

inline Interval operator+(Interval a, Interval b) { return interval_detail::widened(a.lo + b.lo, a.hi + b.hi); }
inline Interval operator-(Interval a, Interval b) { return interval_detail::widened(a.lo - b.hi, a.hi - b.lo); }
inline Interval operator-(Interval a) { return {-a.hi, -a.lo}; }
inline Interval operator*(Interval a, Interval b)
{
    // Zero times infinity would give NaN; intervals here stay finite because
    // every input is finite (the reader refuses non-finite numbers).
    const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    return interval_detail::widened(*std::min_element(p, p + 4), *std::max_element(p, p + 4));
}
inline Interval& operator+=(Interval& a, Interval b) { return a = a + b; }

inline Interval square(Interval a)
{
    // x^2 over an interval that straddles zero has its minimum at zero, which
    // plain multiplication (a * a) would miss: it treats the operands as
    // independent and gives a negative lower bound.
    const double l2 = a.lo * a.lo, h2 = a.hi * a.hi;
    if (a.lo >= 0.0) return interval_detail::widened(l2, h2);
    if (a.hi <= 0.0) return interval_detail::widened(h2, l2);
    return {0.0, interval_detail::up(std::max(l2, h2))};
}

inline Interval sqrt(Interval a)
{
    // Callers take square roots of sums of squares; a lower bound below zero
    // only comes from rounding and is clamped rather than turned into NaN.
    const double lo = a.lo <= 0.0 ? 0.0 : interval_detail::down(std::sqrt(a.lo));
    const double hi = a.hi <= 0.0 ? 0.0 : interval_detail::up(std::sqrt(a.hi));
    return {std::max(lo, 0.0), hi};
}

inline Interval abs(Interval a)
{
    if (a.lo >= 0.0) return a;
    if (a.hi <= 0.0) return -a;
    return {0.0, std::max(-a.lo, a.hi)};
}

inline Interval min(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)}; }
inline Interval max(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)}; }

/// Intersection of two sound enclosures of the same quantity is sound.
inline Interval intersect(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::min(a.hi, b.hi)}; }

inline Interval hull(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }

} // namespace kerf

#pragma once
// Forward-mode automatic differentiation with three partial derivatives
// (d/dx, d/dy, d/dz in the tape's frame). Comparisons look at values only, so
// a primitive's distance function written for plain scalars differentiates
// itself branch by branch.

#include <cmath>

namespace kerf {

template <class T> struct Dual {
    T v{};
    T d[3]{};

    constexpr Dual() = default;
    constexpr Dual(T value) : v(value) {}
    constexpr Dual(T value, T dx, T dy, T dz) : v(value), d{dx, dy, dz} {}
};

template <class T> Dual<T> operator+(const Dual<T>& a, const Dual<T>& b)
{
    return {a.v + b.v, a.d[0] + b.d[0], a.d[1] + b.d[1], a.d[2] + b.d[2]};
}
template <class T> Dual<T> operator-(const Dual<T>& a, const Dual<T>& b)
{
    return {a.v - b.v, a.d[0] - b.d[0], a.d[1] - b.d[1], a.d[2] - b.d[2]};
}
template <class T> Dual<T> operator-(const Dual<T>& a) { return {-a.v, -a.d[0], -a.d[1], -a.d[2]}; }
template <class T> Dual<T> operator*(const Dual<T>& a, const Dual<T>& b)
{
    return {a.v * b.v, a.d[0] * b.v + a.v * b.d[0], a.d[1] * b.v + a.v * b.d[1], a.d[2] * b.v + a.v * b.d[2]};
}
template <class T> Dual<T> operator/(const Dual<T>& a, const Dual<T>& b)
{
    const T inv = T(1) / b.v;
    const T q = a.v * inv;
    return {q, (a.d[0] - q * b.d[0]) * inv, (a.d[1] - q * b.d[1]) * inv, (a.d[2] - q * b.d[2]) * inv};
}
// Scaling by a plain number (a constant: no derivative to carry): a third of
// the work of the product and quotient rules, and no rounding from them.
template <class T> Dual<T> operator*(const Dual<T>& a, T s) { return {a.v * s, a.d[0] * s, a.d[1] * s, a.d[2] * s}; }
template <class T> Dual<T> operator*(T s, const Dual<T>& a) { return a * s; }
template <class T> Dual<T> operator/(const Dual<T>& a, T s) { return {a.v / s, a.d[0] / s, a.d[1] / s, a.d[2] / s}; }
template <class T> Dual<T>& operator+=(Dual<T>& a, const Dual<T>& b) { return a = a + b; }
template <class T> Dual<T>& operator*=(Dual<T>& a, const Dual<T>& b) { return a = a * b; }

template <class T> bool operator<(const Dual<T>& a, const Dual<T>& b) { return a.v < b.v; }
template <class T> bool operator>(const Dual<T>& a, const Dual<T>& b) { return a.v > b.v; }
template <class T> bool operator<=(const Dual<T>& a, const Dual<T>& b) { return a.v <= b.v; }
template <class T> bool operator>=(const Dual<T>& a, const Dual<T>& b) { return a.v >= b.v; }

template <class T> Dual<T> sqrt(const Dual<T>& a)
{
    using std::sqrt;
    const T s = sqrt(a.v);
    // The derivative of sqrt at 0 is infinite; the distance functions only
    // take sqrt of squared lengths, whose gradient is zero there, so the
    // product is 0 (a point exactly on an edge or axis: any normal will do).
    const T k = s > T(0) ? T(0.5) / s : T(0);
    return {s, a.d[0] * k, a.d[1] * k, a.d[2] * k};
}
template <class T> Dual<T> abs(const Dual<T>& a) { return a.v < T(0) ? -a : a; }
template <class T> Dual<T> min(const Dual<T>& a, const Dual<T>& b) { return b.v < a.v ? b : a; }
template <class T> Dual<T> max(const Dual<T>& a, const Dual<T>& b) { return a.v < b.v ? b : a; }

} // namespace kerf

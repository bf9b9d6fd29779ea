#pragma once
// The operations that combine distances, written once for every value type
// the point evaluators carry (float, double, Dual<float>, Dual<double>).
// Smooth booleans use the spec's polynomial smooth minimum:
//   smin(a, b) = min(a, b) - h*h*k/4,  h = max(k - |a - b|, 0) / k
// Callers never pass k = 0 here: exact booleans compile to Min/Max.

#include "kerf/evaluator/Dual.hpp"

#include <algorithm>
#include <cmath>

namespace kerf::combine {

using std::abs;
using std::max;
using std::min;

template <class V, class S> V smoothMin(const V& a, const V& b, S k)
{
    const V h = max(V(k) - abs(a - b), V(S(0))) * V(S(1) / k);
    return min(a, b) - h * h * V(k * S(0.25));
}

template <class V, class S> V smoothMax(const V& a, const V& b, S k)
{
    const V h = max(V(k) - abs(a - b), V(S(0))) * V(S(1) / k);
    return max(a, b) + h * h * V(k * S(0.25));
}

template <class V, class S> V shell(const V& a, S thickness) { return max(a, -(a + V(thickness))); }

} // namespace kerf::combine

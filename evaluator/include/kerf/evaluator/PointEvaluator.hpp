#pragma once
// Evaluates a tape at many points per call, in blocks of structure-of-arrays
// values (one array per stack slot), so that the inner loops run over points
// and vectorize.
//
// V is the value type: float or double for distances, Dual<float> or
// Dual<double> for distances with gradients (GradientEvaluator below wraps
// that). Points are relative to the tape's origin. An evaluator holds only
// scratch memory: one per thread, reused across tapes. Not thread-safe.

#include "kerf/evaluator/Dual.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace kerf {

template <class V> class PointEvaluator {
public:
    using Scalar = std::conditional_t<std::is_same_v<V, float> || std::is_same_v<V, Dual<float>>, float, double>;
    static constexpr std::size_t kBlock = 64;

    /// out[i] = field at (x[i], y[i], z[i]); features[i] (optional) = index
    /// into tape.features() of the feature that decides the value there. An
    /// empty tape gives +infinity.
    void evaluate(const Tape& tape, const Scalar* x, const Scalar* y, const Scalar* z, std::size_t n, V* out,
                  std::uint32_t* features = nullptr);

    V evaluate(const Tape& tape, Scalar x, Scalar y, Scalar z, std::uint32_t* feature = nullptr)
    {
        V v;
        evaluate(tape, &x, &y, &z, 1, &v, feature);
        return v;
    }

private:
    void evaluateBlock(const Tape& tape, const Scalar* x, const Scalar* y, const Scalar* z, std::size_t n, V* out,
                       std::uint32_t* features);

    std::vector<V> stack_;
    std::vector<std::uint32_t> featureStack_;
};

extern template class PointEvaluator<float>;
extern template class PointEvaluator<double>;
extern template class PointEvaluator<Dual<float>>;
extern template class PointEvaluator<Dual<double>>;

/// Distances and gradients (unnormalised normals) at many points.
template <class S> class GradientEvaluator {
public:
    void evaluate(const Tape& tape, const S* x, const S* y, const S* z, std::size_t n, S* distance, S* gx, S* gy,
                  S* gz, std::uint32_t* features = nullptr);
    /// Distance and gradient at one point.
    Dual<S> evaluate(const Tape& tape, S x, S y, S z) { return points_.evaluate(tape, x, y, z); }

private:
    PointEvaluator<Dual<S>> points_;
    std::vector<Dual<S>> scratch_;
};

extern template class GradientEvaluator<float>;
extern template class GradientEvaluator<double>;

} // namespace kerf

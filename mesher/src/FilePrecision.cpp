#include "kerf/mesher/FilePrecision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace kerf {

double float32Spacing(double x)
{
    const float f = float(std::min(std::abs(x), double(std::numeric_limits<float>::max()) / 2));
    return double(std::nextafter(f, std::numeric_limits<float>::infinity())) - double(f);
}

double float32Spacing(const Aabb& box)
{
    double m = 0.0;
    for (int a = 0; a < 3; ++a)
        m = std::max({m, std::abs(box.min[a]), std::abs(box.max[a])});
    return float32Spacing(m);
}

} // namespace kerf

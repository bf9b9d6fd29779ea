#include "kerf/accuracy/ErrorStats.hpp"

#include <algorithm>
#include <cmath>

namespace kerf {

ErrorStats summarizeErrors(std::vector<double>& values)
{
    ErrorStats s;
    s.count = values.size();
    if (values.empty()) return s;
    double sum = 0.0;
    for (double v : values) {
        sum += v;
        s.max = std::max(s.max, v);
    }
    s.mean = sum / double(values.size());
    // Nearest rank: the ceil(0.99 n)-th smallest value (1-based).
    const std::size_t rank = std::size_t(std::ceil(0.99 * double(values.size())));
    const auto nth = values.begin() + long(std::max<std::size_t>(rank, 1) - 1);
    std::nth_element(values.begin(), nth, values.end());
    s.p99 = *nth;
    return s;
}

} // namespace kerf

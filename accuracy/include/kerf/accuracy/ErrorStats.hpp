#pragma once
// A summary of many non-negative errors: mean, 99th percentile, maximum.

#include <cstddef>
#include <vector>

namespace kerf {

struct ErrorStats {
    std::size_t count = 0;
    double mean = 0.0;
    /// The nearest-rank 99th percentile: the smallest value that at least 99%
    /// of the values do not exceed.
    double p99 = 0.0;
    double max = 0.0;
};

/// Summarizes `values` (reordered in place, for the percentile). An empty
/// list gives zeros with count 0.
ErrorStats summarizeErrors(std::vector<double>& values);

} // namespace kerf

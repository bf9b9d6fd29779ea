#include "kerf/tracer/TraceQuality.hpp"

namespace kerf {

std::string_view traceQualityName(TraceQuality q) { return q == TraceQuality::Exact ? "exact" : "voxels"; }

std::optional<TraceQuality> parseTraceQuality(std::string_view name)
{
    if (name == "voxels") return TraceQuality::Voxels;
    if (name == "exact") return TraceQuality::Exact;
    return std::nullopt;
}

} // namespace kerf

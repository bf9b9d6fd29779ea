#include "kerf/tracer/TraceQuality.hpp"

namespace kerf {

std::string_view traceQualityName(TraceQuality q)
{
    switch (q) {
    case TraceQuality::Exact: return "exact";
    case TraceQuality::ExactEverywhere: return "exact-everywhere";
    case TraceQuality::Voxels: break;
    }
    return "voxels";
}

std::optional<TraceQuality> parseTraceQuality(std::string_view name)
{
    if (name == "voxels") return TraceQuality::Voxels;
    if (name == "exact") return TraceQuality::Exact;
    if (name == "exact-everywhere") return TraceQuality::ExactEverywhere;
    return std::nullopt;
}

} // namespace kerf

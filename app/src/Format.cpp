#include "kerf/app/Format.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace kerf {

std::string number(double v, int decimals)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

std::string mm(double v)
{
    // Tiny and huge lengths in significant digits: never "0" for 1e-9, never
    // 60 digits for 1e60.
    const double a = std::fabs(v);
    if (!std::isfinite(v) || (a > 0.0 && a < 0.001) || a >= 1e9) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.4g", v);
        return buf;
    }
    std::string s = number(v, 3);
    while (s.size() > 1 && s.back() == '0')
        s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    if (s == "-0") s = "0";
    return s;
}

std::string significant(double v, int digits)
{
    if (v == 0.0 || !std::isfinite(v)) return number(v, 0);
    int magnitude = int(std::floor(std::log10(std::abs(v))));
    if (magnitude < -4 || magnitude > 12) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.*e", digits - 1, v);
        return buf;
    }
    // Rounding may carry into the next power of ten (0.996 to 2 digits is 1.0).
    const double rounded = std::stod(number(std::abs(v), std::max(0, digits - 1 - magnitude)));
    if (rounded >= std::pow(10.0, magnitude + 1)) ++magnitude;
    return number(v, std::max(0, digits - 1 - magnitude));
}

std::string megabytes(std::uint64_t bytes) { return number(double(bytes) / 1e6, 1) + " MB"; }

std::string fileSize(std::uint64_t bytes)
{
    return bytes < 1000000 ? number(double(bytes) / 1e3, 1) + " kB" : megabytes(bytes);
}

} // namespace kerf

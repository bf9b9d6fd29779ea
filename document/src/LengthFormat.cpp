#include "kerf/document/LengthFormat.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>

namespace kerf {

namespace {

constexpr double kMmPerInch = 25.4;
// A length counts as a whole 64th when it is within this of one: the
// fields keep six decimals of a millimetre, and 3/4in is 19.05 in decimal
// but not in binary.
constexpr double kFractionSlackMm = 5e-7;

// Fixed decimals without trailing zeros: 18, 2.5, 0.708661; never "-0".
std::string trimmedDecimal(double v, int decimals)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    std::string s = buf;
    if (s.find('.') != std::string::npos) {
        while (s.back() == '0') s.pop_back();
        if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    return s;
}

// "11 3/4", "3/4", "12", "-1 1/2" for a count of 64ths.
std::string fractionText(std::int64_t sixtyFourths)
{
    const bool negative = sixtyFourths < 0;
    const std::int64_t n = negative ? -sixtyFourths : sixtyFourths;
    const std::int64_t whole = n / kInchDenominator;
    std::int64_t num = n % kInchDenominator;
    std::int64_t den = kInchDenominator;
    const std::int64_t g = std::gcd(num, den);
    if (num != 0) {
        num /= g;
        den /= g;
    }
    std::string s = negative ? "-" : "";
    if (whole != 0 || num == 0) s += std::to_string(whole);
    if (num != 0) s += (whole != 0 ? " " : "") + std::to_string(num) + "/" + std::to_string(den);
    return s;
}

// The nearest whole 64th, or nullopt when the length is beyond what an
// int64 of 64ths holds (no tape measure reaches there either).
std::optional<std::int64_t> nearestSixtyFourths(double mm)
{
    const double n = std::round(mm / kMmPerInch * kInchDenominator);
    if (!std::isfinite(n) || std::abs(n) > 1e15) return std::nullopt;
    return static_cast<std::int64_t>(n);
}

bool isWholeSixtyFourths(double mm, std::int64_t n)
{
    return std::abs(double(n) * kMmPerInch / kInchDenominator - mm) <= kFractionSlackMm;
}

} // namespace

std::string lengthForEditing(double mm, LengthUnit unit)
{
    if (unit == LengthUnit::Millimetres) return trimmedDecimal(mm, 6);
    if (const auto n = nearestSixtyFourths(mm); n && isWholeSixtyFourths(mm, *n)) return fractionText(*n) + "\"";
    return trimmedDecimal(mm / kMmPerInch, 6) + "\"";
}

std::string lengthReadout(double mm, LengthUnit unit, int mmDecimals)
{
    if (unit == LengthUnit::Millimetres) {
        // No "-0.00" for a difference that rounds to nothing.
        const double shown = std::abs(mm) < 0.5 * std::pow(10.0, -mmDecimals) ? 0.0 : mm;
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.*f mm", mmDecimals, shown);
        return buf;
    }
    const auto n = nearestSixtyFourths(mm);
    if (!n) return trimmedDecimal(mm / kMmPerInch, 3) + "\"";
    return (isWholeSixtyFourths(mm, *n) ? "" : "≈ ") + fractionText(*n) + "\"";
}

double bareLengthToMm(double value, LengthUnit unit)
{
    return unit == LengthUnit::Inches ? value * kMmPerInch : value;
}

std::string_view lengthUnitKey(LengthUnit unit) { return unit == LengthUnit::Inches ? "in" : "mm"; }

std::optional<LengthUnit> lengthUnitFromKey(std::string_view key)
{
    if (key == "mm") return LengthUnit::Millimetres;
    if (key == "in") return LengthUnit::Inches;
    return std::nullopt;
}

} // namespace kerf

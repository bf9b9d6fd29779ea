#include "kerf/app/Arguments.hpp"

#include "kerf/app/Format.hpp"
#include "kerf/document/Limits.hpp"
#include "kerf/document/PrintableText.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace kerf {

void refuseOverwriting(const std::string& output, const std::string& other, const std::string& role)
{
    namespace fs = std::filesystem;
    std::error_code a, b;
    bool same = false;
    if (fs::exists(output, a) && fs::exists(other, b)) {
        same = fs::equivalent(output, other, a) && !a; // the same file, by any name
    } else {
        // One of them is not there yet: the same name, once links and dots are resolved.
        const fs::path x = fs::weakly_canonical(output, a), y = fs::weakly_canonical(other, b);
        same = !a && !b && x == y;
    }
    if (same)
        throw RefusedRequest(printable(output) + " is " + role + " (" + printable(other) +
                             "); nothing was written: choose another output file");
}

Arguments::Arguments(const std::vector<std::string>& args, const std::vector<std::string>& valueOptions,
                     const std::vector<std::string>& flags)
{
    auto isIn = [](const std::vector<std::string>& v, const std::string& s) {
        return std::find(v.begin(), v.end(), s) != v.end();
    };
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a.size() > 1 && a[0] == '-') {
            std::string name = a, value;
            const auto eq = a.find('=');
            bool inlineValue = eq != std::string::npos && a.rfind("--", 0) == 0;
            if (inlineValue) {
                name = a.substr(0, eq);
                value = a.substr(eq + 1);
            } else if (a.rfind("-D", 0) == 0 && a.size() > 2 && isIn(valueOptions, "-D")) {
                // OpenSCAD's spelling without a space: -Dthickness=19
                name = "-D";
                value = a.substr(2);
                inlineValue = true;
            }
            if (isIn(flags, name) && !inlineValue) {
                flags_.push_back(name);
            } else if (isIn(valueOptions, name)) {
                if (!inlineValue) {
                    if (i + 1 >= args.size()) throw UsageError("option " + name + " needs a value");
                    value = args[++i];
                }
                values_.emplace_back(name, value);
            } else {
                throw UsageError("unknown option " + printable(name));
            }
        } else {
            positional_.push_back(a);
        }
    }
}

bool Arguments::has(const std::string& flag) const
{
    return std::find(flags_.begin(), flags_.end(), flag) != flags_.end();
}

std::optional<std::string> Arguments::value(const std::string& option) const
{
    std::optional<std::string> v;
    for (const auto& [name, value] : values_)
        if (name == option) v = value; // the last one wins
    return v;
}

std::vector<std::string> Arguments::values(const std::string& option) const
{
    std::vector<std::string> v;
    for (const auto& [name, value] : values_)
        if (name == option) v.push_back(value);
    return v;
}

std::vector<std::pair<std::string, std::string>> Arguments::defines() const
{
    std::vector<std::pair<std::string, std::string>> out;
    for (const std::string& d : values("-D")) {
        const auto eq = d.find('=');
        if (eq == std::string::npos || eq == 0)
            throw UsageError("-D wants NAME=VALUE (a parameter of the document and its new value), not '" + printable(d) + "'");
        out.emplace_back(d.substr(0, eq), d.substr(eq + 1));
    }
    return out;
}

namespace {
// A decimal number as people write one (12, 0.5, .5, 1e-3): strtod also
// reads hexadecimal ("0x10" was 16 mm), "inf" and "nan", and leading spaces.
bool isDecimal(const std::string& text)
{
    std::size_t i = 0, digits = 0;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) ++digits;
    if (i < text.size() && text[i] == '.')
        for (++i; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) ++digits;
    if (digits == 0) return false;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        std::size_t exponent = 0;
        for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) ++exponent;
        if (exponent == 0) return false;
    }
    return i == text.size();
}
} // namespace

double Arguments::parsePositiveMillimetres(const std::string& option, const std::string& text)
{
    if (!isDecimal(text))
        throw UsageError(option + " must be a positive number of millimetres, not '" + printable(text) + "'");
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || !(v > 0.0))
        throw UsageError(option + " must be a positive number of millimetres, not '" + printable(text) + "'");
    return v;
}

double Arguments::parseFeatureSize(const std::string& option, const std::string& text)
{
    const double v = parsePositiveMillimetres(option, text);
    if (v < limits::kMinFeatureSize || v > limits::kMaxFeatureSize)
        throw UsageError(option + " must be between " + mm(limits::kMinFeatureSize) + " and " +
                         mm(limits::kMaxFeatureSize) + " mm, not '" + printable(text) + "'");
    return v;
}

double Arguments::parseTolerance(const std::string& option, const std::string& text)
{
    if (!isDecimal(text))
        throw UsageError(option + " must be a number of millimetres (0 for none), not '" + printable(text) + "'");
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (!text.empty() && *end == '\0' && v == 0.0) return 0.0;
    if (!text.empty() && *end == '\0' && std::isfinite(v) && v < 0.0)
        throw UsageError(option + " must be a positive number of millimetres (0 for none), not '" + printable(text) +
                         "'");
    if (text.empty() || *end != '\0' || !std::isfinite(v) || !(v > 0.0))
        throw UsageError(option + " must be a number of millimetres (0 for none), not '" + printable(text) + "'");
    return parseFeatureSize(option, text);
}

ImageSize Arguments::parseImageSize(const std::string& option, const std::string& text)
{
    const auto x = text.find('x');
    ImageSize s;
    try {
        if (x == std::string::npos) throw std::invalid_argument("no x");
        std::size_t used = 0;
        s.width = std::stoi(text.substr(0, x), &used);
        if (used != x) throw std::invalid_argument("width");
        s.height = std::stoi(text.substr(x + 1), &used);
        if (used != text.size() - x - 1) throw std::invalid_argument("height");
    } catch (const std::exception&) {
        throw UsageError(option + " must be WIDTHxHEIGHT in pixels, like 1920x1080, not '" + printable(text) + "'");
    }
    if (s.width < 1 || s.height < 1 || s.width > 16384 || s.height > 16384)
        throw UsageError(option + " must be between 1x1 and 16384x16384, not '" + printable(text) + "'");
    if (long(s.width) * s.height > kMaxImagePixels)
        throw UsageError(option + " " + printable(text) + " is " + grouped(std::uint64_t(long(s.width) * s.height)) +
                         " pixels; a picture may have at most " + grouped(std::uint64_t(kMaxImagePixels)) +
                         " (8192x8192)");
    return s;
}

} // namespace kerf

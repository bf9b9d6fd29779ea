#include "Expression.hpp"

#include "kerf/document/Expression.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace kerf::ui {

namespace {

std::string trimmed(std::string_view s)
{
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return std::string(s);
}

bool endsWith(const std::string& s, std::string_view tail)
{
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

ExpressionResult evaluate(std::string_view text, std::string_view unit, bool wantLength, LengthUnit bareLength);

} // namespace

ExpressionResult evaluateExpression(std::string_view text, std::string_view unit)
{
    return evaluate(text, unit, unit == "mm", LengthUnit::Millimetres);
}

ExpressionResult evaluateLength(std::string_view text, LengthUnit shown)
{
    // The field's "mm" may trail the number shown; in inches a typed "mm"
    // is a unit the language reads ("300mm" stays 300 millimetres).
    return evaluate(text, shown == LengthUnit::Millimetres ? "mm" : "", true, shown);
}

namespace {

ExpressionResult evaluate(std::string_view text, std::string_view unit, bool wantLength, LengthUnit bareLength)
{
    ExpressionResult r;
    std::string expr = trimmed(text);
    // The field's unit may be typed (or left from the displayed value).
    // Typed after the number shown with its unit, a unit may come twice ("151 mm mm").
    for (bool again = true; again;) {
        again = false;
        for (std::string_view u : {unit, std::string_view(unit == "°" ? "deg" : "")})
            if (!u.empty() && endsWith(expr, u)) {
                expr = trimmed(std::string_view(expr).substr(0, expr.size() - u.size()));
                again = true;
            }
    }
    // A decimal comma, as typed on many European keyboards, when it cannot
    // be a separator (muparser's functions take several arguments).
    if (expr.find(',') != std::string::npos && expr.find('(') == std::string::npos)
        for (char& c : expr)
            if (c == ',') c = '.';
    if (expr.empty()) {
        r.error = "enter a number";
        return r;
    }
    try {
        // The document's own expression language (kerf/document/Expression.hpp):
        // lengths with units ("3/4in", "1.8cm"), the same functions; no names
        // here (a field takes a number; parameters live in their panel).
        expr::Resolver none;
        none.name = [](std::string_view n) -> expr::Quantity {
            throw expr::ExpressionError("'" + std::string(n) + "' is not a number or a unit");
        };
        // Another feature's value typed without the '=' that makes an
        // expression: said how (a newcomer's "box.size[0] + 20" was only
        // "not a number").
        none.field = [](std::string_view id, std::string_view path) -> expr::Quantity {
            throw expr::ExpressionError("'" + std::string(id) + "." + std::string(path) +
                                        "' is not a number (to use another feature's value, start with '=': =" +
                                        std::string(id) + "." + std::string(path) + ")");
        };
        none.bareLengthMm = bareLengthToMm(1.0, bareLength); // "3/4in + 1/8" in a field shown in inches
        const expr::Quantity q = expr::evaluate(expr, none);
        if (!q.fits(wantLength))
            throw expr::ExpressionError(wantLength ? "it is not a length" : "a length does not belong here");
        const double value = wantLength && q.bare ? bareLengthToMm(q.value, bareLength) : q.value;
        // To 12 significant digits: 2 3/8in is 60.325 mm, not the
        // 60.324999999999996 that 2.375 * 25.4 gives and the file then held.
        // A nanometre in a metre at most.
        char digits[32];
        std::snprintf(digits, sizeof digits, "%.12g", value);
        r.value = std::strtod(digits, nullptr);
    } catch (const expr::ExpressionError& e) {
        r.error = "cannot read '" + expr + "' as a number: " + e.what();
    }
    return r;
}

} // namespace

} // namespace kerf::ui

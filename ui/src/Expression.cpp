#include "Expression.hpp"

#include <muParser.h>

#include <cctype>
#include <cmath>

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

} // namespace

ExpressionResult evaluateExpression(std::string_view text, std::string_view unit)
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
        mu::Parser parser;
        parser.SetExpr(expr);
        const double v = parser.Eval();
        if (!std::isfinite(v)) {
            r.error = "'" + expr + "' is not a finite number";
            return r;
        }
        r.value = v;
    } catch (const mu::Parser::exception_type& e) {
        r.error = "cannot read '" + expr + "' as a number: " + e.GetMsg();
    }
    return r;
}

} // namespace kerf::ui

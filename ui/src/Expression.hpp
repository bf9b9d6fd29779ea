#pragma once
// Arithmetic a person types into a numeric field: "18*2", "450 - 2*18",
// "(300+2)/2", "sqrt(2)*10", "pi*25". Evaluated with muparser (Debian's
// libmuparser), so the grammar, precedence and functions are a well-kept
// library's, not ours. A trailing unit that matches the field ("mm", "°",
// "deg") is accepted and ignored. Qt-free.

#include <optional>
#include <string>
#include <string_view>

namespace kerf::ui {

struct ExpressionResult {
    std::optional<double> value; // finite, when the text is a valid expression
    std::string error;           // why not, in a sentence
};

/// Evaluates `text`; `unit` (e.g. "mm") may follow the expression.
ExpressionResult evaluateExpression(std::string_view text, std::string_view unit = {});

} // namespace kerf::ui

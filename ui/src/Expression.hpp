#pragma once
// Arithmetic a person types into a numeric field: "18*2", "450 - 2*18",
// "(300+2)/2", "sqrt(2)*10", "3/4in", "1.8cm". Evaluated in the document's
// own expression language (kerf/document/Expression.hpp), so a field reads
// what a parameter reads, lengths with units included (a length field
// takes inches and fractions of an inch, and keeps millimetres). A
// trailing unit that matches the field ("mm", "°", "deg") is accepted and
// ignored. Qt-free.

#include "kerf/document/LengthFormat.hpp"

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

/// Evaluates `text` for a length field whose lengths are shown in `shown`:
/// the result in millimetres; a number without a unit is in `shown` ("12"
/// is 12 inches when lengths are shown in inches); "mm" may follow.
ExpressionResult evaluateLength(std::string_view text, LengthUnit shown);

} // namespace kerf::ui

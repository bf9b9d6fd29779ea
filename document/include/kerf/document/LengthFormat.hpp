#pragma once
// How a length is shown to a person: in millimetres, or in inches and
// fractions of an inch (a woodworker's tape measure). Documents always hold
// millimetres; this is display only, and the text for editing reads back,
// in the expression language (Expression.hpp), as the same length.

#include <optional>
#include <string>
#include <string_view>

namespace kerf {

enum class LengthUnit { Millimetres, Inches };

/// The finest fraction of an inch shown: 1/64.
inline constexpr int kInchDenominator = 64;

/// Text for a field being edited, exact: "18", "-2.5" (millimetres, no
/// unit); "11 3/4\"", "-1/2\"" (a whole 64th of an inch) or "0.708661\""
/// (any other length, in decimal inches to a millionth). Read back by
/// expr::evaluate it gives the length again (to the decimals shown).
std::string lengthForEditing(double mm, LengthUnit unit);

/// Text for a readout, with its unit: "32.00 mm" (with `mmDecimals`);
/// "1 1/4\"" when the length is a whole 64th of an inch, otherwise the
/// nearest 64th after "≈ " ("≈ 45/64\"" for 18 mm).
std::string lengthReadout(double mm, LengthUnit unit, int mmDecimals = 2);

/// A number typed without a unit where a length belongs, in millimetres:
/// 12 is 12 mm, or 12 inches when lengths are shown in inches.
double bareLengthToMm(double value, LengthUnit unit);

/// "mm" or "in" (for settings files), and back (nullopt for anything else).
std::string_view lengthUnitKey(LengthUnit unit);
std::optional<LengthUnit> lengthUnitFromKey(std::string_view key);

} // namespace kerf

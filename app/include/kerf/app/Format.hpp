#pragma once
// How kerf's commands write numbers for people (the --json output writes
// plain numbers instead).

#include "kerf/document/GroupedNumber.hpp" // grouped(): counts with commas

#include <cstdint>
#include <string>

namespace kerf {

/// Fixed decimals: number(3.14159, 2) = "3.14".
std::string number(double v, int decimals);
/// A length as kerf prints it: up to 3 decimals, no trailing zeros ("0.5", "12");
/// below 0.001 or from 1e9 on, 4 significant digits ("1e-06", "1e+12").
std::string mm(double v);
/// Significant digits, no exponent from 1e-4 to 1e12: significant(0.012345, 3) = "0.0123",
/// significant(1e-6, 2) = "1.0e-06".
std::string significant(double v, int digits);
/// Decimal megabytes with one decimal: "10.2 MB".
std::string megabytes(std::uint64_t bytes);
/// A file's size as people read it: "17.9 kB" under a megabyte, else
/// megabytes ("0.0 MB" said nothing of a 17.9 kB export).
std::string fileSize(std::uint64_t bytes);

} // namespace kerf

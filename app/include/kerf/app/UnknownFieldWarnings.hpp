#pragma once
// The commands that read a document (check, render, export) warn on stderr of
// each field Kerf does not know (kerf/document/UnknownFields.hpp): a
// misspelt field is one the part goes without, and the command's output
// alone would not show it.

#include "kerf/document/Document.hpp"

#include <ostream>
#include <string>

namespace kerf {

/// "kerf CMD: warning: feature 'leg': field 'transfom' is not one Kerf
/// knows: ..." for each, at most ten, then how many more.
void warnOfUnknownFields(const Document& doc, const std::string& command, std::ostream& err);

} // namespace kerf

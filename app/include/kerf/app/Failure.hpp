#pragma once
// What a command prints when its work fails with an exception: one line in
// words, never an exception's type name ("std::bad_alloc") or a library's
// internals ("vector::_M_default_append"), with user text escaped.

#include <exception>
#include <string>

namespace kerf {

/// "ran out of memory ..." for std::bad_alloc, "the request is too large
/// for this program" for std::length_error, else the exception's message,
/// escaped to one line.
std::string describeFailure(const std::exception& e);

} // namespace kerf

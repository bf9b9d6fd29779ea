#pragma once
// User text (ids, names, paths, keys) made safe to print on one line of a
// terminal or a log: every control character (newline, escape, NUL, the C1
// range), every invisible formatting character that can reorder or hide text
// (bidirectional overrides, zero-width characters, line and paragraph
// separators) and every byte that is not UTF-8 is written as an escape
// (\n, \t, \x1b, \u202e); very long text is shortened in the middle of
// nothing: its start is kept, and the line says how long it was.

#include <cstddef>
#include <string>
#include <string_view>

namespace kerf {

/// The printable form of `text`; at most about `maxBytes` bytes of it are
/// kept (then "...", and the original length).
std::string printable(std::string_view text, std::size_t maxBytes = 200);

} // namespace kerf

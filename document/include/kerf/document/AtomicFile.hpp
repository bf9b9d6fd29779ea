#pragma once
// Writes a file whole or not at all: the bytes go to a temporary file in the
// same folder, are flushed to disk, and the temporary replaces the target by
// rename(2). On any failure the target is untouched and the temporary removed.

#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

namespace kerf {

/// Throws std::runtime_error naming the file and the system's reason.
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);

/// As above, for output produced by a writer function (large files).
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(std::ostream&)>& writer);

} // namespace kerf

#pragma once
// Every file Kerf writes (documents, autosaves, STL, PNG, JSON, CSV) goes
// through here, and only ever becomes a regular file, whole or not at all:
//
// - checkOutputFile() runs before any work: a target that exists and is not a
//   regular file (a folder, a device, a FIFO, a socket, a symbolic link to one
//   of those or to nothing) is refused, and so is a folder that does not exist
//   or cannot be written (found by creating and removing a file there), so
//   that minutes of meshing never end in "cannot write".
// - A symbolic link to a regular file is followed: the file it points to is
//   replaced and the link stays a link (as an editor saving through a link
//   does); the temporary file is made in the link target's folder.
// - writeFileAtomically() checks again, writes a temporary file beside the
//   target (created with mode 0666 less the umask, like any new file; a file
//   that is replaced keeps its permissions), flushes it to disk and renames it
//   over the target. On any failure the target is untouched and the
//   temporary removed. Ctrl+C, SIGTERM or SIGHUP during the write (where the
//   program has not taken them over itself) are held until the temporary file
//   is removed, then take effect: no partial file is ever left.

#include <filesystem>
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string_view>

namespace kerf {

/// A refused or failed output. what() is one line naming the file (escaped).
class OutputFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Checks that `target` may be written as a regular file, before any work.
/// Returns the file that will actually be written (a symbolic link resolved).
/// Throws OutputFileError.
std::filesystem::path checkOutputFile(const std::filesystem::path& target);

/// Throws OutputFileError naming the file and the system's reason.
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);

/// As above, for output produced by a writer function (large files).
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(std::ostream&)>& writer);

} // namespace kerf

#pragma once
// Names what a path is, for messages: "a folder", "a character device", ...

#include <string>
#include <sys/types.h>

namespace kerf {

/// "a regular file", "a folder", "a character device", "a block device",
/// "a named pipe (FIFO)", "a socket", "a symbolic link", from a stat mode.
std::string describeFileKind(mode_t mode);

} // namespace kerf

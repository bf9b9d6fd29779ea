#pragma once
// Reads a document file's bytes, refusing before reading what is not a
// document: a folder, a device or a socket (each named as what it is), and
// anything larger than limits::kMaxDocumentBytes (a regular file by its
// size, a pipe once it has delivered that much). Throws DocumentError.

#include <filesystem>
#include <string>

namespace kerf::detail {

std::string readDocumentFile(const std::filesystem::path& file);

} // namespace kerf::detail

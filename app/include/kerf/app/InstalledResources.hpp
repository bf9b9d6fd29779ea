#pragma once
// Where kerf finds the files it ships with (the bundled example parts).
// An installed kerf looks beside itself: <prefix>/bin/kerf finds
// <prefix>/share/kerf/examples, whatever the prefix, so a package, a
// `cmake --install --prefix ANYWHERE` and a moved install tree all work.
// A kerf run from its build tree, where nothing is installed, falls back to
// the source tree's resources/examples. No Qt, no Vulkan.

#include <filesystem>

namespace kerf {

/// The folder of bundled example parts, for the running executable.
std::filesystem::path examplesDirectory();

/// The bundled side chair: the part the application opens when given no file.
std::filesystem::path defaultExample();

/// examplesDirectory() as an executable at `executable` would see it: the
/// installed folder relative to it when that folder exists, else the source
/// tree's. (The running program's answer comes from /proc/self/exe.)
std::filesystem::path examplesDirectoryFor(const std::filesystem::path& executable);

} // namespace kerf

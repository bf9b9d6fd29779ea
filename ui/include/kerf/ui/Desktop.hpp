#pragma once
// The desktop application's entry point (kerf with no subcommand).

#include <filesystem>
#include <optional>

namespace kerf::ui {

/// Runs the application on `file`, or on `defaultExample` (the bundled part,
/// whose folder also marks the examples that open as untitled copies).
/// Returns the process's exit status. The caller says where the installed
/// files are: the desktop shell knows nothing of the installation.
int runDesktop(int argc, char** argv, const std::optional<std::filesystem::path>& file,
               const std::filesystem::path& defaultExample);

} // namespace kerf::ui

#pragma once
// The desktop application's entry point (kerf with no subcommand).

#include <filesystem>
#include <optional>

namespace kerf::ui {

/// Runs the application on `file`, or on the bundled example part. Returns
/// the process's exit status.
int runDesktop(int argc, char** argv, const std::optional<std::filesystem::path>& file);

} // namespace kerf::ui

#include "kerf/app/InstalledResources.hpp"

#include <system_error>

// Both come from app/CMakeLists.txt: the install layout (bin -> share/kerf/examples,
// from GNUInstallDirs) and the source tree, for a build tree that is not installed.
#ifndef KERF_INSTALLED_EXAMPLES_RELATIVE
#error "KERF_INSTALLED_EXAMPLES_RELATIVE must be defined by the build"
#endif
#ifndef KERF_EXAMPLES_DIR
#error "KERF_EXAMPLES_DIR must be defined by the build"
#endif

namespace kerf {

std::filesystem::path examplesDirectoryFor(const std::filesystem::path& executable)
{
    const std::filesystem::path installed =
        (executable.parent_path() / KERF_INSTALLED_EXAMPLES_RELATIVE).lexically_normal();
    std::error_code ec;
    if (std::filesystem::is_directory(installed, ec)) return installed;
    return std::filesystem::path(KERF_EXAMPLES_DIR);
}

std::filesystem::path examplesDirectory()
{
    // The kernel's link to the running binary: symlinks to kerf (say from
    // /usr/local/bin) resolve to where it really lives, beside its share/.
    std::error_code ec;
    const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return std::filesystem::path(KERF_EXAMPLES_DIR); // no /proc (a bare chroot)
    return examplesDirectoryFor(executable);
}

std::filesystem::path defaultExample() { return examplesDirectory() / "side-chair.kerf"; }

} // namespace kerf

// kerf: the command-line entry point. Subcommands run headless; with no
// subcommand kerf opens the desktop application.

#include "kerf/app/Commands.hpp"
#include "kerf/app/InstalledResources.hpp"
#include "kerf/app/TradePlot.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/ui/Desktop.hpp"

#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace kerf {

std::string mainHelp()
{
    return R"(Usage: kerf [FILE.kerf]
  or:  kerf COMMAND [OPTIONS]

Kerf models furniture parts as implicit solids: a feature tree of primitives,
booleans, blends, offsets, shells, arrays and mirrors, in millimetres.

Commands:
  check FILE.kerf      load and validate a document; print its feature count,
                       bounding box, feature size and voxel memory
  export FILE.kerf -o OUT.stl|OUT.3mf [--tolerance MM] [--feature-size MM]
         [--ascii]     mesh the part (marching cubes on the exact field,
                       sharp edges kept, simplified to a tolerance: 0.05 mm
                       unless told) and
                       write it as STL or 3MF; print the mesh as a reader
                       of the file gets it
  render FILE.kerf -o OUT.png [--size WxH] [--view iso|front|top|...]
         [--quality voxels|exact|exact-everywhere]
                       voxelize and trace the part with the Vulkan compute
                       tracer, headless, and write the image; exact refines
                       the surface on the exact field (sharp edges)
  bench [FILE.kerf] [--feature-sizes LIST] [--json OUT.json] [--plot OUT.png]
                       measure speed against accuracy at each feature size:
                       voxelize, re-voxelize and trace times, GPU memory, the
                       picture's and the exported mesh's error against the
                       exact part (default part: the bundled side chair)

Options:
  --help               show this help (also: kerf COMMAND --help)
  --version            show the version

Exit status: 0 success, 1 the work failed, 2 bad usage or a bad input file.
)";
}

namespace {

// kerf, kerf FILE.kerf, or Qt's own options (-platform xcb, -style fusion)
// before either: the desktop application; anything else is a subcommand.
bool opensDesktop(const std::vector<std::string>& args)
{
    if (args.empty()) return true;
    const std::string& first = args.front();
    if (first.size() > 5 && first.ends_with(".kerf")) return true;
    return first.size() > 1 && first[0] == '-' && first[1] != '-' && first != "-h";
}

} // namespace

} // namespace kerf

int main(int argc, char** argv)
{
    std::vector<std::string> args(argv + 1, argv + argc);
    // No subcommand: the desktop application, on the bundled example or on
    // the document named (a double-click on a .kerf file).
    const bool desktop = kerf::opensDesktop(args);
    if (desktop) {
        std::optional<std::filesystem::path> file;
        for (const auto& a : args)
            if (a.size() > 5 && a.ends_with(".kerf")) file = a;
        return kerf::ui::runDesktop(argc, argv, file, kerf::defaultExample());
    }
    const std::string command = args.front();
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    if (command == "--help" || command == "-h" || command == "help") {
        std::cout << kerf::mainHelp();
        return 0;
    }
    if (command == "--version") {
        std::cout << "kerf " << KERF_VERSION << "\n";
        return 0;
    }
    if (command == "check") return kerf::runCheck(rest, std::cout, std::cerr);
    if (command == "export") return kerf::runExport(rest, std::cout, std::cerr);
    if (command == "render") return kerf::runRender(rest, std::cout, std::cerr);
    if (command == "bench") return kerf::runBench(rest, std::cout, std::cerr, kerf::writeTradePlot);
    std::cerr << "kerf: unknown command '" << kerf::printable(command) << "' (see kerf --help)\n";
    return 2;
}

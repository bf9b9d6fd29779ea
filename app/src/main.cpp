// kerf: the command-line entry point. Subcommands run headless; with no
// subcommand kerf opens the desktop application.

#include "kerf/app/Commands.hpp"
#include "kerf/app/TradePlot.hpp"

#include <iostream>
#include <string>
#include <vector>

namespace kerf {

std::string mainHelp()
{
    return R"(Usage: kerf [FILE.kerf]
       kerf COMMAND [OPTIONS]

Kerf models furniture parts as implicit solids: a feature tree of primitives,
booleans, blends, offsets, shells, arrays and mirrors, in millimetres.

Commands:
  check FILE.kerf      load and validate a document; print its feature count,
                       bounding box, feature size and voxel memory
  export FILE.kerf -o OUT.stl [--feature-size MM] [--ascii]
                       mesh the part (marching cubes on the exact field) and
                       write it as STL, binary by default; print triangles,
                       time and the mesh's closedness
  render FILE.kerf -o OUT.png [--size WxH] [--view iso|front|top|...]
                       voxelize and trace the part with the Vulkan compute
                       tracer, headless, and write the image
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

} // namespace kerf

int main(int argc, char** argv)
{
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) {
        std::cerr << "kerf: the desktop application is not part of this build yet; "
                     "use a subcommand (kerf --help)\n";
        return 2;
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
    std::cerr << "kerf: unknown command '" << command << "' (see kerf --help)\n";
    return 2;
}

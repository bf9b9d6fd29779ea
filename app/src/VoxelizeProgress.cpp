#include "kerf/app/VoxelizeProgress.hpp"

#include "kerf/app/Format.hpp"

#include <unistd.h>

namespace kerf {

VoxelSnapshot voxelizeWithProgress(const Tape& tape, const GridLayout& layout, const std::string& prefix,
                                   bool longWork, std::ostream& err)
{
    const bool shown = longWork && ::isatty(STDERR_FILENO);
    int percent = -1;
    Progress work;
    if (shown)
        work = Progress([&](double fraction) {
            const int p = int(fraction * 100.0);
            if (p == percent) return;
            percent = p;
            err << "\r" << prefix << ": voxelizing at " << mm(layout.voxelSize) << " mm... " << p << "% (Ctrl+C stops)"
                << std::flush;
        });
    VoxelSnapshot snap = voxelize(tape, layout, {}, work);
    if (shown) err << "\r\033[K" << std::flush;
    return snap;
}

} // namespace kerf

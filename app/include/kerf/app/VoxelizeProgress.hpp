#pragma once
// voxelize() for the commands: with a percentage on stderr while it runs
// when that is a terminal and the work is long enough to need one.

#include "kerf/voxelizer/Voxelize.hpp"

#include <ostream>
#include <string>

namespace kerf {

/// `prefix` starts the progress line ("kerf render"); `long` says whether
/// the estimate expects more than a couple of seconds.
VoxelSnapshot voxelizeWithProgress(const Tape& tape, const GridLayout& layout, const std::string& prefix,
                                   bool longWork, std::ostream& err);

} // namespace kerf

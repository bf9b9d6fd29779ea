#pragma once
// What kerf export checks before it meshes anything (issue 14), kept out of
// ExportCommand.cpp so that the exporter can change without touching it:
//  - the output is, or can become, a regular file in a folder that takes
//    new files (checkOutputFile): a device, a FIFO, a folder or a link to one
//    is refused and left as it is;
//  - the mesh fits this machine's request budget (RequestBudget.hpp), else
//    the refusal says what it would take and which feature size would fit.

#include "kerf/document/Document.hpp"
#include "kerf/voxelizer/RequestBudget.hpp"

#include <filesystem>
#include <string>

namespace kerf {

/// Throws RefusedRequest (exit 2) with the whole message line. Returns the
/// estimate (its seconds tell whether to show progress).
RequestCost preflightExport(const Document& doc, const std::string& file, const std::filesystem::path& target,
                            double featureSize, double tolerance);

} // namespace kerf

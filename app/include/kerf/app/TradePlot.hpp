#pragma once
// `kerf bench --plot`: the speed/accuracy trade as a PNG, drawn with Qt
// Charts. Two log-log panels side by side, error against time and error
// against memory, one labelled point per feature size: the picture's depth
// error (99th percentile) against the cold voxelization time and the GPU
// buffers, and the mesh's largest distance to the exact surface against the
// export time and the binary STL's size.
//
// Needs no display: when the program has no QApplication yet, one is made
// for the call on Qt's offscreen platform (set for that application only,
// through its arguments), so kerf check, render and export never touch Qt.

#include "kerf/app/TradeBench.hpp"

#include <filesystem>
#include <string>

namespace kerf {

/// Draws `report` titled with `title` (the part's file name) and writes the
/// PNG whole or not at all. Throws std::runtime_error naming the file.
void writeTradePlot(const TradeReport& report, const std::string& title, const std::filesystem::path& png);

} // namespace kerf

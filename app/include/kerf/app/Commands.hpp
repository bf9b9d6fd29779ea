#pragma once
// kerf's headless subcommands. Each returns the process exit status:
// 0 success, 1 the work failed, 2 bad usage or a bad input file.

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace kerf {

struct TradeReport;

/// Draws `kerf bench`'s trade as a PNG (titled `title`) at the path, whole or
/// not at all; throws std::runtime_error on failure. The kerf program passes
/// one built on Qt Charts; a headless program passes none and --plot is then
/// refused.
using TradePlotter =
    std::function<void(const TradeReport& report, const std::string& title, const std::filesystem::path& png)>;

int runCheck(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int runExport(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int runRender(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int runBench(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
             const TradePlotter& plot = {});

std::string mainHelp();

} // namespace kerf

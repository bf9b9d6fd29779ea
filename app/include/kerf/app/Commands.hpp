#pragma once
// kerf's headless subcommands. Each returns the process exit status:
// 0 success, 1 the work failed, 2 bad usage or a bad input file.

#include <iosfwd>
#include <string>
#include <vector>

namespace kerf {

int runCheck(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int runExport(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int runRender(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

std::string mainHelp();

} // namespace kerf

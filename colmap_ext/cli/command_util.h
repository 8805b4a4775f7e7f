#pragma once
// Small helpers shared by the `colmap-mp` commands.
#include <string>
#include <vector>

#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/evaluation/evaluation_report.h"

namespace mpmvs {

// "colmap-mp COMMAND ARGS..." with arguments quoted where needed (for result files).
std::string CommandLine(const std::string& command, const std::vector<std::string>& args);

// Last component of a path, trailing slashes ignored.
std::string Basename(std::string path);

// Prints the usage and the parser's option list; returns true.
bool ShowHelp(const OptionParser& parser, const std::string& usage);

// Command line and source revision for a report (commit: given, else DetectSourceCommit()).
ReportContext MakeContext(const std::string& command, const std::vector<std::string>& args,
                          const std::string& commit);

// Source revision for result files: $MPMVS_COMMIT, else `git rev-parse --short HEAD` in
// the current directory, else "unknown".
std::string DetectSourceCommit();

}  // namespace mpmvs

#include "colmap_ext/cli/command_util.h"

#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace mpmvs {

std::string CommandLine(const std::string& command, const std::vector<std::string>& args) {
  std::string line = "colmap-mp " + command;
  for (const std::string& a : args) {
    line += " ";
    line += a.find_first_of(" \t\"'") == std::string::npos ? a : "'" + a + "'";
  }
  return line;
}

std::string Basename(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

bool ShowHelp(const OptionParser& parser, const std::string& usage) {
  std::cout << "Usage: " << usage << "\n\nOptions:\n" << parser.Help();
  return true;
}

ReportContext MakeContext(const std::string& command, const std::vector<std::string>& args,
                          const std::string& commit) {
  ReportContext context;
  context.command = CommandLine(command, args);
  context.commit = commit.empty() ? DetectSourceCommit() : commit;
  return context;
}

std::string DetectSourceCommit() {
  if (const char* env = std::getenv("MPMVS_COMMIT")) {
    if (*env) return env;
  }
  std::string out;
  if (FILE* pipe = popen("git rev-parse --short HEAD 2>/dev/null", "r")) {
    char buf[128];
    while (std::fgets(buf, sizeof(buf), pipe)) out += buf;
    pclose(pipe);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out.empty() ? "unknown" : out;
}

}  // namespace mpmvs

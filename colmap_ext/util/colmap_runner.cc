#include "colmap_ext/util/colmap_runner.h"

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "colmap_ext/util/error.h"

namespace mpmvs {

std::string ColmapExecutableName() {
  const char* env = std::getenv("MPMVS_COLMAP_EXE");
  return env && *env ? env : "colmap";
}

namespace {

std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

}  // namespace

bool ColmapAvailable() {
  const std::string exe = ColmapExecutableName();
  std::error_code ec;
  if (exe.find('/') != std::string::npos) return std::filesystem::is_regular_file(exe, ec);
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (std::filesystem::is_regular_file(std::filesystem::path(dir) / exe, ec)) return true;
  }
  return false;
}

int RunColmap(const std::vector<std::string>& args, const std::string& log_path) {
  std::string command = ShellQuote(ColmapExecutableName());
  for (const std::string& a : args) command += " " + ShellQuote(a);
  command += " >> " + ShellQuote(log_path) + " 2>&1";
  const int status = std::system(command.c_str());
  if (status == -1 || !WIFEXITED(status)) return 127;
  return WEXITSTATUS(status);
}

void RunStereoFusion(const std::string& workspace_path, const std::string& input_type,
                     const std::string& output_path, int num_images, const std::string& log_path) {
  const int min_num_pixels = std::max(1, std::min(5, num_images - 1));
  const int code = RunColmap({"stereo_fusion", "--workspace_path", workspace_path, "--workspace_format",
                              "COLMAP", "--input_type", input_type, "--output_path", output_path,
                              "--StereoFusion.num_threads", "1", "--StereoFusion.min_num_pixels",
                              std::to_string(min_num_pixels)},
                             log_path);
  if (code != 0) {
    throw Error("colmap stereo_fusion failed with exit code " + std::to_string(code) + "; see " + log_path);
  }
}

}  // namespace mpmvs

// colmap-mp: COLMAP's command line with mp_patch_match_stereo added. Our own commands run
// here, and so does COLMAP's patch_match_stereo (as mp_patch_match_stereo, which takes its
// options); every other command is handed to the `colmap` executable unchanged (arguments and
// exit code), so existing scripts only rename the binary.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/cli/commands.h"
#include "colmap_ext/util/colmap_runner.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"

namespace {

using Command = std::function<int(const std::vector<std::string>&)>;

// COLMAP's name for the dense step: a script written for `colmap` runs MP-MVS when it calls
// colmap-mp instead. Stock COLMAP's stays reachable as `colmap patch_match_stereo`.
int RunPatchMatchStereoUnderColmapsName(const std::vector<std::string>& args) {
  mpmvs::LogInfo("colmap-mp patch_match_stereo runs MP-MVS (mp_patch_match_stereo); COLMAP's own is `" +
                 mpmvs::ColmapExecutableName() + " patch_match_stereo`");
  return mpmvs::RunMpPatchMatchStereoCommand(args);
}

const std::vector<std::pair<std::string, std::pair<Command, std::string>>>& Commands() {
  static const std::vector<std::pair<std::string, std::pair<Command, std::string>>> commands = {
      {"mp_patch_match_stereo", {mpmvs::RunMpPatchMatchStereoCommand,
                                 "MP-MVS depth/normal maps for a COLMAP dense workspace"}},
      {"patch_match_stereo", {RunPatchMatchStereoUnderColmapsName,
                              "the same under COLMAP's name (COLMAP's own: colmap patch_match_stereo)"}},
      {"slurm_submit", {mpmvs::RunSlurmSubmitCommand,
                        "run mp_patch_match_stereo on a Slurm cluster: one job array per stage"}},
      {"demo", {mpmvs::RunDemoCommand,
                "synthetic indoor scene -> mp_patch_match_stereo -> colmap stereo_fusion -> evaluation"}},
      {"generate_scene", {mpmvs::RunGenerateSceneCommand,
                          "render a synthetic scene with exact ground truth as a dense workspace"}},
      {"evaluate", {mpmvs::RunEvaluateCommand, "score depth maps / fused points against ground truth"}},
      {"compare", {mpmvs::RunCompareCommand, "score several workspaces of one scene side by side"}},
      {"ablation", {mpmvs::RunAblationCommand,
                    "the paper's Table 1 (ACMH ... mPM+rs+gp) on one scene, scored against GT"}},
  };
  return commands;
}

void PrintHelp() {
  std::cout << "colmap-mp " << MPMVS_VERSION_STRING
            << " -- MP-MVS multi-view stereo for COLMAP workspaces\n\n"
               "Usage:\n  colmap-mp COMMAND [OPTIONS]\n  colmap-mp COMMAND -h\n  colmap-mp --version\n\n"
               "mp-mvs commands:\n";
  for (const auto& c : Commands()) {
    std::printf("  %-22s %s\n", c.first.c_str(), c.second.second.c_str());
  }
  std::cout << "\nEvery other command (stereo_fusion, image_undistorter, feature_extractor, ...)\n"
               "is run by COLMAP: colmap-mp passes it with its arguments to `"
            << mpmvs::ColmapExecutableName()
            << "`\n(set MPMVS_COLMAP_EXE to use another colmap executable).\n";
}

}  // namespace

#ifndef MPMVS_VERSION_STRING
#define MPMVS_VERSION_STRING "0.1.0"
#endif

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "help" || std::string(argv[1]) == "-h" ||
      std::string(argv[1]) == "--help") {
    PrintHelp();
    return argc < 2 ? 1 : 0;
  }
  const std::string command = argv[1];
  if (command == "version" || command == "--version") {
    std::cout << "colmap-mp " << MPMVS_VERSION_STRING << "\n";
    return 0;
  }
  for (const auto& c : Commands()) {
    if (c.first != command) continue;
    try {
      return c.second.first(std::vector<std::string>(argv + 2, argv + argc));
    } catch (const mpmvs::Error& e) {
      mpmvs::LogError(e.what());
      return 1;
    } catch (const std::exception& e) {
      mpmvs::LogError(std::string("unexpected failure: ") + e.what());
      return 1;
    }
  }
  // Not ours: hand it to colmap, replacing this process so the exit code is colmap's.
  const std::string colmap = mpmvs::ColmapExecutableName();
  std::vector<char*> colmap_argv;
  colmap_argv.push_back(const_cast<char*>(colmap.c_str()));
  for (int i = 1; i < argc; ++i) colmap_argv.push_back(argv[i]);
  colmap_argv.push_back(nullptr);
  execvp(colmap.c_str(), colmap_argv.data());
  std::fprintf(stderr, "ERROR: `%s` is not an mp-mvs command and the colmap executable `%s` could not be run: %s\n"
               "Install COLMAP (apt-get install colmap) or set MPMVS_COLMAP_EXE.\n",
               command.c_str(), colmap.c_str(), std::strerror(errno));
  return 127;
}

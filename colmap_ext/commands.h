#pragma once
// Command functions of `colmap-mp` (argv without program and command name). Each returns
// the process exit code; errors are thrown as mpmvs::Error and printed by main().
#include <string>
#include <vector>

namespace mpmvs {

int RunMpPatchMatchStereoCommand(const std::vector<std::string>& args);
int RunDemoCommand(const std::vector<std::string>& args);
int RunAblationCommand(const std::vector<std::string>& args);

// The `colmap` executable to hand other commands to: --colmap_path is handled by main;
// else $MPMVS_COLMAP_EXE, else "colmap" on PATH.
std::string ColmapExecutableName();

}  // namespace mpmvs

#pragma once
// Command functions of `colmap-mp` (argv without program and command name). Each returns
// the process exit code; errors are thrown as mpmvs::Error and printed by main().
#include <string>
#include <vector>

namespace mpmvs {

class WorkspaceIo;

int RunMpPatchMatchStereoCommand(const std::vector<std::string>& args);
// The same command reading and writing through io (not owned); program names the
// executable in the usage text ("colmap-mp", "colmap").
int RunMpPatchMatchStereoCommandWithIo(const std::vector<std::string>& args, WorkspaceIo* io,
                                       const std::string& program);
int RunDemoCommand(const std::vector<std::string>& args);
int RunAblationCommand(const std::vector<std::string>& args);

// The `colmap` executable to hand other commands to: --colmap_path is handled by main;
// else $MPMVS_COLMAP_EXE, else "colmap" on PATH.
std::string ColmapExecutableName();

}  // namespace mpmvs

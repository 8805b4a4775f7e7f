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
//   generate_scene --scene indoor|facade|plane --output_path DIR [--width --height
//                  --num_views --seed --noise_sigma --supersampling --blur_sigma ...]
int RunGenerateSceneCommand(const std::vector<std::string>& args);
//   evaluate --workspace_path WS [--gt_path GT] [--input_type geometric]
//            [--fused_path WS/fused.ply] [--output_path DIR for JSON + PNGs]
int RunEvaluateCommand(const std::vector<std::string>& args);
//   compare --workspace_paths WS1,WS2,... [--gt_path GT] [--labels a,b,...]
//           [--output_path DIR]   (scores side by side, or mutual agreement)
int RunCompareCommand(const std::vector<std::string>& args);
//   slurm_submit --workspace_path WS --shards N [--partition --time --cpus_per_task --mem
//                --account --extra "..." --dry_run 1 --fuse 1] [mp_patch_match_stereo options]
int RunSlurmSubmitCommand(const std::vector<std::string>& args);

}  // namespace mpmvs

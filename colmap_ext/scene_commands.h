#pragma once
// `colmap-mp` commands around synthetic scenes and evaluation (argv without the program
// and command names; return the exit code; errors are thrown as mpmvs::Error):
//   generate_scene --scene indoor|facade|plane --output_path DIR [--width --height
//                  --num_views --seed --noise_sigma --supersampling --blur_sigma ...]
//   evaluate       --workspace_path WS [--gt_path GT] [--input_type geometric]
//                  [--fused_path WS/fused.ply] [--output_path DIR for JSON + PNGs]
//   compare        --workspace_paths WS1,WS2,... [--gt_path GT] [--labels a,b,...]
//                  [--output_path DIR]   (scores side by side, or mutual agreement)
#include <string>
#include <vector>

namespace mpmvs {

int RunGenerateSceneCommand(const std::vector<std::string>& args);
int RunEvaluateCommand(const std::vector<std::string>& args);
int RunCompareCommand(const std::vector<std::string>& args);

// Source revision for result files: $MPMVS_COMMIT, else `git rev-parse --short HEAD` in
// the current directory, else "unknown".
std::string DetectSourceCommit();

}  // namespace mpmvs

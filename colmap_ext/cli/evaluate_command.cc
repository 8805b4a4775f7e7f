#include <filesystem>
#include <iostream>
#include <sstream>

#include "colmap_ext/cli/command_util.h"
#include "colmap_ext/cli/commands.h"
#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/evaluation/evaluation.h"
#include "colmap_ext/evaluation/evaluation_report.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

// A fused cloud made before the maps were last written scores earlier maps: say so.
void WarnIfFusedIsOlderThanTheMaps(const std::string& workspace, const std::string& fused,
                                   const std::string& input_type) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto fused_time = fs::last_write_time(fused, ec);
  if (ec) return;
  const std::string suffix = "." + input_type + ".bin";
  for (fs::recursive_directory_iterator it(JoinPaths(workspace, "stereo/depth_maps"), ec), end; !ec && it != end;
       it.increment(ec)) {
    const std::string path = it->path().string();
    if (path.size() < suffix.size() || path.compare(path.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
    std::error_code time_error;
    if (fs::last_write_time(it->path(), time_error) > fused_time && !time_error) {
      LogWarning(fused + " is older than " + path + ": its scores describe earlier maps; fuse again (colmap "
                 "stereo_fusion) to score the current ones");
      return;
    }
  }
}

// The tolerances of the scores: ETH3D reports clouds at several (issue 37 judges a real
// RGB-D scene at 5 %).
void AddToleranceOptions(OptionParser* parser, EvaluationOptions* options) {
  parser->Add("depth_tolerances", &options->depth_tolerances,
              "relative depth errors at which the depth maps are scored, fractions in (0, 1)");
  parser->Add("cloud_tolerances", &options->cloud_tolerances,
              "distances at which the fused cloud is scored, fractions of the median GT depth in (0, 1)");
}

}  // namespace

int RunEvaluateCommand(const std::vector<std::string>& args) {
  EvaluationOptions options;
  std::string workspace_path, gt_path, fused_path, output_path, label, commit;
  bool pictures = true;
  OptionParser parser;
  parser.AddRequired("workspace_path", &workspace_path, "dense workspace with stereo/depth_maps");
  parser.Add("gt_path", &gt_path, "folder with depth_<stem>.pfm (default: WORKSPACE/gt)");
  parser.Add("input_type", &options.input_type, "geometric or photometric depth maps");
  parser.Add("fused_path", &fused_path,
             "fused PLY to score (default: WORKSPACE/fused.ply when present; none = skip)");
  parser.Add("output_path", &output_path, "folder for evaluation.json and PNG pictures");
  parser.Add("pictures", &pictures, "write PNG pictures into --output_path");
  parser.Add("label", &label, "name of this run in the JSON (default: the workspace folder name)");
  parser.Add("commit", &commit, "source revision recorded in the JSON (default: detected)");
  AddToleranceOptions(&parser, &options);
  parser.Add("num_threads", &options.num_threads, "threads for the point-cloud search");
  if (!parser.Parse(args)) {
    ShowHelp(parser, "colmap-mp evaluate --workspace_path WS [--gt_path GT] [options]");
    return 0;
  }
  for (const std::string& w : parser.Warnings()) LogWarning(w);
  options.Check();
  if (gt_path.empty()) {
    gt_path = JoinPaths(workspace_path, "gt");
    if (!DirectoryExists(gt_path)) {
      throw Error("missing --gt_path (and " + gt_path + " does not exist)");
    }
  }
  const std::string fused = fused_path.empty() ? JoinPaths(workspace_path, "fused.ply") : fused_path;
  if (fused != "none" && FileExists(fused)) WarnIfFusedIsOlderThanTheMaps(workspace_path, fused, options.input_type);
  WorkspaceEvaluation evaluation = EvaluateWorkspace(workspace_path, gt_path, fused_path, options);
  evaluation.label = label.empty() ? Basename(workspace_path) : label;
  PrintScoreTable(evaluation);
  if (!output_path.empty()) {
    CreateDirectories(output_path);
    const std::string json_path = JoinPaths(output_path, "evaluation.json");
    WriteJsonFile(json_path, EvaluationJson({evaluation}, MakeContext("evaluate", args, commit)));
    std::cout << "Wrote " << json_path << "\n";
    if (pictures) {
      const std::vector<std::string> written = WriteEvaluationPictures(evaluation, output_path);
      std::cout << "Wrote " << written.size() << " pictures (" << output_path << "/<image>_eval.png)\n";
    }
  }
  return 0;
}

int RunCompareCommand(const std::vector<std::string>& args) {
  EvaluationOptions options;
  std::string workspace_paths, labels_text, gt_path, fused_name = "fused.ply", output_path, commit;
  double tolerance = 0.01;
  OptionParser parser;
  parser.AddRequired("workspace_paths", &workspace_paths, "comma-separated dense workspaces of one scene");
  parser.Add("labels", &labels_text, "comma-separated column names (default: folder names)");
  parser.Add("gt_path", &gt_path, "GT folder; without it the workspaces are compared with each other");
  parser.Add("input_type", &options.input_type, "geometric or photometric depth maps");
  parser.Add("fused_name", &fused_name, "fused PLY inside each workspace scored when present (none = skip)");
  parser.Add("agreement_tolerance", &tolerance, "relative depth difference counted as agreement (no GT)");
  parser.Add("output_path", &output_path, "folder for comparison.json");
  parser.Add("commit", &commit, "source revision recorded in the JSON (default: detected)");
  AddToleranceOptions(&parser, &options);
  parser.Add("num_threads", &options.num_threads, "threads for the point-cloud search");
  if (!parser.Parse(args)) {
    ShowHelp(parser, "colmap-mp compare --workspace_paths WS1,WS2,... [--gt_path GT] [options]");
    return 0;
  }
  for (const std::string& w : parser.Warnings()) LogWarning(w);
  options.Check();
  const std::vector<std::string> workspaces = SplitList(workspace_paths);
  if (workspaces.empty()) throw Error("--workspace_paths lists no workspace");
  // A missing folder would score as an empty workspace (0.0 everywhere) and exit 0.
  for (const std::string& w : workspaces) {
    if (!DirectoryExists(JoinPaths(w, "stereo/depth_maps"))) {
      ThrowFileError(w, "is not a dense workspace with depth maps (no folder stereo/depth_maps); check "
                        "--workspace_paths");
    }
  }
  std::vector<std::string> labels = SplitList(labels_text);
  if (!labels.empty() && labels.size() != workspaces.size()) {
    throw Error("--labels has " + std::to_string(labels.size()) + " names for " +
                std::to_string(workspaces.size()) + " workspaces");
  }
  if (labels.empty()) {
    for (const std::string& w : workspaces) labels.push_back(Basename(w));
  }
  std::string json;
  if (!gt_path.empty()) {
    std::vector<WorkspaceEvaluation> evaluations;
    for (size_t i = 0; i < workspaces.size(); ++i) {
      std::string fused = "none";
      if (fused_name != "none" && FileExists(JoinPaths(workspaces[i], fused_name))) {
        fused = JoinPaths(workspaces[i], fused_name);
        WarnIfFusedIsOlderThanTheMaps(workspaces[i], fused, options.input_type);
      }
      evaluations.push_back(EvaluateWorkspace(workspaces[i], gt_path, fused, options));
      evaluations.back().label = labels[i];
    }
    std::cout << FormatComparisonTable(evaluations) << std::flush;
    json = EvaluationJson(evaluations, MakeContext("compare", args, commit));
  } else {
    if (workspaces.size() < 2) throw Error("compare without --gt_path needs at least two workspaces");
    const std::vector<PairAgreement> pairs =
        ComputeDepthAgreement(workspaces, options.input_type, tolerance);
    std::cout << FormatAgreementTable(labels, pairs, tolerance) << std::flush;
    json = AgreementJson(labels, pairs, tolerance, options.input_type,
                         MakeContext("compare", args, commit));
  }
  if (!output_path.empty()) {
    CreateDirectories(output_path);
    const std::string json_path = JoinPaths(output_path, "comparison.json");
    WriteJsonFile(json_path, json);
    std::cout << "Wrote " << json_path << "\n";
  }
  return 0;
}

}  // namespace mpmvs

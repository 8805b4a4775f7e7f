#include "colmap_ext/scene_commands.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "colmap_ext/error.h"
#include "colmap_ext/evaluation.h"
#include "colmap_ext/evaluation_report.h"
#include "colmap_ext/file_util.h"
#include "colmap_ext/option_parser.h"
#include "colmap_ext/synthetic_scene.h"

namespace mpmvs {
namespace {

std::string CommandLine(const std::string& command, const std::vector<std::string>& args) {
  std::string line = "colmap-mp " + command;
  for (const std::string& a : args) {
    line += " ";
    line += a.find_first_of(" \t\"'") == std::string::npos ? a : "'" + a + "'";
  }
  return line;
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const size_t b = item.find_first_not_of(" \t");
    const size_t e = item.find_last_not_of(" \t");
    if (b != std::string::npos) items.push_back(item.substr(b, e - b + 1));
  }
  return items;
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

}  // namespace

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

int RunGenerateSceneCommand(const std::vector<std::string>& args) {
  SyntheticSceneOptions options;
  std::string output_path;
  OptionParser parser;
  parser.AddRequired("output_path", &output_path, "folder of the new dense workspace + gt/");
  parser.Add("scene", &options.scene, "indoor, facade or plane");
  parser.Add("width", &options.width, "image width in pixels");
  parser.Add("height", &options.height, "image height in pixels");
  parser.Add("num_views", &options.num_views, "number of cameras");
  parser.Add("seed", &options.seed, "random seed (textures, camera jitter, noise)");
  parser.Add("noise_sigma", &options.noise_sigma, "Gaussian sensor noise in 8-bit grey levels");
  parser.Add("supersampling", &options.supersampling, "s x s anti-aliasing samples per pixel");
  parser.Add("blur_sigma", &options.blur_sigma, "Gaussian optical blur in pixels (0 = off)");
  parser.Add("exposure_variation", &options.exposure_variation,
             "scale of per-view gain/offset differences (0 = identical exposures)");
  parser.Add("plane_tilt_deg", &options.plane_tilt_deg,
             "plane scene: tilt of the plane away from every camera's optical axis");
  parser.Add("max_sparse_points", &options.max_sparse_points, "cap on SfM-like sparse points");
  parser.Add("sparse_noise_px", &options.sparse_noise_px, "noise of sparse 2-D observations (px)");
  parser.Add("write_gt_points", &options.write_gt_points, "write gt/gt_points.ply");
  parser.Add("num_threads", &options.num_threads, "render threads (-1 = all)");
  if (!parser.Parse(args)) {
    ShowHelp(parser, "colmap-mp generate_scene --scene indoor --output_path DIR [options]");
    return 0;
  }
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  const SyntheticScene scene = GenerateSyntheticScene(options, output_path);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("Generated scene '%s': %d views %dx%d, %zu sparse points, in %.2f s -> %s\n",
              options.scene.c_str(), options.num_views, options.width, options.height,
              scene.model.points.size(), seconds, output_path.c_str());
  for (const SyntheticView& v : scene.views) {
    std::printf("  %s  untextured %4.1f%%  GT depth %.2f..%.2f  sparse points %4d  "
                "sparse depth range %.2f..%.2f covers %5.1f%% of GT\n",
                v.name.c_str(), 100 * v.stats.untextured_fraction, v.stats.gt_depth_min,
                v.stats.gt_depth_max, v.stats.num_sparse_points, v.stats.sparse_depth_min,
                v.stats.sparse_depth_max, 100 * v.stats.gt_in_sparse_range);
  }
  std::printf("Next: colmap-mp mp_patch_match_stereo --workspace_path %s\n"
              "      colmap-mp evaluate --workspace_path %s --gt_path %s/gt\n",
              output_path.c_str(), output_path.c_str(), output_path.c_str());
  return 0;
}

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
  parser.Add("num_threads", &options.num_threads, "threads for the point-cloud search");
  if (!parser.Parse(args)) {
    ShowHelp(parser, "colmap-mp evaluate --workspace_path WS [--gt_path GT] [options]");
    return 0;
  }
  options.Check();
  if (gt_path.empty()) {
    gt_path = JoinPaths(workspace_path, "gt");
    if (!DirectoryExists(gt_path)) {
      throw Error("missing --gt_path (and " + gt_path + " does not exist)");
    }
  }
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
  parser.Add("num_threads", &options.num_threads, "threads for the point-cloud search");
  if (!parser.Parse(args)) {
    ShowHelp(parser, "colmap-mp compare --workspace_paths WS1,WS2,... [--gt_path GT] [options]");
    return 0;
  }
  options.Check();
  const std::vector<std::string> workspaces = SplitList(workspace_paths);
  if (workspaces.empty()) throw Error("--workspace_paths lists no workspace");
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

// `colmap-mp ablation`: the paper's Table 1 on one scene (see ablation.h).
#include <cstdio>
#include <fstream>
#include <iostream>

#include "colmap_ext/cli/command_util.h"
#include "colmap_ext/cli/commands.h"
#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/cli/patch_match_flags.h"
#include "colmap_ext/evaluation/ablation.h"
#include "colmap_ext/evaluation/evaluation_report.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/colmap_runner.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {

int RunAblationCommand(const std::vector<std::string>& args) {
  AblationOptions options;
  std::string dataset_path, scene_name, rows;
  SyntheticSceneOptions scene;
  OptionParser parser;
  parser.Add("workspace_path", &options.workspace_path, "a dense workspace (with --gt_path)");
  parser.Add("gt_path", &options.gt_path, "folder with depth_<stem>.pfm");
  parser.Add("dataset_path", &dataset_path,
             "a dataset folder with images/, sparse/ and gt/ (undistorted here with colmap)");
  parser.Add("scene", &scene_name, "a synthetic scene instead: indoor | facade | plane");
  parser.Add("width", &scene.width);
  parser.Add("height", &scene.height);
  parser.Add("num_views", &scene.num_views);
  parser.AddRequired("output_path", &options.output_path, "one sub-folder per row, plus ablation.txt/.json");
  parser.Add("rows", &rows, "comma-separated subset, e.g. ACMH,mPM+rs+gp (default: all six)");
  parser.Add("fuse", &options.fuse, "fuse with colmap stereo_fusion and score the point cloud");
  AddPatchMatchOptions(&parser, &options.colmap_options, &options.options);
  if (!parser.Parse(args)) {
    std::cout << "Usage: colmap-mp ablation (--dataset_path DS | --scene indoor | --workspace_path WS "
                 "--gt_path GT) --output_path DIR\n\nOptions:\n"
              << parser.Help();
    return 0;
  }
  for (const std::string& w : parser.Warnings()) LogWarning(w);
  const int sources = !dataset_path.empty() + !scene_name.empty() + !options.workspace_path.empty();
  if (sources != 1) throw Error("give exactly one of --dataset_path, --scene, --workspace_path");
  options.rows = SplitList(rows);
  CreateDirectories(options.output_path);
  if (!scene_name.empty()) {
    scene.scene = scene_name;
    scene.Check();
    const std::string dir = JoinPaths(options.output_path, "scene");
    if (!FileExists(JoinPaths(dir, "gt/scene_info.json"))) GenerateSyntheticScene(scene, dir);
    options.workspace_path = dir;
    options.gt_path = JoinPaths(dir, "gt");
  } else if (!dataset_path.empty()) {
    const std::string dir = JoinPaths(options.output_path, "workspace");
    if (!DirectoryExists(JoinPaths(dir, "stereo"))) {
      if (!ColmapAvailable()) throw Error("--dataset_path needs the colmap executable (image_undistorter)");
      const int code = RunColmap({"image_undistorter", "--image_path", JoinPaths(dataset_path, "images"),
                                  "--input_path", JoinPaths(dataset_path, "sparse"), "--output_path", dir,
                                  "--output_type", "COLMAP"},
                                 JoinPaths(options.output_path, "image_undistorter.log"));
      if (code != 0) throw Error("colmap image_undistorter failed on " + dataset_path);
    }
    options.workspace_path = dir;
    options.gt_path = JoinPaths(dataset_path, "gt");
  } else if (options.gt_path.empty()) {
    throw Error("--workspace_path needs --gt_path");
  }

  const std::vector<AblationRowResult> results = RunAblation(options);
  const std::string table = FormatAblationTable(results);
  std::printf("\n%s\n", table.c_str());
  WriteFileAtomically(JoinPaths(options.output_path, "ablation.txt"),
                      [&](std::ostream& out) { out << table; });
  ReportContext context;
  context.command = "colmap-mp ablation";
  for (const std::string& a : args) context.command += " " + a;
  context.commit = DetectSourceCommit();
  WriteJsonFile(JoinPaths(options.output_path, "ablation.json"), AblationJson(results, context));
  LogInfo("Wrote " + JoinPaths(options.output_path, "ablation.txt") + " and ablation.json");
  return 0;
}

}  // namespace mpmvs

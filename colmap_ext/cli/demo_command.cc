// `colmap-mp demo`: the whole job on the embedded synthetic indoor scene, from nothing:
// generate -> mp_patch_match_stereo -> colmap stereo_fusion -> evaluation against exact GT.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "colmap_ext/cli/command_util.h"
#include "colmap_ext/cli/commands.h"
#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/cli/patch_match_flags.h"
#include "colmap_ext/evaluation/evaluation.h"
#include "colmap_ext/evaluation/evaluation_report.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/colmap_runner.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {

namespace fs = std::filesystem;

int RunDemoCommand(const std::vector<std::string>& args) {
  std::string output_path = "mpmvs_demo";
  SyntheticSceneOptions scene;
  MpPatchMatchRun run;
  bool overwrite = false;
  OptionParser parser;
  parser.Add("output_path", &output_path, "folder for the scene, its depth maps, fused.ply and the report");
  parser.Add("scene", &scene.scene, "indoor | facade | plane");
  parser.Add("width", &scene.width);
  parser.Add("height", &scene.height);
  parser.Add("num_views", &scene.num_views);
  parser.Add("seed", &scene.seed);
  parser.Add("overwrite", &overwrite, "delete an earlier demo in output_path and start over");
  run.options.write_pictures = "all";  // the demo shows every stage and planar prior
  AddPatchMatchOptions(&parser, &run.colmap_options, &run.options);
  if (!parser.Parse(args)) {
    std::cout << "Usage: colmap-mp demo [--output_path mpmvs_demo] [options]\n\n"
                 "Renders a synthetic scene with exact ground truth, runs mp_patch_match_stereo,\n"
                 "fuses with `colmap stereo_fusion` and prints quality figures.\n\nOptions:\n"
              << parser.Help();
    return 0;
  }
  for (const std::string& w : parser.Warnings()) LogWarning(w);
  scene.Check();

  // Never clobber a folder that is not an earlier demo.
  const std::string marker = JoinPaths(output_path, "gt/scene_info.json");
  std::error_code ec;
  if (fs::exists(output_path) && !fs::is_empty(output_path, ec) && !FileExists(marker)) {
    throw Error(output_path + ": exists and is not an mp-mvs demo folder; choose another --output_path");
  }
  if (overwrite && FileExists(marker)) {
    LogInfo("Removing the earlier demo in " + output_path);
    fs::remove_all(output_path);
  }

  LogHeading("demo 1/4: synthetic '" + scene.scene + "' scene, " + std::to_string(scene.num_views) +
             " views of " + std::to_string(scene.width) + "x" + std::to_string(scene.height));
  if (FileExists(marker)) {
    LogInfo("Reusing the scene in " + output_path + " (--overwrite 1 renders it again)");
  } else {
    GenerateSyntheticScene(scene, output_path);
    LogInfo("Wrote the dense workspace and ground truth to " + output_path);
  }

  LogHeading("demo 2/4: mp_patch_match_stereo");
  run.workspace_path = output_path;
  const MpPatchMatchSummary summary = RunMpPatchMatchStereo(run);
  const std::string input_type = run.colmap_options.geom_consistency ? "geometric" : "photometric";

  LogHeading("demo 3/4: colmap stereo_fusion");
  const std::string fused = JoinPaths(output_path, "fused.ply");
  std::string fused_for_eval = "none";
  if (!ColmapAvailable()) {
    LogWarning("`" + ColmapExecutableName() +
               "` not found: skipping point-cloud fusion and its scores (apt-get install colmap)");
  } else {
    const std::string log = JoinPaths(output_path, "stereo_fusion.log");
    RunStereoFusion(output_path, input_type, fused, scene.num_views, log);
    LogInfo("Fused point cloud: " + fused + " (log: " + log + ")");
    fused_for_eval = fused;
  }

  LogHeading("demo 4/4: evaluation against the exact ground truth");
  EvaluationOptions eval_options;
  eval_options.input_type = input_type;
  WorkspaceEvaluation evaluation =
      EvaluateWorkspace(output_path, JoinPaths(output_path, "gt"), fused_for_eval, eval_options);
  evaluation.label = "mp-mvs (" + scene.scene + ")";
  PrintScoreTable(evaluation);
  const std::string report_dir = JoinPaths(output_path, "evaluation");
  CreateDirectories(report_dir);
  ReportContext context;
  context.command = "colmap-mp demo --output_path " + output_path;
  context.commit = DetectSourceCommit();
  WriteJsonFile(JoinPaths(report_dir, "evaluation.json"), EvaluationJson({evaluation}, context));
  const std::vector<std::string> pictures = WriteEvaluationPictures(evaluation, report_dir);
  std::printf("\nmp_patch_match_stereo: %s on %s\n", FormatDuration(summary.seconds).c_str(),
              summary.backend.empty() ? "-" : summary.backend.c_str());
  std::printf("Report: %s/evaluation.json\n", report_dir.c_str());
  std::printf("Pictures (%zu): %s/ (depth, GT, error maps) and %s/stereo/mpmvs/pictures/\n", pictures.size(),
              report_dir.c_str(), output_path.c_str());
  if (fused_for_eval != "none") std::printf("Point cloud: %s\n", fused.c_str());
  return 0;
}

}  // namespace mpmvs

#include <chrono>
#include <filesystem>
#include <iostream>

#include "colmap_ext/cli/command_util.h"
#include "colmap_ext/cli/commands.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {

namespace {

namespace fs = std::filesystem;

// The --scene value, if given: the other options' defaults depend on it.
std::string SceneArgument(const std::vector<std::string>& args) {
  std::string scene = SyntheticSceneOptions().scene;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--scene" && i + 1 < args.size()) scene = args[i + 1];
    if (args[i].rfind("--scene=", 0) == 0) scene = args[i].substr(8);
  }
  return scene;
}

// A non-empty output folder holds an earlier scene or workspace whose maps the next run
// would trust beside the new images: refused, unless it is an earlier generated scene
// (gt/scene_info.json) and overwrite is given, which removes it first.
void PrepareOutputFolder(const std::string& output_path, bool overwrite) {
  std::error_code ec;
  if (!fs::exists(output_path, ec) || fs::is_empty(output_path, ec)) return;
  if (!fs::is_directory(output_path, ec)) throw Error(output_path + ": is a file, not a folder");
  const bool earlier_scene = FileExists(JoinPaths(output_path, "gt/scene_info.json"));
  if (!earlier_scene) {
    throw Error(output_path + ": is not empty and holds no scene of generate_scene (" +
                (DirectoryExists(JoinPaths(output_path, "stereo")) ? "it has a stereo/ folder" : "other files") +
                "); choose another --output_path");
  }
  if (!overwrite) {
    throw Error(output_path + ": holds an earlier generated scene (and any maps computed on it); choose "
                "another --output_path, or add --overwrite 1 to delete it and generate the new scene there");
  }
  LogInfo("Removing the earlier scene in " + output_path + " (--overwrite 1)");
  fs::remove_all(output_path);
}

}  // namespace

int RunGenerateSceneCommand(const std::vector<std::string>& args) {
  SyntheticSceneOptions options = SyntheticSceneOptions::ForScene(SceneArgument(args));
  std::string output_path;
  OptionParser parser;
  std::string scene_names;
  for (const std::string& name : SyntheticSceneNames()) {
    scene_names += (scene_names.empty() ? "" : ", ") + name;
  }
  bool overwrite = false;
  parser.AddRequired("output_path", &output_path, "folder of the new dense workspace + gt/ (empty or new)");
  parser.Add("overwrite", &overwrite, "replace an earlier generated scene in output_path, with any maps on it");
  parser.Add("scene", &options.scene,
             scene_names + " (defaults below are this scene's; the rooms default to 640x480, "
                           "10 views, SIFT sparse points)");
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
  parser.Add("sparse_source", &options.sparse_source,
             "simulated (detector model knowing the GT) or sift (COLMAP CPU SIFT + matching, "
             "triangulated with the known poses; needs colmap)");
  parser.Add("vignetting", &options.vignetting, "corner darkening 1 - v r^2 (0 = off)");
  parser.Add("shot_noise", &options.shot_noise,
             "signal-dependent noise: variance noise_sigma^2 + shot_noise * intensity");
  parser.Add("pose_noise_px", &options.pose_noise_px,
             "calibration error: each written camera pose turned about its centre by a random angle of this "
             "many pixels (standard deviation; the images keep the true poses), 0 = exact");
  if (!parser.Parse(args)) {
    ShowHelp(parser, "colmap-mp generate_scene --scene indoor --output_path DIR [options]\n"
                     "Scenes: " + scene_names + "; e.g. --scene room_l");
    return 0;
  }
  options.Check();
  PrepareOutputFolder(output_path, overwrite);
  const auto start = std::chrono::steady_clock::now();
  const SyntheticScene scene = GenerateSyntheticScene(options, output_path);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("Generated scene '%s': %d views %dx%d, %zu sparse points, in %.2f s -> %s\n",
              options.scene.c_str(), options.num_views, options.width, options.height,
              scene.model.points.size(), seconds, output_path.c_str());
  const SparsePointLabels& l = scene.sparse_labels;
  std::printf("  untextured: %.1f%% of GT pixels; sparse points (%s) on textured surfaces %d, "
              "on untextured %d, off the GT surface %d\n",
              100 * UntexturedShare(scene), options.sparse_source.c_str(), l.on_textured,
              l.on_untextured, l.off_surface);
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

}  // namespace mpmvs

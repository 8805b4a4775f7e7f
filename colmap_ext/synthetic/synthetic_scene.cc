#include "colmap_ext/synthetic/synthetic_scene.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "colmap_ext/io/gt_files.h"
#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/synthetic/room_layouts.h"
#include "colmap_ext/synthetic/sift_sparse.h"
#include "colmap_ext/synthetic/synthetic_layouts.h"
#include "colmap_ext/synthetic/synthetic_random.h"
#include "colmap_ext/synthetic/synthetic_sparse.h"
#include "colmap_ext/util/colmap_runner.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"

namespace mpmvs {
namespace {

std::string ViewName(int index, int num_views) {
  size_t digits = 2;
  for (int n = num_views - 1; n >= 100; n /= 10) ++digits;
  std::string number = std::to_string(index);
  if (number.size() < digits) number.insert(0, digits - number.size(), '0');
  return "view_" + number + ".png";
}

SyntheticViewStats ComputeStats(const SyntheticView& view, const SparseModel& model, int index) {
  SyntheticViewStats s;
  const FloatMap& depth = view.render.depth;
  const size_t total = static_cast<size_t>(depth.width) * depth.height;
  std::vector<float> valid;
  size_t untextured = 0;
  for (size_t i = 0; i < total; ++i) {
    if (depth.data[i] > 0) valid.push_back(depth.data[i]);
    if (view.render.untextured[i]) ++untextured;
  }
  s.gt_valid_fraction = total ? static_cast<double>(valid.size()) / total : 0;
  s.untextured_fraction = total ? static_cast<double>(untextured) / total : 0;
  if (!valid.empty()) {
    const auto mm = std::minmax_element(valid.begin(), valid.end());
    s.gt_depth_min = *mm.first;
    s.gt_depth_max = *mm.second;
  }
  for (const SparsePoint2D& p : model.images[index].points2D) {
    if (p.point3D_id != UINT64_MAX) ++s.num_sparse_points;
  }
  if (SparseDepthRange(model, index, &s.sparse_depth_min, &s.sparse_depth_max) && !valid.empty()) {
    size_t inside = 0;
    for (float z : valid) inside += (z >= s.sparse_depth_min && z <= s.sparse_depth_max);
    s.gt_in_sparse_range = static_cast<double>(inside) / valid.size();
  }
  return s;
}

void WriteTextFile(const std::string& path, const std::string& text) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << text; });
}

std::string SceneInfoJson(const SyntheticScene& scene) {
  // ordered_json: keys stay in the order written here.
  using Json = nlohmann::ordered_json;
  const SyntheticSceneOptions& o = scene.options;
  Json j = {{"generator", "mp-mvs generate_scene"},
            {"options",
             {{"scene", o.scene},
              {"width", o.width},
              {"height", o.height},
              {"num_views", o.num_views},
              {"seed", o.seed},
              {"noise_sigma", o.noise_sigma},
              {"supersampling", o.supersampling},
              {"blur_sigma", o.blur_sigma},
              {"exposure_variation", o.exposure_variation},
              {"plane_tilt_deg", o.plane_tilt_deg},
              {"max_sparse_points", o.max_sparse_points},
              {"sparse_noise_px", o.sparse_noise_px}}}};
  // Options and figures added after indoor/facade/plane were frozen are written only when
  // they matter, so that those scenes' files keep their content.
  const bool extended = IsRoomLayout(o.scene) || o.sparse_source != "simulated" ||
                        o.vignetting != 0 || o.shot_noise != 0 || o.pose_noise_px != 0;
  if (extended) {
    j["options"]["sparse_source"] = o.sparse_source;
    j["options"]["vignetting"] = o.vignetting;
    j["options"]["shot_noise"] = o.shot_noise;
    if (o.pose_noise_px != 0) j["options"]["pose_noise_px"] = o.pose_noise_px;
  }
  j["num_sparse_points"] = scene.model.points.size();
  if (extended) {
    const SparsePointLabels& l = scene.sparse_labels;
    j["sparse_points_by_gt_surface"] = {
        {"textured", l.on_textured}, {"untextured", l.on_untextured}, {"off_surface", l.off_surface}};
    j["untextured_fraction_of_gt_pixels"] = UntexturedShare(scene);
  }
  j["pixel_convention"] =
      "depth-map pixel (col,row) is centred at image coordinate (col,row); sparse "
      "observations use x = col + 0.5";
  if (!scene.plane_view_angles_deg.empty()) j["plane_view_angles_deg"] = scene.plane_view_angles_deg;
  Json& views = j["views"] = Json::array();
  for (const SyntheticView& v : scene.views) {
    const SyntheticCamera& c = v.camera;
    const Eigen::Vector3d center = c.Center();
    views.push_back(
        {{"name", v.name},
         {"K_fx_fy_cx_cy", {c.fx, c.fy, c.cx, c.cy}},
         {"center", {center.x(), center.y(), center.z()}},
         {"R", {c.R(0, 0), c.R(0, 1), c.R(0, 2), c.R(1, 0), c.R(1, 1), c.R(1, 2), c.R(2, 0),
                c.R(2, 1), c.R(2, 2)}},
         {"t", {c.t.x(), c.t.y(), c.t.z()}},
         {"gain", v.gain},
         {"offset", v.offset},
         {"gt_valid_fraction", v.stats.gt_valid_fraction},
         {"untextured_fraction", v.stats.untextured_fraction},
         {"gt_depth_range", {v.stats.gt_depth_min, v.stats.gt_depth_max}},
         {"num_sparse_points", v.stats.num_sparse_points},
         {"sparse_depth_range", {v.stats.sparse_depth_min, v.stats.sparse_depth_max}},
         {"gt_in_sparse_depth_range", v.stats.gt_in_sparse_range}});
  }
  return j.dump(2) + "\n";
}

}  // namespace

double UntexturedShare(const SyntheticScene& scene) {
  size_t valid = 0, untextured = 0;
  for (const SyntheticView& v : scene.views) {
    for (size_t i = 0; i < v.render.untextured.size(); ++i) {
      valid += v.render.depth.data[i] > 0;
      untextured += v.render.untextured[i] != 0;
    }
  }
  return valid ? static_cast<double>(untextured) / valid : 0.0;
}

SyntheticSceneOptions SyntheticSceneOptions::ForScene(const std::string& scene) {
  SyntheticSceneOptions o;
  o.scene = scene;
  if (IsRoomLayout(scene)) {
    o.width = 640;
    o.height = 480;
    o.num_views = 10;
    o.supersampling = 2;  // 4 samples per pixel: anti-aliased edges at half the time of 3x3
    // About 1.5 grey levels at mid-grey: read noise plus a little shot noise.
    o.noise_sigma = 1.2;
    o.shot_noise = 0.01;
    o.vignetting = 0.12;
    o.sparse_source = "sift";
  }
  return o;
}

void SyntheticSceneOptions::Check() const {
  const std::vector<std::string> names = SyntheticSceneNames();
  if (std::find(names.begin(), names.end(), scene) == names.end()) {
    throw Error("--scene '" + scene + "' is unknown (valid: " + SyntheticLayoutNameList() + ")");
  }
  if (width < 16 || height < 16 || width > 16384 || height > 16384) {
    throw Error("--width/--height must be between 16 and 16384 pixels");
  }
  if (num_views < 2 || num_views > 1000) throw Error("--num_views must be between 2 and 1000");
  if (!(noise_sigma >= 0 && noise_sigma <= 100)) throw Error("--noise_sigma must be in [0, 100]");
  if (supersampling < 1 || supersampling > 8) throw Error("--supersampling must be in [1, 8]");
  if (!(blur_sigma >= 0 && blur_sigma <= 10)) throw Error("--blur_sigma must be in [0, 10]");
  if (!(exposure_variation >= 0 && exposure_variation <= 5)) {
    throw Error("--exposure_variation must be in [0, 5]");
  }
  if (!(plane_tilt_deg >= 0 && plane_tilt_deg <= 80)) {
    throw Error("--plane_tilt_deg must be in [0, 80]");
  }
  if (max_sparse_points < 1) throw Error("--max_sparse_points must be >= 1");
  if (!(sparse_noise_px >= 0 && sparse_noise_px <= 10)) {
    throw Error("--sparse_noise_px must be in [0, 10]");
  }
  if (num_threads == 0 || num_threads < -1) throw Error("--num_threads must be -1 or >= 1");
  if (sparse_source != "simulated" && sparse_source != "sift") {
    throw Error("--sparse_source must be 'simulated' or 'sift'");
  }
  if (!(vignetting >= 0 && vignetting <= 0.9)) throw Error("--vignetting must be in [0, 0.9]");
  if (!(shot_noise >= 0 && shot_noise <= 10)) throw Error("--shot_noise must be in [0, 10]");
  if (!(pose_noise_px >= 0 && pose_noise_px <= 20)) throw Error("--pose_noise_px must be in [0, 20]");
}

std::vector<std::string> SyntheticSceneNames() { return SyntheticLayoutNames(); }

std::vector<std::string> SyntheticRoomSceneNames() { return RoomLayoutNames(); }

SyntheticScene RenderSyntheticScene(const SyntheticSceneOptions& options) {
  options.Check();
  if (options.sparse_source == "sift" && !ColmapAvailable()) {  // fail before rendering
    throw Error(MissingColmapMessage("Scene '" + options.scene + "' with --sparse_source sift") +
                " Or pass --sparse_source simulated.");
  }
  const uint64_t seed = static_cast<uint64_t>(static_cast<int64_t>(options.seed));
  LayoutParams params;
  params.scene = options.scene;
  params.width = options.width;
  params.height = options.height;
  params.num_views = options.num_views;
  params.seed = seed;
  params.plane_tilt_deg = options.plane_tilt_deg;
  const SyntheticLayout layout = BuildSyntheticLayout(params);

  SyntheticScene scene;
  scene.options = options;
  scene.plane_view_angles_deg = layout.plane_view_angles_deg;
  scene.surface_names = SurfaceNames(layout.world);
  SynthRng exposure_rng(SynthHash(seed, 0xe7b05e));
  std::vector<SyntheticCamera> cameras;
  std::vector<std::string> names;
  std::vector<RenderedView> renders;
  for (int v = 0; v < options.num_views; ++v) {
    SyntheticView view;
    view.name = ViewName(v, options.num_views);
    view.camera = layout.cameras[v];
    view.gain = 1.0 + options.exposure_variation * exposure_rng.Uniform(-0.08, 0.08);
    view.offset = options.exposure_variation * exposure_rng.Uniform(-6, 6);
    RenderOptions render;
    render.supersampling = options.supersampling;
    render.noise_sigma = options.noise_sigma;
    render.blur_sigma = options.blur_sigma;
    render.gain = view.gain;
    render.offset = view.offset;
    render.noise_seed = SynthHash(seed, 0x9015e, v);
    render.num_threads = options.num_threads;
    render.vignetting = options.vignetting;
    render.shot_noise = options.shot_noise;
    view.render = RenderView(layout.world, view.camera, render);
    cameras.push_back(view.camera);
    names.push_back(view.name);
    renders.push_back(view.render);
    scene.views.push_back(std::move(view));
  }
  // The model the workspace gets: the poses as calibration would have them.
  const std::vector<SyntheticCamera> true_cameras = cameras;
  if (options.pose_noise_px > 0) {
    for (size_t v = 0; v < cameras.size(); ++v) {
      SynthRng rng(SynthHash(seed, 0x905e0, v));
      const Eigen::Vector3d axis = Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
      const double angle = options.pose_noise_px / cameras[v].fx * rng.Normal();
      const Eigen::Matrix3d turn = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
      cameras[v].R = turn * cameras[v].R;  // about the camera centre: R' = T R, t' = T t
      cameras[v].t = turn * cameras[v].t;
    }
  }
  if (options.sparse_source == "sift") {
    std::vector<RgbImage> images;
    for (const RenderedView& r : renders) images.push_back(r.image);
    scene.model = TriangulateSiftSparseModel(cameras, names, images, SiftSparseOptions());
  } else {
    SparseSimulationOptions sparse;
    sparse.max_points = options.max_sparse_points;
    sparse.observation_noise_px = options.sparse_noise_px;
    sparse.seed = SynthHash(seed, 0x5a25e);
    scene.model = SimulateSparseModel(cameras, names, renders, sparse);
  }
  scene.sparse_labels = LabelSparsePoints(scene.model, true_cameras, renders);
  for (size_t v = 0; v < scene.views.size(); ++v) {
    scene.views[v].stats = ComputeStats(scene.views[v], scene.model, static_cast<int>(v));
  }
  return scene;
}

void AppendBackProjectedPoints(const SyntheticCamera& camera, const FloatMap& depth,
                               const FloatMap* normal, const RgbImage* image,
                               PlyPointCloud* cloud) {
  const Eigen::Matrix3d Rt = camera.R.transpose();
  for (int row = 0; row < depth.height; ++row) {
    for (int col = 0; col < depth.width; ++col) {
      const double z = depth.At(row, col);
      if (!(z > 0)) continue;
      const Eigen::Vector3d Xc(z * (col - camera.cx) / camera.fx, z * (row - camera.cy) / camera.fy, z);
      const Eigen::Vector3d X = Rt * (Xc - camera.t);
      PlyPoint p;
      p.x = static_cast<float>(X.x());
      p.y = static_cast<float>(X.y());
      p.z = static_cast<float>(X.z());
      if (normal) {
        const Eigen::Vector3d n = Rt * Eigen::Vector3d(normal->At(row, col, 0),
                                                       normal->At(row, col, 1),
                                                       normal->At(row, col, 2));
        p.nx = static_cast<float>(n.x());
        p.ny = static_cast<float>(n.y());
        p.nz = static_cast<float>(n.z());
      }
      if (image) {
        const size_t i = 3 * (static_cast<size_t>(row) * image->width + col);
        p.r = image->data[i];
        p.g = image->data[i + 1];
        p.b = image->data[i + 2];
      }
      cloud->points.push_back(p);
    }
  }
  cloud->has_normals = cloud->has_normals || normal != nullptr;
  cloud->has_colors = cloud->has_colors || image != nullptr;
}

void WriteSyntheticScene(const SyntheticScene& scene, const std::string& dir) {
  const std::string images = JoinPaths(dir, "images");
  const std::string sparse = JoinPaths(dir, "sparse");
  const std::string stereo = JoinPaths(dir, "stereo");
  const std::string gt = JoinPaths(dir, "gt");
  for (const std::string& d :
       {images, sparse, JoinPaths(stereo, "depth_maps"), JoinPaths(stereo, "normal_maps"),
        JoinPaths(stereo, "consistency_graphs"), JoinPaths(gt, "depth_maps"),
        JoinPaths(gt, "normal_maps")}) {
    CreateDirectories(d);
  }
  std::string patch_match_cfg, fusion_cfg;
  PlyPointCloud gt_cloud;
  for (const SyntheticView& v : scene.views) {
    WriteRgbPng(JoinPaths(images, v.name), v.render.image);
    PfmImage pfm;
    pfm.width = v.render.depth.width;
    pfm.height = v.render.depth.height;
    pfm.data = v.render.depth.data;
    WritePfm(GtDepthPath(gt, v.name), pfm);
    WriteGrayPng(GtUntexturedMaskPath(gt, v.name), pfm.width, pfm.height, v.render.untextured);
    if (!scene.surface_names.empty()) {
      WriteGrayPng(GtSurfaceLabelPath(gt, v.name), pfm.width, pfm.height, v.render.surface);
    }
    WriteFloatMap(JoinPaths(gt, "depth_maps/" + v.name + ".bin"), v.render.depth);
    WriteFloatMap(JoinPaths(gt, "normal_maps/" + v.name + ".bin"), v.render.normal);
    patch_match_cfg += v.name + "\n__auto__, 20\n";
    fusion_cfg += v.name + "\n";
    if (scene.options.write_gt_points) {
      AppendBackProjectedPoints(v.camera, v.render.depth, &v.render.normal, &v.render.image,
                                &gt_cloud);
    }
  }
  WriteSparseModelBinary(scene.model, sparse);
  WriteSparseModelText(scene.model, sparse);
  WriteTextFile(JoinPaths(stereo, "patch-match.cfg"), patch_match_cfg);
  WriteTextFile(JoinPaths(stereo, "fusion.cfg"), fusion_cfg);
  if (scene.options.write_gt_points) WritePlyPointCloud(JoinPaths(gt, "gt_points.ply"), gt_cloud);
  WriteTextFile(JoinPaths(gt, "scene_info.json"), SceneInfoJson(scene));
  if (!scene.surface_names.empty()) {
    std::string lines;
    for (const std::string& name : scene.surface_names) lines += name + "\n";
    WriteTextFile(GtSurfaceNamesPath(gt), lines);
  }
}

SyntheticScene GenerateSyntheticScene(const SyntheticSceneOptions& options, const std::string& dir) {
  SyntheticScene scene = RenderSyntheticScene(options);
  WriteSyntheticScene(scene, dir);
  return scene;
}

}  // namespace mpmvs

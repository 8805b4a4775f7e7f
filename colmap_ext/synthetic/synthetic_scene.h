#pragma once
// Synthetic calibrated multi-view scenes with exact ground truth, written as a ready COLMAP
// dense workspace (as `colmap image_undistorter --output_type COLMAP` leaves it) plus gt/:
//
//   DIR/images/NAME.png                       rendered RGB images
//   DIR/sparse/{cameras,images,points3D}.{bin,txt}   PINHOLE cameras, SfM(-like) points
//   DIR/stereo/patch-match.cfg, fusion.cfg, depth_maps/, normal_maps/, consistency_graphs/
//   DIR/gt/depth_<stem>.pfm                   z-depth (m), 0 = no surface
//   DIR/gt/untextured_<stem>.png              255 where the surface MATERIAL is plain
//   DIR/gt/surface_<stem>.png, surfaces.txt   named surfaces (rooms): line k of surfaces.txt
//                                             names the pixels of value k, 0 = none
//   DIR/gt/depth_maps/NAME.bin, normal_maps/NAME.bin   COLMAP-layout GT maps
//   DIR/gt/gt_points.ply                      every valid GT pixel of every view, back-projected
//   DIR/gt/scene_info.json                    options, cameras, per-view statistics
//
// Output is a deterministic function of the options (thread count does not matter).
#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/io/ply_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/synthetic/scene_renderer.h"
#include "colmap_ext/synthetic/synthetic_sparse.h"

namespace mpmvs {

struct SyntheticSceneOptions {
  // indoor, facade, plane, or a room (room_window, room_l, room_corridor, room_sweep). The defaults
  // below are those of indoor/facade/plane; ForScene gives the rooms' defaults.
  std::string scene = "indoor";
  int width = 320;
  int height = 240;
  int num_views = 5;
  int seed = 1;
  double noise_sigma = 2.0;   // Gaussian sensor noise, 8-bit grey levels
  int supersampling = 3;      // s x s anti-aliasing samples per pixel
  double blur_sigma = 0.0;    // optical blur in pixels, 0 = off
  // Scale of the per-view exposure differences (gain 1 +- 8 %, offset +- 6 levels at 1).
  double exposure_variation = 1.0;
  double plane_tilt_deg = 0.0;  // plane scene: tilt of the plane away from all cameras
  int max_sparse_points = 2000;
  double sparse_noise_px = 0.5;  // noise of the sparse 2-D observations
  bool write_gt_points = true;   // gt/gt_points.ply
  int num_threads = -1;
  // Where the sparse points come from: "simulated" (a detector model on the rendered images
  // that knows the GT, synthetic_sparse.h) or "sift" (COLMAP's CPU SIFT features and
  // matches triangulated with the known poses, sift_sparse.h; needs the colmap executable).
  std::string sparse_source = "simulated";
  double vignetting = 0.0;  // corner darkening, 0 = off (RenderOptions::vignetting)
  double shot_noise = 0.0;  // signal-dependent noise variance per grey level, 0 = off
  // Calibration error of the written model (images are rendered with the true poses): each
  // camera's written pose is turned about its centre by a random angle of this many pixels
  // (standard deviation, at the focal length), as real SfM poses are off by a few tenths of
  // a pixel after bundle adjustment. 0 = exact poses.
  double pose_noise_px = 0.0;

  // Defaults for a scene: the rooms render 640x480 with 10 views and 2x2 supersampling,
  // weaker and partly signal-dependent noise, slight vignetting and SIFT sparse points;
  // other scenes get the defaults above.
  static SyntheticSceneOptions ForScene(const std::string& scene);

  // Throws Error naming the offending option.
  void Check() const;
};

std::vector<std::string> SyntheticSceneNames();
// The multi-view room family (a subset of SyntheticSceneNames()).
std::vector<std::string> SyntheticRoomSceneNames();

struct SyntheticViewStats {
  double gt_valid_fraction = 0;   // pixels with a surface
  double untextured_fraction = 0; // pixels on plain material (of all pixels)
  double gt_depth_min = 0, gt_depth_max = 0;
  int num_sparse_points = 0;      // observed in this image
  // COLMAP's depth range from the sparse points, and the share of GT pixels inside it.
  double sparse_depth_min = -1, sparse_depth_max = -1;
  double gt_in_sparse_range = 0;
};

struct SyntheticView {
  std::string name;  // image name, e.g. "view_00.png"
  SyntheticCamera camera;
  RenderedView render;
  double gain = 1, offset = 0;
  SyntheticViewStats stats;
};

struct SyntheticScene {
  SyntheticSceneOptions options;
  std::vector<SyntheticView> views;
  SparseModel model;  // images in view order, ids 1..n
  SparsePointLabels sparse_labels;  // where the sparse points lie, from the GT
  std::vector<double> plane_view_angles_deg;  // plane scene only
  std::vector<std::string> surface_names;     // SurfaceNames of the world (rooms)
};

// Share of GT pixels (depth > 0) on plain material, over all views.
double UntexturedShare(const SyntheticScene& scene);

// Renders everything in memory.
SyntheticScene RenderSyntheticScene(const SyntheticSceneOptions& options);
// Writes the workspace and gt/ into dir (created if needed; existing files are replaced).
void WriteSyntheticScene(const SyntheticScene& scene, const std::string& dir);
// Both of the above.
SyntheticScene GenerateSyntheticScene(const SyntheticSceneOptions& options, const std::string& dir);

// Every pixel with depth > 0 back-projected (MVS convention) to world coordinates, with
// world normals (when the map is given) and the image colour.
void AppendBackProjectedPoints(const SyntheticCamera& camera, const FloatMap& depth,
                               const FloatMap* normal, const RgbImage* image,
                               PlyPointCloud* cloud);

}  // namespace mpmvs

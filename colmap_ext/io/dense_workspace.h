#pragma once
// A COLMAP dense workspace as `colmap image_undistorter --output_type COLMAP` writes it:
// images/, sparse/ (bin or txt), stereo/{patch-match.cfg,fusion.cfg,depth_maps,normal_maps,
// consistency_graphs}. Loads the model, checks it is undistorted pinhole, applies
// max_image_size like COLMAP, resolves patch-match.cfg into problems.
#include <string>
#include <vector>

#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/sparse_model.h"

namespace mpmvs {

// One image of the workspace after max_image_size scaling. K, R row-major; X_cam = R X + T.
struct DenseView {
  std::string name;        // relative name as in images.bin, may contain '/'
  std::string image_path;  // workspace/images/name
  int width = 0;           // after max_image_size scaling
  int height = 0;
  int original_width = 0;  // as in the sparse model
  int original_height = 0;
  double K[9] = {0};
  double R[9] = {0};
  double T[3] = {0};
  // COLMAP's depth range from the sparse points seen by the image: 0.75 * z[floor(0.01 n)]
  // and 1.25 * z[floor(0.99 n)], z > 0 only, in float (ComputeDepthRanges). -1 when the
  // image sees no point.
  double depth_min = -1;
  double depth_max = -1;
  int num_sparse_points = 0;  // observations of sparse points (track entries of the image)
  // The range above is not to be trusted: float rounding of the points' world coordinates
  // reaches 10 % of the nearest depth (a model far from the origin, e.g. georeferenced).
  bool depth_range_imprecise = false;
};

// A reference image and its source images (model image indices).
struct StereoProblem {
  int ref = -1;
  std::vector<int> src;
};

struct DenseWorkspace {
  std::string path;
  SparseModel model;
  std::vector<DenseView> views;  // model image index order (= images.bin order)

  int FindView(const std::string& name) const;

  // stereo/depth_maps/NAME.TYPE.bin etc. (TYPE = "photometric" / "geometric").
  std::string DepthMapPath(int view, const std::string& type) const;
  std::string NormalMapPath(int view, const std::string& type) const;
  std::string ConsistencyGraphPath(int view, const std::string& type) const;
  // Folder for mp-mvs's intermediate results (stereo/mpmvs).
  std::string IntermediateDir() const;

  // Reads the image of a view as grey and resizes it to (width, height) when
  // max_image_size scaled it. Throws Error naming the file when missing, unreadable, or
  // when its size differs from the camera's.
  GrayImage ReadGray(int view) const;
  // The same as colour (grey files give R = G = B).
  RgbImage ReadRgb(int view) const;
};

// Maps and states are written under stereo/ by each image's name: it must be a path below
// images/, relative and without ".." (which could also make two names one file). Throws
// Error naming model_path otherwise.
void CheckImageNameStaysInside(const std::string& name, const std::string& model_path);

// Loads path/sparse (binary preferred) and checks images/ and stereo/ exist. Throws Error
// (naming the file/folder) for a missing workspace or sub-folder, a corrupt model, or a
// camera that is not SIMPLE_PINHOLE/PINHOLE ("... undistort the images first with colmap
// image_undistorter"). max_image_size <= 0: no scaling; else as COLMAP:
// f = min(max/w, max/h) if max(w,h) > max, new size round(w f), round(h f), fx,cx scaled by
// new_w/w and fy,cy by new_h/h.
DenseWorkspace LoadDenseWorkspace(const std::string& path, int max_image_size);

// Throws Error naming the path when it is not a folder with images/, sparse/ and stereo/.
void CheckDenseWorkspaceFolders(const std::string& path);

// Sets every view's depth_min/depth_max from the sparse points (model.points, tracks by
// model.images' ids) exactly as COLMAP's mvs::Model::ComputeDepthRanges does, in float from
// the float-rounded cameras and points, so that every loader that holds the same
// float cameras and points (mp-mvs's reader, COLMAP's mvs::Model) gets identical values.
void ComputeDepthRanges(DenseWorkspace* workspace);

// Parses patch-match.cfg (docs/colmap_interface.md §4): lines trimmed, '#' and empty lines
// skipped; alternating reference NAME and a source line: "__all__", "__auto__, N" or a
// comma-separated list of names. Unknown names, a dangling reference or a bad N -> Error
// naming the cfg file and line. __auto__ uses SelectSourcesAuto. References with zero
// sources are kept with an empty src (the caller warns and skips them).
std::vector<StereoProblem> ReadPatchMatchConfig(const std::string& cfg_path,
                                                const DenseWorkspace& workspace,
                                                double min_triangulation_angle_deg);

// COLMAP's __auto__ selection: images sharing sparse points with ref whose 75th-percentile
// triangulation angle is >= min angle, sorted by shared point count (desc, ties by index),
// at most max_num. As in COLMAP, a point counts once per pair of its track entries (an image
// observing a point twice counts twice) and the percentile is 3.8's nearest rank.
std::vector<int> SelectSourcesAuto(const DenseWorkspace& workspace, int ref, int max_num,
                                   double min_triangulation_angle_deg);

}  // namespace mpmvs

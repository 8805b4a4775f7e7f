#include "colmap_ext/evaluation/evaluation.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <unordered_map>

#include <nanoflann.hpp>

#include "colmap_ext/io/gt_files.h"
#include "colmap_ext/io/ply_io.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/thread_range.h"

namespace mpmvs {
namespace {

bool ValidDepth(float z) { return std::isfinite(z) && z > 0; }

// Index in a grid of size `to` nearest to index i of a grid of size `from` under the MVS
// convention (pixel i at coordinate i; K scales with the size).
int NearestIndex(int i, int from, int to) {
  if (from == to) return i;
  const long v = std::lround(static_cast<double>(i) * to / from);
  return static_cast<int>(std::min<long>(to - 1, std::max<long>(0, v)));
}

double Median(std::vector<float>* values) {
  if (values->empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t mid = values->size() / 2;
  std::nth_element(values->begin(), values->begin() + mid, values->end());
  double m = (*values)[mid];
  if (values->size() % 2 == 0) {
    m = 0.5 * (m + *std::max_element(values->begin(), values->begin() + mid));
  }
  return m;
}

// Counts of one pixel set (an image, its untextured part, or a pooled set).
class DepthAccumulator {
 public:
  explicit DepthAccumulator(const std::vector<double>& tolerances)
      : tolerances_(tolerances), good_(tolerances.size(), 0) {}

  void Add(float gt, float estimate) {
    ++num_gt_;
    if (!ValidDepth(estimate)) return;
    ++num_estimated_;
    const double rel = std::abs(static_cast<double>(estimate) - gt) / gt;
    errors_.push_back(static_cast<float>(rel));
    for (size_t k = 0; k < tolerances_.size(); ++k) good_[k] += rel < tolerances_[k];
    if (!tolerances_.empty() && rel >= tolerances_[0]) (estimate < gt ? too_near_ : too_far_) += 1;
  }

  void Merge(const DepthAccumulator& other) {
    num_gt_ += other.num_gt_;
    num_estimated_ += other.num_estimated_;
    too_near_ += other.too_near_;
    too_far_ += other.too_far_;
    for (size_t k = 0; k < good_.size(); ++k) good_[k] += other.good_[k];
    errors_.insert(errors_.end(), other.errors_.begin(), other.errors_.end());
  }

  DepthPixelScore Finish() const {
    DepthPixelScore s;
    s.num_gt = num_gt_;
    s.num_estimated = num_estimated_;
    s.num_too_near = too_near_;
    s.num_too_far = too_far_;
    for (size_t k = 0; k < tolerances_.size(); ++k) {
      DepthScoreAtTolerance t;
      t.tolerance = tolerances_[k];
      t.num_good = good_[k];
      t.accuracy = num_estimated_ ? static_cast<double>(good_[k]) / num_estimated_ : 0;
      t.completeness = num_gt_ ? static_cast<double>(good_[k]) / num_gt_ : 0;
      t.f1 = F1Score(t.accuracy, t.completeness);
      s.at.push_back(t);
    }
    std::vector<float> errors = errors_;
    s.median_rel_error = Median(&errors);
    return s;
  }

 private:
  std::vector<double> tolerances_;
  int64_t num_gt_ = 0;
  int64_t num_estimated_ = 0;
  int64_t too_near_ = 0, too_far_ = 0;
  std::vector<int64_t> good_;
  std::vector<float> errors_;
};

// Scores one image into the accumulators; surfaces (optional) holds one per label of
// gt.surface (label k in surfaces[k - 1]).
void AccumulateDepthMap(const FloatMap& estimate, const GtView& gt, DepthAccumulator* all,
                        DepthAccumulator* untextured,
                        std::vector<DepthAccumulator*>* surfaces = nullptr) {
  const int W = gt.depth.width, H = gt.depth.height;
  const bool has_mask = !gt.untextured.empty();
  const bool has_surfaces = surfaces && !gt.surface.empty();
  auto add = [&](int gr, int gc, float est) {
    const size_t p = static_cast<size_t>(gr) * W + gc;
    const float z = gt.depth.data[p];
    if (!ValidDepth(z)) return;
    all->Add(z, est);
    if (has_mask && gt.untextured[p]) untextured->Add(z, est);
    if (has_surfaces && gt.surface[p] > 0 && gt.surface[p] <= surfaces->size()) {
      (*surfaces)[gt.surface[p] - 1]->Add(z, est);
    }
  };
  if (estimate.Empty()) {
    for (int r = 0; r < H; ++r) {
      for (int c = 0; c < W; ++c) add(r, c, 0.f);
    }
    return;
  }
  const int w = estimate.width, h = estimate.height;
  if (static_cast<int64_t>(w) * h < static_cast<int64_t>(W) * H) {
    for (int r = 0; r < h; ++r) {
      for (int c = 0; c < w; ++c) add(NearestIndex(r, h, H), NearestIndex(c, w, W), estimate.At(r, c));
    }
  } else {
    for (int r = 0; r < H; ++r) {
      for (int c = 0; c < W; ++c) add(r, c, estimate.At(NearestIndex(r, H, h), NearestIndex(c, W, w)));
    }
  }
}

DepthImageScore ScoreImage(const FloatMap& estimate, const GtView& gt, DepthAccumulator* all,
                           DepthAccumulator* untextured,
                           std::vector<DepthAccumulator*>* surfaces = nullptr) {
  AccumulateDepthMap(estimate, gt, all, untextured, surfaces);
  DepthImageScore s;
  s.name = gt.name;
  s.has_estimate = !estimate.Empty();
  s.has_mask = !gt.untextured.empty();
  s.all = all->Finish();
  s.untextured = untextured->Finish();
  return s;
}

struct CloudAdaptor {
  const std::vector<Eigen::Vector3f>* points;
  size_t kdtree_get_point_count() const { return points->size(); }
  float kdtree_get_pt(size_t index, size_t dim) const { return (*points)[index][dim]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};
using CloudKdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudAdaptor>,
                                        CloudAdaptor, 3>;

// Squared distance from each query to its nearest neighbour in `cloud` (+inf when empty).
std::vector<float> NearestSquaredDistances(const std::vector<Eigen::Vector3f>& cloud,
                                           const std::vector<Eigen::Vector3f>& queries,
                                           int num_threads) {
  std::vector<float> d2(queries.size(), std::numeric_limits<float>::infinity());
  if (cloud.empty() || queries.empty()) return d2;
  CloudAdaptor adaptor{&cloud};
  CloudKdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  RunRangeInThreads(static_cast<int>(queries.size()), num_threads, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      uint32_t index = 0;
      float dist2 = 0;
      if (tree.knnSearch(queries[i].data(), 1, &index, &dist2) == 1) d2[i] = dist2;
    }
  });
  return d2;
}

// The depth of X in the view and the GT depth at its pixel, when X projects onto valid GT.
bool GtDepthAtPoint(const GtView& v, const Eigen::Vector3d& X, double* z, double* z_gt) {
  const double zc = v.R[6] * X.x() + v.R[7] * X.y() + v.R[8] * X.z() + v.t[2];
  if (!(zc > 0)) return false;
  const double xc = v.R[0] * X.x() + v.R[1] * X.y() + v.R[2] * X.z() + v.t[0];
  const double yc = v.R[3] * X.x() + v.R[4] * X.y() + v.R[5] * X.z() + v.t[1];
  const long col = std::lround(v.fx * xc / zc + v.cx);
  const long row = std::lround(v.fy * yc / zc + v.cy);
  if (col < 0 || row < 0 || col >= v.depth.width || row >= v.depth.height) return false;
  const float g = v.depth.data[static_cast<size_t>(row) * v.depth.width + col];
  if (!ValidDepth(g)) return false;
  *z = zc;
  *z_gt = g;
  return true;
}

bool ProjectsOntoValidGt(const GtView& v, const Eigen::Vector3f& X) {
  double z, z_gt;
  return GtDepthAtPoint(v, X.cast<double>(), &z, &z_gt);
}

std::string DepthMapPathOf(const std::string& workspace, const std::string& name,
                           const std::string& input_type) {
  return JoinPaths(workspace, "stereo/depth_maps/" + name + "." + input_type + ".bin");
}

}  // namespace

double F1Score(double accuracy, double completeness) {
  const double sum = accuracy + completeness;
  return sum > 0 ? 2 * accuracy * completeness / sum : 0;
}

void EvaluationOptions::Check() const {
  if (input_type != "geometric" && input_type != "photometric") {
    throw Error("--input_type must be geometric or photometric, not '" + input_type + "'");
  }
  if (depth_tolerances.empty() || cloud_tolerances.empty()) {
    throw Error("evaluation needs at least one depth and one point-cloud tolerance");
  }
  for (double t : depth_tolerances) {
    if (!(t > 0 && t < 1)) throw Error("--depth_tolerances: " + FormatNumber(t) + " is not in (0, 1)");
  }
  for (double t : cloud_tolerances) {
    if (!(t > 0 && t < 1)) throw Error("--cloud_tolerances: " + FormatNumber(t) + " is not in (0, 1)");
  }
  if (num_threads == 0 || num_threads < -1) throw Error("num_threads must be -1 or >= 1");
}

std::string ResolveGtDir(const std::string& gt_path) {
  if (!DirectoryExists(gt_path)) ThrowFileError(gt_path, "GT folder does not exist");
  const std::string nested = JoinPaths(gt_path, "gt");
  return DirectoryExists(nested) ? nested : gt_path;
}

namespace {

// The lines of gt/surfaces.txt (empty when absent): line k names surface label k.
std::vector<std::string> ReadGtSurfaceNames(const std::string& gt_dir) {
  const std::string path = GtSurfaceNamesPath(gt_dir);
  std::vector<std::string> names;
  if (!FileExists(path)) return names;
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  std::string line;
  for (const uint8_t c : bytes) {
    if (c == '\n') {
      names.push_back(line);
      line.clear();
    } else if (c != '\r') {
      line += static_cast<char>(c);
    }
  }
  if (!line.empty()) names.push_back(line);
  if (names.size() > 255) ThrowFileError(path, "more than 255 surfaces");
  return names;
}

// A GT picture (mask, labels) that must cover the GT depth map pixel for pixel.
GrayImage ReadGtImageOfDepthSize(const std::string& path, const PfmImage& depth) {
  GrayImage image = ReadGrayImage(path);
  if (image.width != depth.width || image.height != depth.height) {
    ThrowFileError(path, "size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                             " differs from the GT depth");
  }
  return image;
}

}  // namespace

std::vector<GtView> LoadGtViews(const SparseModel& model, const std::string& gt_dir) {
  const std::vector<std::string> surface_names = ReadGtSurfaceNames(gt_dir);
  std::vector<GtView> views;
  for (size_t i = 0; i < model.images.size(); ++i) {
    const SparseImage& image = model.images[i];
    const std::string depth_path = GtDepthPath(gt_dir, image.name);
    if (!FileExists(depth_path)) continue;
    const int cam_index = model.FindCamera(image.camera_id);
    if (cam_index < 0) {
      throw Error("image " + image.name + " refers to missing camera " +
                  std::to_string(image.camera_id));
    }
    const SparseCamera& cam = model.cameras[cam_index];
    GtView v;
    v.name = image.name;
    v.model_index = static_cast<int>(i);
    if (cam.model_id == kSimplePinholeModelId && cam.params.size() == 3) {
      v.fx = v.fy = cam.params[0];
      v.cx = cam.params[1];
      v.cy = cam.params[2];
    } else if (cam.model_id == kPinholeModelId && cam.params.size() == 4) {
      v.fx = cam.params[0];
      v.fy = cam.params[1];
      v.cx = cam.params[2];
      v.cy = cam.params[3];
    } else {
      throw Error("image " + image.name + ": camera model " + CameraModelName(cam.model_id) +
                  " cannot be evaluated; undistort the images first with colmap "
                  "image_undistorter");
    }
    v.depth = ReadPfm(depth_path);
    if (cam.width > 0 && cam.height > 0 &&
        (static_cast<uint64_t>(v.depth.width) != cam.width ||
         static_cast<uint64_t>(v.depth.height) != cam.height)) {
      const double sx = static_cast<double>(v.depth.width) / cam.width;
      const double sy = static_cast<double>(v.depth.height) / cam.height;
      v.fx *= sx;
      v.cx *= sx;
      v.fy *= sy;
      v.cy *= sy;
    }
    QuaternionToRotationMatrix(image.qvec, v.R);
    for (int k = 0; k < 3; ++k) v.t[k] = image.tvec[k];
    const std::string mask_path = GtUntexturedMaskPath(gt_dir, image.name);
    if (FileExists(mask_path)) {
      const GrayImage mask = ReadGtImageOfDepthSize(mask_path, v.depth);
      v.untextured.resize(mask.data.size());
      for (size_t p = 0; p < mask.data.size(); ++p) v.untextured[p] = mask.data[p] > 127.f;
    }
    const std::string surface_path = GtSurfaceLabelPath(gt_dir, image.name);
    if (!surface_names.empty() && FileExists(surface_path)) {
      const GrayImage labels = ReadGtImageOfDepthSize(surface_path, v.depth);
      v.surface.resize(labels.data.size());
      for (size_t p = 0; p < labels.data.size(); ++p) {
        const float k = std::round(labels.data[p]);
        if (k > surface_names.size()) {
          ThrowFileError(surface_path, "label " + std::to_string(static_cast<int>(k)) + " but " +
                                           GtSurfaceNamesPath(gt_dir) + " names " +
                                           std::to_string(surface_names.size()) + " surfaces");
        }
        v.surface[p] = static_cast<uint8_t>(k);
      }
      v.surface_names = surface_names;
    }
    views.push_back(std::move(v));
  }
  if (views.empty()) {
    throw Error(gt_dir + ": no GT depth file depth_<image stem>.pfm for any image of the model");
  }
  return views;
}

DepthImageScore ScoreDepthMap(const FloatMap& estimate, const GtView& gt,
                              const std::vector<double>& tolerances) {
  DepthAccumulator all(tolerances), untextured(tolerances);
  return ScoreImage(estimate, gt, &all, &untextured);
}

DepthEvaluation EvaluateDepthMaps(const std::vector<GtView>& gt,
                                  const std::vector<FloatMap>& estimates,
                                  const std::vector<double>& tolerances) {
  if (gt.size() != estimates.size()) {
    throw Error("EvaluateDepthMaps: " + std::to_string(gt.size()) + " GT views but " +
                std::to_string(estimates.size()) + " estimates");
  }
  DepthEvaluation e;
  e.tolerances = tolerances;
  DepthAccumulator pooled(tolerances), pooled_untextured(tolerances);
  std::deque<DepthAccumulator> pooled_surfaces;  // e.surface_names[k]'s in entry k (stable addresses)
  for (size_t i = 0; i < gt.size(); ++i) {
    // This view's labels, each to the pooled accumulator of its name.
    std::vector<DepthAccumulator*> surfaces;
    for (const std::string& name : gt[i].surface_names) {
      const size_t k = std::find(e.surface_names.begin(), e.surface_names.end(), name) - e.surface_names.begin();
      if (k == e.surface_names.size()) {
        e.surface_names.push_back(name);
        pooled_surfaces.emplace_back(tolerances);
      }
      surfaces.push_back(&pooled_surfaces[k]);
    }
    DepthAccumulator all(tolerances), untextured(tolerances);
    const DepthImageScore s = ScoreImage(estimates[i], gt[i], &all, &untextured, &surfaces);
    e.has_masks = e.has_masks || s.has_mask;
    e.images.push_back(s);
    pooled.Merge(all);
    pooled_untextured.Merge(untextured);
  }
  e.pooled = pooled.Finish();
  e.pooled_untextured = pooled_untextured.Finish();
  for (const DepthAccumulator& a : pooled_surfaces) e.pooled_surfaces.push_back(a.Finish());
  return e;
}

namespace {

DepthEvaluation EvaluateDepthMapsOf(const std::string& workspace_path,
                                    const std::vector<GtView>& gt,
                                    const EvaluationOptions& options) {
  std::vector<FloatMap> estimates(gt.size());
  for (size_t i = 0; i < gt.size(); ++i) {
    const std::string path = DepthMapPathOf(workspace_path, gt[i].name, options.input_type);
    if (FileExists(path)) estimates[i] = ReadFloatMap(path, 1);
  }
  DepthEvaluation e = EvaluateDepthMaps(gt, estimates, options.depth_tolerances);
  e.input_type = options.input_type;
  return e;
}

PointCloudEvaluation EvaluatePointCloudOf(const std::vector<GtView>& gt,
                                          const std::string& fused_path,
                                          const EvaluationOptions& options) {
  const PlyPointCloud cloud = ReadPlyPointCloud(fused_path);
  std::vector<Eigen::Vector3f> points;
  points.reserve(cloud.points.size());
  for (const PlyPoint& p : cloud.points) points.emplace_back(p.x, p.y, p.z);
  PointCloudEvaluation e = ScorePointCloud(gt, points, options.cloud_tolerances, options.num_threads);
  e.fused_path = fused_path;
  return e;
}

}  // namespace

DepthEvaluation EvaluateDepthMaps(const std::string& workspace_path, const std::string& gt_path,
                                  const EvaluationOptions& options) {
  options.Check();
  const SparseModel model = ReadSparseModel(JoinPaths(workspace_path, "sparse"));
  return EvaluateDepthMapsOf(workspace_path, LoadGtViews(model, ResolveGtDir(gt_path)), options);
}

SparseGtAgreement CompareSparsePointsWithGt(const SparseModel& model, const std::vector<GtView>& gt) {
  std::unordered_map<uint32_t, int> gt_of_image_id;  // tracks name images by id
  for (size_t k = 0; k < gt.size(); ++k) {
    if (gt[k].model_index >= 0 && static_cast<size_t>(gt[k].model_index) < model.images.size()) {
      gt_of_image_id[model.images[gt[k].model_index].image_id] = static_cast<int>(k);
    }
  }
  std::vector<float> signed_diff;
  for (const SparsePoint3D& p : model.points) {
    const Eigen::Vector3d X(p.xyz[0], p.xyz[1], p.xyz[2]);
    for (const SparseTrackElement& el : p.track) {
      const auto view = gt_of_image_id.find(el.image_id);
      double z, z_gt;
      if (view == gt_of_image_id.end() || !GtDepthAtPoint(gt[view->second], X, &z, &z_gt)) continue;
      signed_diff.push_back(static_cast<float>((z - z_gt) / z_gt));
    }
  }
  SparseGtAgreement a;
  a.num_observations = static_cast<int64_t>(signed_diff.size());
  if (!signed_diff.empty()) {
    std::vector<float> abs_diff(signed_diff.size());
    for (size_t i = 0; i < signed_diff.size(); ++i) abs_diff[i] = std::fabs(signed_diff[i]);
    a.median_rel_difference = Median(&signed_diff);
    a.median_abs_rel_difference = Median(&abs_diff);
  }
  return a;
}

bool GtDisagreesWithPoses(const SparseGtAgreement& agreement, double tolerance) {
  return agreement.num_observations > 0 && std::fabs(agreement.median_rel_difference) >= 0.5 * tolerance;
}

std::vector<Eigen::Vector3f> BackProjectGtViews(const std::vector<GtView>& gt) {
  std::vector<Eigen::Vector3f> points;
  for (const GtView& v : gt) {
    for (int r = 0; r < v.depth.height; ++r) {
      for (int c = 0; c < v.depth.width; ++c) {
        const double z = v.depth.data[static_cast<size_t>(r) * v.depth.width + c];
        if (!ValidDepth(static_cast<float>(z))) continue;
        const double xc = z * (c - v.cx) / v.fx - v.t[0];
        const double yc = z * (r - v.cy) / v.fy - v.t[1];
        const double zc = z - v.t[2];
        // X = R^T (X_cam - t)
        points.emplace_back(static_cast<float>(v.R[0] * xc + v.R[3] * yc + v.R[6] * zc),
                            static_cast<float>(v.R[1] * xc + v.R[4] * yc + v.R[7] * zc),
                            static_cast<float>(v.R[2] * xc + v.R[5] * yc + v.R[8] * zc));
      }
    }
  }
  return points;
}

PointCloudEvaluation ScorePointCloud(const std::vector<GtView>& gt,
                                     const std::vector<Eigen::Vector3f>& points,
                                     const std::vector<double>& relative_tolerances,
                                     int num_threads) {
  PointCloudEvaluation e;
  const std::vector<Eigen::Vector3f> gt_points = BackProjectGtViews(gt);
  std::vector<float> depths;
  depths.reserve(gt_points.size());
  for (const GtView& v : gt) {
    for (float z : v.depth.data) {
      if (ValidDepth(z)) depths.push_back(z);
    }
  }
  e.median_gt_depth = Median(&depths);
  e.num_points = static_cast<int64_t>(points.size());
  e.num_gt_points = static_cast<int64_t>(gt_points.size());

  std::vector<uint8_t> observed(points.size(), 0);
  RunRangeInThreads(static_cast<int>(points.size()), num_threads, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      for (const GtView& v : gt) {
        if (ProjectsOntoValidGt(v, points[i])) {
          observed[i] = 1;
          break;
        }
      }
    }
  });
  std::vector<Eigen::Vector3f> observed_points;
  for (size_t i = 0; i < points.size(); ++i) {
    if (observed[i]) observed_points.push_back(points[i]);
  }
  e.num_observed = static_cast<int64_t>(observed_points.size());

  const std::vector<float> acc_d2 = NearestSquaredDistances(gt_points, observed_points, num_threads);
  const std::vector<float> comp_d2 = NearestSquaredDistances(points, gt_points, num_threads);
  for (double rel : relative_tolerances) {
    CloudScoreAtTolerance s;
    s.relative_tolerance = rel;
    s.tolerance = std::isfinite(e.median_gt_depth) ? rel * e.median_gt_depth : 0;
    const double d2 = s.tolerance * s.tolerance;
    for (float v : acc_d2) s.num_accurate += v <= d2;
    for (float v : comp_d2) s.num_complete += v <= d2;
    s.accuracy = e.num_observed ? static_cast<double>(s.num_accurate) / e.num_observed : 0;
    s.completeness = e.num_gt_points ? static_cast<double>(s.num_complete) / e.num_gt_points : 0;
    s.f1 = F1Score(s.accuracy, s.completeness);
    e.at.push_back(s);
  }
  return e;
}

PointCloudEvaluation EvaluatePointCloud(const std::string& workspace_path,
                                        const std::string& gt_path,
                                        const std::string& fused_path,
                                        const EvaluationOptions& options) {
  options.Check();
  const SparseModel model = ReadSparseModel(JoinPaths(workspace_path, "sparse"));
  return EvaluatePointCloudOf(LoadGtViews(model, ResolveGtDir(gt_path)), fused_path, options);
}

WorkspaceEvaluation EvaluateWorkspace(const std::string& workspace_path,
                                      const std::string& gt_path, const std::string& fused_path,
                                      const EvaluationOptions& options) {
  options.Check();
  WorkspaceEvaluation w;
  w.label = workspace_path;
  w.workspace_path = workspace_path;
  w.gt_dir = ResolveGtDir(gt_path);
  const SparseModel model = ReadSparseModel(JoinPaths(workspace_path, "sparse"));
  const std::vector<GtView> gt = LoadGtViews(model, w.gt_dir);
  w.depth = EvaluateDepthMapsOf(workspace_path, gt, options);
  w.sparse_vs_gt = CompareSparsePointsWithGt(model, gt);
  std::string cloud_path = fused_path;
  if (cloud_path.empty()) {
    const std::string default_path = JoinPaths(workspace_path, "fused.ply");
    if (FileExists(default_path)) cloud_path = default_path;
  } else if (cloud_path == "none") {
    cloud_path.clear();
  } else if (!FileExists(cloud_path)) {
    ThrowFileError(cloud_path, "fused point cloud does not exist");
  }
  if (!cloud_path.empty()) {
    w.has_cloud = true;
    w.cloud = EvaluatePointCloudOf(gt, cloud_path, options);
  }
  return w;
}

AgreementCounts CompareDepthMaps(const FloatMap& a, const FloatMap& b, double tolerance) {
  AgreementCounts n;
  const bool a_grid = static_cast<int64_t>(a.width) * a.height <= static_cast<int64_t>(b.width) * b.height;
  const FloatMap& g = a_grid ? a : b;   // grid
  const FloatMap& o = a_grid ? b : a;   // sampled
  for (int r = 0; r < g.height; ++r) {
    for (int c = 0; c < g.width; ++c) {
      const float zg = g.At(r, c);
      const float zo = o.At(NearestIndex(r, g.height, o.height), NearestIndex(c, g.width, o.width));
      const float za = a_grid ? zg : zo, zb = a_grid ? zo : zg;
      ++n.num_pixels;
      const bool va = ValidDepth(za), vb = ValidDepth(zb);
      n.num_a += va;
      n.num_b += vb;
      if (va && vb) {
        ++n.num_both;
        n.num_agree += std::abs(static_cast<double>(za) - zb) / (0.5 * (static_cast<double>(za) + zb)) < tolerance;
      }
    }
  }
  return n;
}

std::vector<PairAgreement> ComputeDepthAgreement(const std::vector<std::string>& workspaces,
                                                 const std::string& input_type,
                                                 double tolerance) {
  if (workspaces.size() < 2) throw Error("comparing depth maps needs at least two workspaces");
  if (!(tolerance > 0 && tolerance < 1)) throw Error("agreement tolerance must be in (0, 1)");
  const SparseModel model = ReadSparseModel(JoinPaths(workspaces[0], "sparse"));
  std::vector<PairAgreement> pairs;
  for (size_t a = 0; a < workspaces.size(); ++a) {
    for (size_t b = a + 1; b < workspaces.size(); ++b) {
      PairAgreement pair;
      pair.a = static_cast<int>(a);
      pair.b = static_cast<int>(b);
      for (const SparseImage& image : model.images) {
        ImageAgreement ia;
        ia.name = image.name;
        const std::string pa = DepthMapPathOf(workspaces[a], image.name, input_type);
        const std::string pb = DepthMapPathOf(workspaces[b], image.name, input_type);
        ia.present_a = FileExists(pa);
        ia.present_b = FileExists(pb);
        if (ia.present_a && ia.present_b) {
          ia.counts = CompareDepthMaps(ReadFloatMap(pa, 1), ReadFloatMap(pb, 1), tolerance);
        } else if (ia.present_a || ia.present_b) {
          const FloatMap m = ReadFloatMap(ia.present_a ? pa : pb, 1);
          ia.counts.num_pixels = static_cast<int64_t>(m.width) * m.height;
          int64_t valid = 0;
          for (float z : m.data) valid += ValidDepth(z);
          (ia.present_a ? ia.counts.num_a : ia.counts.num_b) = valid;
        }
        pair.pooled.num_pixels += ia.counts.num_pixels;
        pair.pooled.num_a += ia.counts.num_a;
        pair.pooled.num_b += ia.counts.num_b;
        pair.pooled.num_both += ia.counts.num_both;
        pair.pooled.num_agree += ia.counts.num_agree;
        pair.images.push_back(ia);
      }
      pairs.push_back(pair);
    }
  }
  return pairs;
}

}  // namespace mpmvs

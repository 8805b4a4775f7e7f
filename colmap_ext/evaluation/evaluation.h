#pragma once
// Quality scores against ground truth, exactly as docs/evaluation.md
// defines them:
//  * depth maps: per image and pooled, at relative tolerances tau (by default 1 %, 2 %):
//    accuracy = good / (GT pixels with an estimate), completeness = good / GT pixels,
//    F1; again on untextured pixels where gt/untextured_<stem>.png exists;
//  * point cloud (ETH3D style): GT cloud = every valid GT pixel of every GT image
//    back-projected; accuracy over fused points that project onto valid GT in at least
//    one GT image, completeness over GT points, at fractions of the median GT depth (by
//    default 0.5 % and 1 %);
//  * the GT against the model's poses: the sparse points' depths against the GT depth.
// Also the mutual agreement of several workspaces' depth maps where no GT exists.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/sparse_model.h"

namespace mpmvs {

struct EvaluationOptions {
  std::string input_type = "geometric";                // depth maps NAME.<input_type>.bin
  std::vector<double> depth_tolerances = {0.01, 0.02};  // relative depth error
  std::vector<double> cloud_tolerances = {0.005, 0.01}; // fractions of the median GT depth
  int num_threads = -1;

  void Check() const;  // throws Error
};

// One image with GT: its camera (from the workspace's sparse model, scaled to the GT map
// size), GT depth and optional untextured mask.
struct GtView {
  std::string name;  // image name in the model
  int model_index = -1;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // X_cam = R X + t
  double t[3] = {0, 0, 0};
  PfmImage depth;                   // 0 / non-finite = unknown
  std::vector<uint8_t> untextured;  // 1 = untextured pixel; empty = no mask
  // Named surfaces (gt/surface_<stem>.png, gt/surfaces.txt): surface[p] = k > 0 where pixel p
  // shows surface_names[k - 1]; both empty when the GT names none.
  std::vector<uint8_t> surface;
  std::vector<std::string> surface_names;
};

// gt_path may be the folder holding depth_<stem>.pfm or a dataset folder with gt/ inside.
std::string ResolveGtDir(const std::string& gt_path);
// GT views of all model images that have gt_dir/depth_<stem>.pfm, in model order. Throws
// Error when no image has GT or a mask's size differs from its depth map.
std::vector<GtView> LoadGtViews(const SparseModel& model, const std::string& gt_dir);

// ---- depth maps
struct DepthScoreAtTolerance {
  double tolerance = 0;
  int64_t num_good = 0;
  double accuracy = 0, completeness = 0, f1 = 0;
};

struct DepthPixelScore {
  int64_t num_gt = 0;         // pixels with valid GT
  int64_t num_estimated = 0;  // of those, pixels with an estimate (> 0)
  std::vector<DepthScoreAtTolerance> at;  // one per tolerance, same order
  // Estimates off by at least the first tolerance, nearer / farther than the GT.
  int64_t num_too_near = 0, num_too_far = 0;
  double median_rel_error = std::numeric_limits<double>::quiet_NaN();  // estimated pixels
};

struct DepthImageScore {
  std::string name;
  bool has_estimate = false;  // the depth-map file existed
  bool has_mask = false;
  DepthPixelScore all;
  DepthPixelScore untextured;  // only meaningful when has_mask
};

struct DepthEvaluation {
  std::string input_type;
  std::vector<double> tolerances;
  std::vector<DepthImageScore> images;
  DepthPixelScore pooled;
  DepthPixelScore pooled_untextured;
  bool has_masks = false;  // any image had an untextured mask
  // Pooled over the images, per named surface (GtView::surface_names), in order of appearance.
  std::vector<std::string> surface_names;
  std::vector<DepthPixelScore> pooled_surfaces;
};

// Pixel-wise comparison on a common grid: when the estimate is smaller than the GT, every
// estimate pixel is scored against the GT pixel nearest to it (MVS convention: estimate
// pixel c sits at GT coordinate c * W_gt / W_est); otherwise every GT pixel is scored
// against the nearest estimate pixel. An empty estimate counts as "no estimate anywhere".
DepthImageScore ScoreDepthMap(const FloatMap& estimate, const GtView& gt,
                              const std::vector<double>& tolerances);
// estimates[i] belongs to gt[i]; an empty map means the file is missing.
DepthEvaluation EvaluateDepthMaps(const std::vector<GtView>& gt,
                                  const std::vector<FloatMap>& estimates,
                                  const std::vector<double>& tolerances);
// Reads WS/sparse, the GT and WS/stereo/depth_maps/<name>.<input_type>.bin.
DepthEvaluation EvaluateDepthMaps(const std::string& workspace_path, const std::string& gt_path,
                                  const EvaluationOptions& options);

// ---- point cloud
struct CloudScoreAtTolerance {
  double relative_tolerance = 0;  // fraction of the median GT depth
  double tolerance = 0;           // metres
  int64_t num_accurate = 0;       // observed fused points within tolerance of GT
  int64_t num_complete = 0;       // GT points within tolerance of a fused point
  double accuracy = 0, completeness = 0, f1 = 0;
};

struct PointCloudEvaluation {
  std::string fused_path;
  int64_t num_points = 0;     // fused points
  int64_t num_observed = 0;   // fused points projecting onto valid GT somewhere
  int64_t num_gt_points = 0;
  double median_gt_depth = 0;
  std::vector<CloudScoreAtTolerance> at;
};

// Every valid GT pixel of every view back-projected (MVS convention).
std::vector<Eigen::Vector3f> BackProjectGtViews(const std::vector<GtView>& gt);
PointCloudEvaluation ScorePointCloud(const std::vector<GtView>& gt,
                                     const std::vector<Eigen::Vector3f>& points,
                                     const std::vector<double>& relative_tolerances,
                                     int num_threads = -1);
// Reads WS/sparse, the GT and the fused PLY.
PointCloudEvaluation EvaluatePointCloud(const std::string& workspace_path,
                                        const std::string& gt_path,
                                        const std::string& fused_path,
                                        const EvaluationOptions& options);

// ---- the GT against the model's poses
// The model's sparse points at the GT views that observe them (their tracks): each point's
// depth in the view against the GT depth at its pixel. Real GT (a depth sensor registered to
// the images) can disagree with the poses; scores at tolerances near that disagreement judge
// the GT as much as the depth maps.
struct SparseGtAgreement {
  int64_t num_observations = 0;  // observations that land on valid GT
  double median_rel_difference = std::numeric_limits<double>::quiet_NaN();      // (z - z_gt) / z_gt
  double median_abs_rel_difference = std::numeric_limits<double>::quiet_NaN();  // |z - z_gt| / z_gt
};

SparseGtAgreement CompareSparsePointsWithGt(const SparseModel& model, const std::vector<GtView>& gt);
// Whether the median difference reaches half of the tolerance (then say so beside scores at it).
bool GtDisagreesWithPoses(const SparseGtAgreement& agreement, double tolerance);

// ---- both, for one workspace
struct WorkspaceEvaluation {
  std::string label;  // column title in comparisons (defaults to the workspace path)
  std::string workspace_path;
  std::string gt_dir;
  DepthEvaluation depth;
  SparseGtAgreement sparse_vs_gt;
  bool has_cloud = false;
  PointCloudEvaluation cloud;
};

// fused_path: "" = WS/fused.ply when it exists, "none" = skip the point cloud.
WorkspaceEvaluation EvaluateWorkspace(const std::string& workspace_path,
                                      const std::string& gt_path, const std::string& fused_path,
                                      const EvaluationOptions& options);

// ---- agreement between workspaces without GT
struct AgreementCounts {
  int64_t num_pixels = 0;  // pixels compared
  int64_t num_a = 0;       // with an estimate in A
  int64_t num_b = 0;
  int64_t num_both = 0;
  int64_t num_agree = 0;   // both, and |za - zb| / ((za + zb) / 2) < tolerance
  double AgreeShare() const { return num_both ? static_cast<double>(num_agree) / num_both : 0; }
};

struct ImageAgreement {
  std::string name;
  bool present_a = false, present_b = false;  // the depth-map files existed
  AgreementCounts counts;
};

struct PairAgreement {
  int a = 0, b = 0;  // workspace indices
  std::vector<ImageAgreement> images;
  AgreementCounts pooled;
};

// Pixel-wise agreement of two depth maps (sizes may differ: compared on the smaller grid).
AgreementCounts CompareDepthMaps(const FloatMap& a, const FloatMap& b, double tolerance);
// For every pair of workspaces, over the images of the first workspace's model.
std::vector<PairAgreement> ComputeDepthAgreement(const std::vector<std::string>& workspaces,
                                                 const std::string& input_type,
                                                 double tolerance);

// F1 from accuracy and completeness (0 when both are 0).
double F1Score(double accuracy, double completeness);

}  // namespace mpmvs

// Evaluation (docs/evaluation.md): depth-map scores with known fractions of wrong pixels,
// point-cloud scores with known shifts/removals, GT against itself, PLY I/O, the
// agreement of workspaces without GT and the evaluate/compare commands end to end.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "colmap_ext/cli/commands.h"
#include "colmap_ext/evaluation/evaluation.h"
#include "colmap_ext/evaluation/evaluation_report.h"
#include "colmap_ext/io/gt_files.h"
#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/ply_io.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;

// A camera at the origin looking down +z at a fronto-parallel plane z = depth.
GtView PlaneGtView(int width, int height, double f, float depth) {
  GtView v;
  v.name = "plane.png";
  v.fx = v.fy = f;
  v.cx = 0.5 * width;
  v.cy = 0.5 * height;
  v.depth.width = width;
  v.depth.height = height;
  v.depth.data.assign(static_cast<size_t>(width) * height, depth);
  return v;
}

SyntheticSceneOptions TinyScene() {
  SyntheticSceneOptions o;
  o.scene = "indoor";
  o.width = 160;
  o.height = 120;
  o.num_views = 3;
  o.supersampling = 2;
  return o;
}

// Copies the GT maps into the workspace as if a perfect method had produced them.
void InstallGtAsEstimates(const std::string& dir, const SyntheticScene& scene) {
  for (const SyntheticView& v : scene.views) {
    fs::copy_file(dir + "/gt/depth_maps/" + v.name + ".bin",
                  dir + "/stereo/depth_maps/" + v.name + ".geometric.bin",
                  fs::copy_options::overwrite_existing);
    fs::copy_file(dir + "/gt/normal_maps/" + v.name + ".bin",
                  dir + "/stereo/normal_maps/" + v.name + ".geometric.bin",
                  fs::copy_options::overwrite_existing);
  }
}

TEST(Evaluation, DepthMapsWithKnownFractionWrong) {
  // 10 x 10 GT at 2 m; 10 pixels without GT. Of the 90 with GT: 50 exact, 20 off by
  // 1.5 % (good at 2 % only), 10 off by 10 %, 10 without estimate.
  GtView gt = PlaneGtView(10, 10, 10, 2.0f);
  gt.untextured.assign(100, 0);
  FloatMap est(10, 10, 1, 0.f);
  int expected_untextured_gt = 0, expected_untextured_est = 0, expected_untextured_good1 = 0;
  for (int i = 0; i < 100; ++i) {
    const int r = i / 10, c = i % 10;
    if (i < 10) {
      gt.depth.data[i] = 0;  // no GT; a (wrong) estimate there must not count
      est.At(r, c) = 5.f;
      continue;
    }
    const int k = i - 10;  // 0..89
    if (k < 50) est.At(r, c) = 2.0f;
    else if (k < 70) est.At(r, c) = 2.0f * 1.015f;
    else if (k < 80) est.At(r, c) = 2.0f * 1.10f;
    // else: no estimate
    if (k % 3 == 0) {  // every third GT pixel is "untextured"
      gt.untextured[i] = 1;
      ++expected_untextured_gt;
      if (k < 80) ++expected_untextured_est;
      if (k < 50) ++expected_untextured_good1;
    }
  }
  const DepthImageScore s = ScoreDepthMap(est, gt, {0.01, 0.02});
  EXPECT_EQ(s.all.num_gt, 90);
  EXPECT_EQ(s.all.num_estimated, 80);
  ASSERT_EQ(s.all.at.size(), 2u);
  EXPECT_EQ(s.all.at[0].num_good, 50);
  EXPECT_NEAR(s.all.at[0].accuracy, 50.0 / 80, 1e-12);
  EXPECT_NEAR(s.all.at[0].completeness, 50.0 / 90, 1e-12);
  EXPECT_NEAR(s.all.at[0].f1, 2 * (50.0 / 80) * (50.0 / 90) / (50.0 / 80 + 50.0 / 90), 1e-12);
  EXPECT_EQ(s.all.at[1].num_good, 70);
  EXPECT_NEAR(s.all.at[1].accuracy, 70.0 / 80, 1e-12);
  EXPECT_NEAR(s.all.at[1].completeness, 70.0 / 90, 1e-12);
  EXPECT_NEAR(s.all.median_rel_error, 0.0, 1e-12);  // 50 of 80 are exact
  EXPECT_TRUE(s.has_mask);
  EXPECT_EQ(s.untextured.num_gt, expected_untextured_gt);
  EXPECT_EQ(s.untextured.num_estimated, expected_untextured_est);
  EXPECT_EQ(s.untextured.at[0].num_good, expected_untextured_good1);

  // Pooled over two images = the sums; a missing map counts as no estimate at all.
  const DepthEvaluation e = EvaluateDepthMaps({gt, gt}, {est, FloatMap()}, {0.01, 0.02});
  EXPECT_EQ(e.pooled.num_gt, 180);
  EXPECT_EQ(e.pooled.num_estimated, 80);
  EXPECT_NEAR(e.pooled.at[0].completeness, 50.0 / 180, 1e-12);
  EXPECT_NEAR(e.pooled.at[0].accuracy, 50.0 / 80, 1e-12);
  EXPECT_FALSE(e.images[1].has_estimate);
  EXPECT_EQ(e.images[1].all.num_estimated, 0);
  EXPECT_EQ(e.images[1].all.at[0].f1, 0.0);
  EXPECT_TRUE(e.has_masks);
}

TEST(Evaluation, NamedSurfacesArePooledByNameWithTheSignOfTheirErrors) {
  // Two images whose labels name the same surfaces in another order: scores pool by name.
  // Row 0 of each 10 x 2 image is surface "wall", row 1 "floor"; no label in column 9.
  GtView a = PlaneGtView(10, 2, 10, 2.0f), b = PlaneGtView(10, 2, 10, 2.0f);
  a.surface_names = {"wall", "floor", "ceiling"};  // no pixel shows the ceiling
  b.surface_names = {"floor", "wall"};
  a.surface.assign(20, 0);
  b.surface.assign(20, 0);
  for (int c = 0; c < 9; ++c) {
    a.surface[c] = 1, a.surface[10 + c] = 2;
    b.surface[c] = 2, b.surface[10 + c] = 1;
  }
  // Wall pixels: 4 exact, 2 too near (-5 %), 2 too far (+5 %), 1 without an estimate; floor
  // pixels all exact except 3 too near in image a only.
  FloatMap est(10, 2, 1, 2.0f);
  const float wall[9] = {2.f, 2.f, 2.f, 2.f, 1.9f, 1.9f, 2.1f, 2.1f, 0.f};
  for (int c = 0; c < 9; ++c) est.At(0, c) = wall[c];
  FloatMap est_a = est;
  for (int c = 0; c < 3; ++c) est_a.At(1, c) = 1.5f;
  const DepthEvaluation e = EvaluateDepthMaps({a, b}, {est_a, est}, {0.01, 0.02});
  ASSERT_EQ(e.surface_names, (std::vector<std::string>{"wall", "floor", "ceiling"}));
  ASSERT_EQ(e.pooled_surfaces.size(), 3u);
  EXPECT_EQ(e.pooled_surfaces[2].num_gt, 0);
  const DepthPixelScore& w = e.pooled_surfaces[0];
  EXPECT_EQ(w.num_gt, 18);
  EXPECT_EQ(w.num_estimated, 16);
  EXPECT_EQ(w.at[0].num_good, 8);
  EXPECT_EQ(w.num_too_near, 4);
  EXPECT_EQ(w.num_too_far, 4);
  const DepthPixelScore& f = e.pooled_surfaces[1];
  EXPECT_EQ(f.num_gt, 18);
  EXPECT_EQ(f.at[0].num_good, 15);
  EXPECT_EQ(f.num_too_near, 3);
  EXPECT_EQ(f.num_too_far, 0);
  // The whole image counts the same signs (column 9 included).
  EXPECT_EQ(e.pooled.num_too_near, 7);
  EXPECT_EQ(e.pooled.num_too_far, 4);
  WorkspaceEvaluation we;
  we.depth = e;
  const std::string table = FormatScoreTable(we);
  EXPECT_NE(table.find("surface wall"), std::string::npos) << table;
  EXPECT_NE(table.find("too near"), std::string::npos) << table;
  EXPECT_EQ(table.find("ceiling"), std::string::npos) << table;  // a surface no image shows
}

TEST(Evaluation, SmallerEstimateIsScoredAgainstNearestGtPixel) {
  GtView gt = PlaneGtView(8, 6, 8, 1.0f);
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 8; ++c) gt.depth.data[r * 8 + c] = 1.0f + c;  // distinct per column
  }
  FloatMap half(4, 3, 1);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) half.At(r, c) = 1.0f + 2 * c;  // GT at column 2c
  }
  DepthImageScore s = ScoreDepthMap(half, gt, {0.01});
  EXPECT_EQ(s.all.num_gt, 12);  // scored on the estimate's grid
  EXPECT_EQ(s.all.at[0].num_good, 12);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) half.At(r, c) = 2.0f + 2 * c;  // one column off
  }
  s = ScoreDepthMap(half, gt, {0.01});
  EXPECT_EQ(s.all.at[0].num_good, 0);
}

TEST(Evaluation, PointCloudShiftedRemovedAndOutliers) {
  // Plane at 2 m, 40 x 30 pixels, f = 40: GT points 5 cm apart; median depth 2 m, so the
  // tolerances are 1 cm (0.5 %) and 2 cm (1 %). The first 4 columns have no GT.
  GtView gt = PlaneGtView(40, 30, 40, 2.0f);
  for (int r = 0; r < 30; ++r) {
    for (int c = 0; c < 4; ++c) gt.depth.data[r * 40 + c] = 0;
  }
  const std::vector<Eigen::Vector3f> gt_points = BackProjectGtViews({gt});
  ASSERT_EQ(gt_points.size(), 36u * 30);
  const std::vector<double> tols = {0.005, 0.01};

  PointCloudEvaluation e = ScorePointCloud({gt}, gt_points, tols, 2);
  EXPECT_DOUBLE_EQ(e.median_gt_depth, 2.0);
  ASSERT_EQ(e.at.size(), 2u);
  EXPECT_NEAR(e.at[0].tolerance, 0.01, 1e-9);
  for (const CloudScoreAtTolerance& t : e.at) {
    EXPECT_DOUBLE_EQ(t.accuracy, 1.0);
    EXPECT_DOUBLE_EQ(t.completeness, 1.0);
    EXPECT_DOUBLE_EQ(t.f1, 1.0);
  }

  // Shifted 1.5 cm along the plane normal: wrong at 1 cm, right at 2 cm.
  std::vector<Eigen::Vector3f> shifted = gt_points;
  for (Eigen::Vector3f& p : shifted) p.z() -= 0.015f;
  e = ScorePointCloud({gt}, shifted, tols, 2);
  EXPECT_DOUBLE_EQ(e.at[0].accuracy, 0.0);
  EXPECT_DOUBLE_EQ(e.at[0].completeness, 0.0);
  EXPECT_DOUBLE_EQ(e.at[1].accuracy, 1.0);
  EXPECT_DOUBLE_EQ(e.at[1].completeness, 1.0);

  // Right half removed: every remaining point accurate, completeness = remaining share.
  std::vector<Eigen::Vector3f> half;
  for (const Eigen::Vector3f& p : gt_points) {
    if (p.x() < 0) half.push_back(p);  // columns 4..19 of 4..39
  }
  e = ScorePointCloud({gt}, half, tols, 2);
  EXPECT_DOUBLE_EQ(e.at[0].accuracy, 1.0);
  EXPECT_NEAR(e.at[0].completeness, 16.0 / 36.0, 1e-12);
  EXPECT_NEAR(e.at[1].completeness, 16.0 / 36.0, 1e-12);

  // Outliers: 270 points 30 cm in front of the plane over valid GT lower accuracy by a
  // known share; points over the GT-less columns or outside the view are ignored.
  std::vector<Eigen::Vector3f> noisy = gt_points;
  for (int i = 0; i < 270; ++i) {
    // Pixel (row i % 30, column 10 + i / 30) back-projected to 1.9 m: it projects onto that
    // pixel (valid GT) but lies 10 cm off the plane.
    const int r = i % 30, c = 10 + i / 30;
    noisy.emplace_back(1.9f * (c - 20) / 40.f, 1.9f * (r - 15) / 40.f, 1.9f);
  }
  const size_t observed_before = noisy.size();
  for (int r = 0; r < 30; ++r) noisy.emplace_back(-0.93f, (r - 15) * 0.05f, 2.0f);  // GT-less column
  noisy.emplace_back(50.f, 0.f, 2.f);   // outside the image
  noisy.emplace_back(0.f, 0.f, -3.f);   // behind the camera
  e = ScorePointCloud({gt}, noisy, tols, 2);
  EXPECT_EQ(e.num_points, static_cast<int64_t>(noisy.size()));
  EXPECT_EQ(e.num_observed, static_cast<int64_t>(observed_before));
  EXPECT_NEAR(e.at[0].accuracy, 1080.0 / 1350.0, 1e-12);
  EXPECT_DOUBLE_EQ(e.at[0].completeness, 1.0);

  // Empty cloud.
  e = ScorePointCloud({gt}, {}, tols, 1);
  EXPECT_EQ(e.at[0].f1, 0.0);
}

TEST(Evaluation, SurfaceLabelsAreReadAndCheckedAgainstTheirNames) {
  test::TempDir dir;
  const SyntheticScene scene = GenerateSyntheticScene(TinyScene(), dir.path());
  const SparseModel model = ReadSparseModel(dir / "sparse");
  EXPECT_TRUE(LoadGtViews(model, dir / "gt")[0].surface.empty());  // indoor names no surface
  // Left half "wall" (1), right half "floor" (2) in every view.
  std::ofstream(dir / "gt/surfaces.txt") << "wall\nfloor\n";
  std::vector<uint8_t> labels(160 * 120);
  for (size_t p = 0; p < labels.size(); ++p) labels[p] = p % 160 < 80 ? 1 : 2;
  for (const SyntheticView& v : scene.views) WriteGrayPng(dir / ("gt/surface_" + v.name), 160, 120, labels);
  const std::vector<GtView> views = LoadGtViews(model, dir / "gt");
  ASSERT_EQ(views[0].surface_names, (std::vector<std::string>{"wall", "floor"}));
  EXPECT_EQ(views[0].surface, labels);
  InstallGtAsEstimates(dir.path(), scene);
  EvaluationOptions options;
  const DepthEvaluation e = EvaluateDepthMaps(dir.path(), dir / "gt", options);
  ASSERT_EQ(e.pooled_surfaces.size(), 2u);
  EXPECT_EQ(e.pooled_surfaces[0].num_gt + e.pooled_surfaces[1].num_gt, e.pooled.num_gt);
  EXPECT_DOUBLE_EQ(e.pooled_surfaces[1].at[0].f1, 1.0);
  // A label that surfaces.txt does not name, or labels of another size: errors naming the file.
  labels[5] = 3;
  WriteGrayPng(dir / ("gt/surface_" + scene.views[1].name), 160, 120, labels);
  try {
    LoadGtViews(model, dir / "gt");
    ADD_FAILURE() << "no error for label 3";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("surface_" + scene.views[1].name.substr(0, 7)), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("label 3"), std::string::npos) << error.what();
  }
  WriteGrayPng(dir / ("gt/surface_" + scene.views[1].name), 80, 60, std::vector<uint8_t>(80 * 60, 1));
  EXPECT_THROW(LoadGtViews(model, dir / "gt"), Error);
}

TEST(Evaluation, GtAgainstItselfIsPerfect) {
  test::TempDir dir;
  const SyntheticScene scene = GenerateSyntheticScene(TinyScene(), dir.path());
  InstallGtAsEstimates(dir.path(), scene);
  // gt_points.ply is every valid GT pixel back-projected, as a fused cloud would be.
  fs::copy_file(dir / "gt/gt_points.ply", dir / "fused.ply");
  EvaluationOptions options;
  const WorkspaceEvaluation e = EvaluateWorkspace(dir.path(), dir.path(), "", options);
  EXPECT_EQ(e.gt_dir, dir / "gt");
  ASSERT_EQ(e.depth.images.size(), 3u);
  ASSERT_TRUE(e.depth.has_masks);
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_DOUBLE_EQ(e.depth.pooled.at[k].f1, 1.0);
    EXPECT_DOUBLE_EQ(e.depth.pooled_untextured.at[k].f1, 1.0);
  }
  EXPECT_EQ(e.depth.pooled.num_gt, 3 * 160 * 120);
  EXPECT_GT(e.depth.pooled_untextured.num_gt, e.depth.pooled.num_gt / 3);
  ASSERT_TRUE(e.has_cloud);
  EXPECT_EQ(e.cloud.num_points, e.cloud.num_gt_points);
  EXPECT_EQ(e.cloud.num_observed, e.cloud.num_points);
  for (const CloudScoreAtTolerance& t : e.cloud.at) EXPECT_DOUBLE_EQ(t.f1, 1.0);

  // The printed table and the JSON carry the numbers.
  const std::string table = FormatScoreTable(e);
  EXPECT_NE(table.find("all pixels (pooled)"), std::string::npos);
  EXPECT_NE(table.find("100.0"), std::string::npos);
  const std::string json = EvaluationJson({e}, ReportContext{"test", "abc123"});
  EXPECT_NE(json.find("\"commit\": \"abc123\""), std::string::npos);
  EXPECT_NE(json.find("\"pooled_untextured\""), std::string::npos);
}

TEST(Evaluation, SparsePointsSayWhenTheGtDisagreesWithThePoses) {
  test::TempDir dir;
  const SyntheticScene scene = GenerateSyntheticScene(TinyScene(), dir.path());
  InstallGtAsEstimates(dir.path(), scene);
  EvaluationOptions options;
  // Exact GT: the sparse points (0.5 px of noise) lie on it.
  WorkspaceEvaluation e = EvaluateWorkspace(dir.path(), dir.path(), "none", options);
  ASSERT_GT(e.sparse_vs_gt.num_observations, 100);
  const double exact = e.sparse_vs_gt.median_rel_difference;
  EXPECT_LT(std::fabs(exact), 0.004);
  std::string table = FormatScoreTable(e);
  EXPECT_NE(table.find("Sparse points against the GT depth: " + std::to_string(e.sparse_vs_gt.num_observations) +
                      " observations"), std::string::npos) << table;
  EXPECT_EQ(table.find("warning"), std::string::npos) << table;

  // GT 6 % too far everywhere (a depth sensor at the wrong scale): the points lie 5.4 % in front.
  for (const SyntheticView& v : scene.views) {
    const std::string path = GtDepthPath(dir / "gt", v.name);
    PfmImage depth = ReadPfm(path);
    for (float& z : depth.data) z *= 1.06f;
    WritePfm(path, depth);
  }
  e = EvaluateWorkspace(dir.path(), dir.path(), "none", options);
  EXPECT_NEAR(e.sparse_vs_gt.median_rel_difference, (1 + exact) / 1.06 - 1, 0.001);
  EXPECT_NEAR(e.sparse_vs_gt.median_abs_rel_difference, 1 - (1 + exact) / 1.06, 0.001);
  table = FormatScoreTable(e);
  EXPECT_NE(table.find("median relative difference -5."), std::string::npos) << table;
  EXPECT_NE(table.find("warning: the GT depth and the model's poses disagree by at least half of the 1% tolerance"),
            std::string::npos) << table;
  // compare: the signed median per workspace, the warning once, no per-workspace line.
  const std::string comparison = FormatComparisonTable({e, e});
  const size_t warning = comparison.find("warning: the GT depth");
  ASSERT_NE(warning, std::string::npos) << comparison;
  EXPECT_EQ(comparison.find("warning", warning + 1), std::string::npos) << comparison;
  EXPECT_EQ(comparison.find("Sparse points against"), std::string::npos) << comparison;
  EXPECT_NE(comparison.find("sparse points vs GT (median)"), std::string::npos) << comparison;
  EXPECT_NE(comparison.find("-5."), std::string::npos) << comparison;
  const nlohmann::json json = nlohmann::json::parse(EvaluationJson({e}, ReportContext{"test", "abc"}));
  EXPECT_NEAR(json["workspaces"][0]["sparse_points_vs_gt"]["median_relative_difference"].get<double>(),
              e.sparse_vs_gt.median_rel_difference, 1e-12);
  // Tracks name images by id, which need not be 1..N.
  SparseModel model = ReadSparseModel(dir / "sparse");
  const std::vector<GtView> gt = LoadGtViews(model, dir / "gt");
  for (SparseImage& image : model.images) image.image_id += 100;
  for (SparsePoint3D& point : model.points) {
    for (SparseTrackElement& element : point.track) element.image_id += 100;
  }
  const SparseGtAgreement renumbered = CompareSparsePointsWithGt(model, gt);
  EXPECT_EQ(renumbered.num_observations, e.sparse_vs_gt.num_observations);
  EXPECT_DOUBLE_EQ(renumbered.median_rel_difference, e.sparse_vs_gt.median_rel_difference);
  // The warning's threshold: half of the tolerance.
  SparseGtAgreement half;
  half.num_observations = 1;
  half.median_rel_difference = -0.005;
  EXPECT_TRUE(GtDisagreesWithPoses(half, 0.01));
  half.median_rel_difference = 0.0049;
  EXPECT_FALSE(GtDisagreesWithPoses(half, 0.01));
  half.num_observations = 0;
  half.median_rel_difference = 0.5;
  EXPECT_FALSE(GtDisagreesWithPoses(half, 0.01));
  // At a tolerance of 20 % a 5.4 % disagreement is no reason to doubt the scores.
  options.depth_tolerances = {0.2};
  EXPECT_EQ(FormatScoreTable(EvaluateWorkspace(dir.path(), dir.path(), "none", options)).find("warning"),
            std::string::npos);
}

TEST(Evaluation, DepthMapsWrongByKnownFractionEndToEnd) {
  test::TempDir dir;
  const SyntheticScene scene = GenerateSyntheticScene(TinyScene(), dir.path());
  InstallGtAsEstimates(dir.path(), scene);
  // Image 0: every 4th pixel 5 % too far. Image 1: depth map deleted. Image 2: perfect.
  const std::string p0 = dir / ("stereo/depth_maps/" + scene.views[0].name + ".geometric.bin");
  FloatMap m = ReadFloatMap(p0, 1);
  for (size_t i = 0; i < m.data.size(); i += 4) m.data[i] *= 1.05f;
  WriteFloatMap(p0, m);
  fs::remove(dir / ("stereo/depth_maps/" + scene.views[1].name + ".geometric.bin"));
  EvaluationOptions options;
  const DepthEvaluation e = EvaluateDepthMaps(dir.path(), dir / "gt", options);
  ASSERT_EQ(e.images.size(), 3u);
  const int64_t n = 160 * 120;
  EXPECT_NEAR(e.images[0].all.at[0].accuracy, 0.75, 1e-12);
  EXPECT_NEAR(e.images[0].all.at[0].completeness, 0.75, 1e-12);
  EXPECT_FALSE(e.images[1].has_estimate);
  EXPECT_EQ(e.images[1].all.at[0].completeness, 0.0);
  EXPECT_DOUBLE_EQ(e.images[2].all.at[1].f1, 1.0);
  EXPECT_EQ(e.pooled.num_gt, 3 * n);
  EXPECT_EQ(e.pooled.num_estimated, 2 * n);
  EXPECT_NEAR(e.pooled.at[0].accuracy, 1.75 / 2, 1e-12);
  EXPECT_NEAR(e.pooled.at[0].completeness, 1.75 / 3, 1e-12);
}

TEST(Evaluation, PlyRoundTripAndAsciiReading) {
  test::TempDir dir;
  PlyPointCloud cloud;
  cloud.has_normals = cloud.has_colors = true;
  for (int i = 0; i < 5; ++i) {
    PlyPoint p;
    p.x = 0.5f * i;
    p.y = -1.25f * i;
    p.z = 3.f + i;
    p.nz = -1.f;
    p.r = static_cast<uint8_t>(10 * i);
    p.g = 200;
    p.b = 7;
    cloud.points.push_back(p);
  }
  WritePlyPointCloud(dir / "a.ply", cloud);
  const std::string header = test::ReadTextFile(dir / "a.ply").substr(0, 240);
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(header.find("property float nx"), std::string::npos);
  EXPECT_NE(header.find("property uchar red"), std::string::npos);
  const PlyPointCloud back = ReadPlyPointCloud(dir / "a.ply");
  ASSERT_EQ(back.points.size(), 5u);
  EXPECT_TRUE(back.has_normals && back.has_colors);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(back.points[i].x, cloud.points[i].x);
    EXPECT_EQ(back.points[i].y, cloud.points[i].y);
    EXPECT_EQ(back.points[i].z, cloud.points[i].z);
    EXPECT_EQ(back.points[i].nz, -1.f);
    EXPECT_EQ(back.points[i].r, cloud.points[i].r);
  }
  WriteFileAtomically(dir / "b.ply", [](std::ostream& out) {
    out << "ply\nformat ascii 1.0\ncomment hand-written\nelement vertex 2\nproperty double z\n"
           "property double x\nproperty double y\nproperty uchar intensity\nelement face 0\n"
           "property list uchar int vertex_indices\nend_header\n1 2 3 9\n4 5 6 9\n";
  });
  const PlyPointCloud ascii = ReadPlyPointCloud(dir / "b.ply");
  ASSERT_EQ(ascii.points.size(), 2u);
  EXPECT_EQ(ascii.points[1].x, 5.f);
  EXPECT_EQ(ascii.points[1].y, 6.f);
  EXPECT_EQ(ascii.points[1].z, 4.f);
  EXPECT_FALSE(ascii.has_normals);
  // A truncated binary body is an error naming the file.
  WriteFileAtomically(dir / "c.ply", [](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\n"
           "property float y\nproperty float z\nend_header\n0123456789";
  });
  try {
    ReadPlyPointCloud(dir / "c.ply");
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("c.ply"), std::string::npos);
  }
}

TEST(Evaluation, AgreementOfDepthMapsWithoutGt) {
  FloatMap a(10, 10, 1, 2.0f), b(10, 10, 1, 2.0f);
  for (int i = 0; i < 100; ++i) {
    if (i < 20) b.data[i] = 2.2f;       // disagree by ~10 %
    else if (i < 30) b.data[i] = 0.f;   // missing in b
    else if (i < 35) a.data[i] = 0.f;   // missing in a
  }
  const AgreementCounts c = CompareDepthMaps(a, b, 0.01);
  EXPECT_EQ(c.num_pixels, 100);
  EXPECT_EQ(c.num_a, 95);
  EXPECT_EQ(c.num_b, 90);
  EXPECT_EQ(c.num_both, 85);
  EXPECT_EQ(c.num_agree, 65);
  EXPECT_NEAR(c.AgreeShare(), 65.0 / 85, 1e-12);
}

TEST(Evaluation, EvaluateAndCompareCommands) {
  test::TempDir dir;
  const std::string ws_a = dir / "a", ws_b = dir / "b";
  const SyntheticScene scene = GenerateSyntheticScene(TinyScene(), ws_a);
  InstallGtAsEstimates(ws_a, scene);
  fs::copy(ws_a, ws_b, fs::copy_options::recursive);
  const std::string p = ws_b + "/stereo/depth_maps/" + scene.views[0].name + ".geometric.bin";
  FloatMap m = ReadFloatMap(p, 1);
  for (size_t i = 0; i < m.data.size() / 2; ++i) m.data[i] = 0;
  WriteFloatMap(p, m);

  EXPECT_EQ(RunEvaluateCommand({"--workspace_path", ws_a, "--output_path", dir / "eval",
                                "--commit", "test"}),
            0);
  EXPECT_TRUE(FileExists(dir / "eval/evaluation.json"));
  EXPECT_TRUE(FileExists(dir / "eval/view_00_eval.png"));
  const RgbImage panel = ReadRgbImage(dir / "eval/view_00_eval.png");
  EXPECT_GT(panel.width, 3 * 160);

  EXPECT_EQ(RunCompareCommand({"--workspace_paths", ws_a + "," + ws_b, "--gt_path", ws_a + "/gt",
                               "--labels", "perfect,half", "--output_path", dir / "cmp"}),
            0);
  EXPECT_NE(test::ReadTextFile(dir / "cmp/comparison.json").find("\"label\": \"half\""), std::string::npos);
  EXPECT_EQ(RunCompareCommand({"--workspace_paths", ws_a + "," + ws_b, "--output_path", dir / "agree"}), 0);
  const std::vector<PairAgreement> pairs = ComputeDepthAgreement({ws_a, ws_b}, "geometric", 0.01);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].images[0].counts.num_both, 160 * 120 / 2);
  EXPECT_EQ(pairs[0].images[0].counts.num_agree, 160 * 120 / 2);
  EXPECT_EQ(pairs[0].images[1].counts.num_agree, 160 * 120);

  // A fused cloud older than the maps it should show: a warning naming both.
  fs::copy_file(ws_a + "/gt/gt_points.ply", ws_a + "/fused.ply");
  const std::string map = ws_a + "/stereo/depth_maps/" + scene.views[1].name + ".geometric.bin";
  fs::last_write_time(map, fs::last_write_time(ws_a + "/fused.ply") + std::chrono::seconds(5));
  testing::internal::CaptureStderr();
  EXPECT_EQ(RunCompareCommand({"--workspace_paths", ws_a, "--gt_path", ws_a + "/gt"}), 0);
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_NE(warned.find(ws_a + "/fused.ply is older than " + map), std::string::npos) << warned;

  EXPECT_THROW(RunEvaluateCommand({"--workspace_path", dir / "nope"}), Error);
  EXPECT_THROW(RunGenerateSceneCommand({"--scene", "castle", "--output_path", dir / "x"}), Error);
}

// --depth_tolerances and --cloud_tolerances: maps 3 % too far are wrong at the default
// tolerances and right at 5 %; the cloud is scored at the distances asked for.
TEST(Evaluation, EvaluateScoresAtTheTolerancesGiven) {
  test::TempDir dir;
  const SyntheticScene scene = GenerateSyntheticScene(TinyScene(), dir.path());
  InstallGtAsEstimates(dir.path(), scene);
  for (const SyntheticView& v : scene.views) {
    const std::string p = dir / ("stereo/depth_maps/" + v.name + ".geometric.bin");
    FloatMap m = ReadFloatMap(p, 1);
    for (float& z : m.data) z *= 1.03f;
    WriteFloatMap(p, m);
  }
  fs::copy_file(dir / "gt/gt_points.ply", dir / "fused.ply");
  const auto scores = [&](const std::vector<std::string>& tolerances) {
    std::vector<std::string> args = {"--workspace_path", dir.path(), "--output_path", dir / "eval",
                                     "--pictures", "0"};
    args.insert(args.end(), tolerances.begin(), tolerances.end());
    EXPECT_EQ(RunEvaluateCommand(args), 0);
    return nlohmann::json::parse(test::ReadTextFile(dir / "eval/evaluation.json"))["workspaces"][0];
  };
  nlohmann::json w = scores({});
  ASSERT_EQ(w["depth"]["tolerances"], nlohmann::json({0.01, 0.02}));
  for (const auto& t : w["depth"]["pooled"]["tolerances"]) EXPECT_EQ(t["f1"], 0.0);
  ASSERT_EQ(w["point_cloud"]["tolerances"].size(), 2u);
  EXPECT_EQ(w["point_cloud"]["tolerances"][1]["relative_tolerance"], 0.01);

  w = scores({"--depth_tolerances", "0.01,0.05", "--cloud_tolerances", "0.005,0.02,0.05"});
  ASSERT_EQ(w["depth"]["tolerances"], nlohmann::json({0.01, 0.05}));
  const auto& depth = w["depth"]["pooled"]["tolerances"];
  ASSERT_EQ(depth.size(), 2u);
  EXPECT_EQ(depth[0]["f1"], 0.0);
  EXPECT_DOUBLE_EQ(depth[1]["f1"].get<double>(), 1.0);
  const auto& cloud = w["point_cloud"]["tolerances"];
  ASSERT_EQ(cloud.size(), 3u);
  const double median_depth = w["point_cloud"]["median_gt_depth"];
  EXPECT_EQ(cloud[2]["relative_tolerance"], 0.05);
  EXPECT_NEAR(cloud[2]["tolerance"].get<double>(), 0.05 * median_depth, 1e-9);
  EXPECT_DOUBLE_EQ(cloud[2]["f1"].get<double>(), 1.0);  // the GT cloud itself

  // The printed columns stay apart and aligned with names longer than "comp@1%".
  EvaluationOptions options;
  options.depth_tolerances = {0.005, 0.1};
  const std::string table = FormatScoreTable(EvaluateWorkspace(dir.path(), dir / "gt", "none", options));
  std::string header, pooled;
  std::istringstream lines(table);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("image ", 0) == 0) header = line;
    if (line.rfind("all pixels (pooled)", 0) == 0) pooled = line;
  }
  EXPECT_NE(header.find("  acc@0.5% comp@0.5%   F1@0.5%"), std::string::npos) << table;
  EXPECT_NE(header.find(" comp@10%"), std::string::npos) << table;
  EXPECT_EQ(header.size(), pooled.size()) << table;

  // A value out of range names the option.
  try {
    RunEvaluateCommand({"--workspace_path", dir.path(), "--cloud_tolerances", "0.01,5"});
    ADD_FAILURE() << "no error for a tolerance of 5";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "--cloud_tolerances: 5 is not in (0, 1)");
  }
}

}  // namespace
}  // namespace mpmvs

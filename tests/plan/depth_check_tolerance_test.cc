// The depth check's tolerance follows the sparse model's reprojection error
// (colmap_ext/plan/depth_check_tolerance.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/plan/depth_check_tolerance.h"
#include "colmap_ext/plan/reference_problems.h"
#include "tests/io_test_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

// Two 640x480 views with focal lengths fx, fy (after max_image_size scaling by `scale`) and
// sparse points whose reprojection errors (model pixels) are errors_px.
DenseWorkspace WorkspaceWithErrors(double fx, double fy, const std::vector<double>& errors_px, double scale = 1) {
  DenseWorkspace workspace;
  for (int i = 0; i < 2; ++i) {
    DenseView view;
    view.original_width = 640;
    view.original_height = 480;
    view.width = static_cast<int>(640 * scale);
    view.height = static_cast<int>(480 * scale);
    view.K[0] = fx * scale;
    view.K[4] = fy * scale;
    view.K[8] = 1;
    workspace.views.push_back(view);
  }
  for (size_t i = 0; i < errors_px.size(); ++i) {
    SparsePoint3D point;
    point.point3D_id = i + 1;
    point.error = errors_px[i];
    workspace.model.points.push_back(point);
  }
  return workspace;
}

TEST(DepthCheckTolerance, OnePercentWherePosesAreExact) {
  // 0.5 px at f = 500: 1 mrad, 0.5 % by the rule: the check keeps COLMAP's 1 %.
  const DepthCheckTolerance exact = DepthCheckToleranceOf(WorkspaceWithErrors(500, 500, {0.4, 0.6}));
  EXPECT_EQ(exact.relative, kDepthCheckBaseTolerance);
  EXPECT_NEAR(exact.mean_error_px, 0.5, 1e-12);
  EXPECT_NEAR(exact.mean_error_rad, 0.001, 1e-12);
}

TEST(DepthCheckTolerance, WiderWithTheMeanReprojectionErrorOverTheFocalLength) {
  // 2 px at fx = 400, fy = 600 (mean 500): 4 mrad, 2 %.
  const DepthCheckTolerance wide = DepthCheckToleranceOf(WorkspaceWithErrors(400, 600, {1.0, 3.0}));
  EXPECT_NEAR(wide.relative, 0.02, 1e-6);
  EXPECT_NEAR(wide.mean_error_rad, 0.004, 1e-12);
  // Twice the error at twice the focal length is the same angle.
  EXPECT_NEAR(DepthCheckToleranceOf(WorkspaceWithErrors(800, 1200, {2.0, 6.0})).relative, wide.relative, 1e-6);
  // The errors are in the model's pixels: max_image_size's scaling of the views changes nothing.
  EXPECT_NEAR(DepthCheckToleranceOf(WorkspaceWithErrors(400, 600, {1.0, 3.0}, 0.5)).relative, wide.relative, 1e-6);
  // At most 100 %: the check then keeps every depth a source holds.
  EXPECT_EQ(DepthCheckToleranceOf(WorkspaceWithErrors(500, 500, {1e6})).relative, 1.f);
}

TEST(DepthCheckTolerance, PointsWithoutAnErrorAreLeftOut) {
  // COLMAP writes -1 for a point without an error; inf and NaN are not errors either.
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double bad : {-1.0, inf, nan}) {
    EXPECT_NEAR(DepthCheckToleranceOf(WorkspaceWithErrors(500, 500, {2.0, bad})).relative, 0.02, 1e-6) << bad;
    EXPECT_EQ(DepthCheckToleranceOf(WorkspaceWithErrors(500, 500, {bad})).relative, kDepthCheckBaseTolerance)
        << bad;
  }
  EXPECT_EQ(DepthCheckToleranceOf(WorkspaceWithErrors(500, 500, {})).relative, kDepthCheckBaseTolerance);
}

// The reference problems of a workspace carry its model's tolerance.
TEST(DepthCheckTolerance, EveryReferenceProblemCarriesTheModelsTolerance) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp / "ws", 96, 72, 3);
  const std::string sparse = tmp / "ws/sparse";
  MpMvsWorkspaceIo io;
  const PatchMatchStereoOptions colmap_options;
  auto tolerances = [&]() {
    std::vector<float> out;
    const DenseWorkspace workspace = io.Load(tmp / "ws", -1);
    for (const ReferenceProblem& p : LoadReferenceProblems(workspace, "", colmap_options, 20).runnable) {
      out.push_back(p.depth_check_tolerance);
    }
    return out;
  };
  ASSERT_FALSE(ReadSparseModel(sparse).points.empty());
  const DenseWorkspace loaded = io.Load(tmp / "ws", -1);
  const DenseView& view = loaded.views[0];
  const double focal = 0.5 * (view.K[0] + view.K[4]);  // every view has the same camera
  test::SetSparsePointErrors(sparse, [](size_t) { return 0.1; });
  EXPECT_EQ(tolerances(), std::vector<float>(3, kDepthCheckBaseTolerance));
  // An error of 6 mrad: 3 %.
  test::SetSparsePointErrors(sparse, [=](size_t) { return 0.006 * focal; });
  const std::vector<float> wide = tolerances();
  ASSERT_EQ(wide.size(), 3u);
  for (float t : wide) EXPECT_NEAR(t, 0.03f, 1e-4f);
}

// An image's tolerance widens with the median difference within which its sources' maps hold
// its depths; differences of other surfaces (over 5 %) and pixels without one do not count.
TEST(DepthCheckTolerance, ImageToleranceFollowsTheMedianAgreement) {
  auto agreement = [](std::vector<std::pair<int, float>> runs, float model_tolerance) {
    std::vector<float> differences;
    for (const auto& [count, difference] : runs) differences.insert(differences.end(), count, difference);
    return ImageAgreementOf(differences, model_tolerance);
  };
  const float none = std::numeric_limits<float>::max();
  // Sharp: 0.04 % is 0.6 % by the rule, so the model's 1 % stays.
  const ImageAgreement sharp = agreement({{60, 0.0004f}, {30, 0.02f}, {10, none}}, kDepthCheckBaseTolerance);
  EXPECT_FLOAT_EQ(sharp.median_difference, 0.0004f);
  EXPECT_FLOAT_EQ(sharp.tolerance, kDepthCheckBaseTolerance);
  // Rough: 0.2 % is 3 %, even where most pixels' differences are occlusions (over 5 %).
  const ImageAgreement rough = agreement({{30, 0.002f}, {20, 0.001f}, {100, 0.2f}, {50, none}}, 0.01f);
  EXPECT_FLOAT_EQ(rough.median_difference, 0.002f);
  EXPECT_NEAR(rough.tolerance, 0.03f, 1e-6f);
  // At most 5 %; a model tolerance above that stays.
  EXPECT_FLOAT_EQ(agreement({{10, 0.01f}}, 0.01f).tolerance, kAgreementMaxDifference);
  EXPECT_FLOAT_EQ(agreement({{10, 0.01f}}, 0.08f).tolerance, 0.08f);
  // No pixel a source holds: the model's tolerance.
  const ImageAgreement empty = agreement({{10, none}, {5, 0.3f}}, 0.012f);
  EXPECT_FLOAT_EQ(empty.tolerance, 0.012f);
  EXPECT_EQ(empty.median_difference, 0.f);
}

}  // namespace
}  // namespace mpmvs

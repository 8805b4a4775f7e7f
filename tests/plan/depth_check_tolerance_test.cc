// The depth check's tolerance follows the sparse model's reprojection error
// (colmap_ext/plan/depth_check_tolerance.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/plan/depth_check_tolerance.h"
#include "colmap_ext/plan/reference_problems.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

// Two images of one camera and points whose reprojection errors are errors_px.
SparseModel ModelWithErrors(int model_id, std::vector<double> params, const std::vector<double>& errors_px) {
  SparseModel model;
  SparseCamera camera;
  camera.camera_id = 1;
  camera.model_id = model_id;
  camera.width = 640;
  camera.height = 480;
  camera.params = std::move(params);
  model.cameras.push_back(camera);
  for (uint32_t id : {1u, 2u}) {
    SparseImage image;
    image.image_id = id;
    image.camera_id = 1;
    image.name = "view_" + std::to_string(id) + ".png";
    model.images.push_back(image);
  }
  for (size_t i = 0; i < errors_px.size(); ++i) {
    SparsePoint3D point;
    point.point3D_id = i + 1;
    point.error = errors_px[i];
    model.points.push_back(point);
  }
  return model;
}

TEST(DepthCheckTolerance, OnePercentWherePosesAreExact) {
  // 0.5 px at f = 500: 1 mrad, 0.5 % by the rule: the check keeps COLMAP's 1 %.
  const DepthCheckTolerance exact =
      DepthCheckToleranceOf(ModelWithErrors(kPinholeModelId, {500, 500, 320, 240}, {0.4, 0.6}));
  EXPECT_EQ(exact.relative, kDepthCheckBaseTolerance);
  EXPECT_NEAR(exact.mean_error_px, 0.5, 1e-12);
  EXPECT_NEAR(exact.mean_error_rad, 0.001, 1e-12);
}

TEST(DepthCheckTolerance, WiderWithTheMeanReprojectionErrorOverTheFocalLength) {
  // 2 px at fx = 400, fy = 600 (mean 500): 4 mrad, 2 %.
  const DepthCheckTolerance pinhole =
      DepthCheckToleranceOf(ModelWithErrors(kPinholeModelId, {400, 600, 320, 240}, {1.0, 3.0}));
  EXPECT_NEAR(pinhole.relative, 0.02, 1e-6);
  EXPECT_NEAR(pinhole.mean_error_rad, 0.004, 1e-12);
  // SIMPLE_PINHOLE's one focal length: 3 px at f = 500, 3 %.
  const DepthCheckTolerance simple =
      DepthCheckToleranceOf(ModelWithErrors(kSimplePinholeModelId, {500, 320, 240}, {3.0}));
  EXPECT_NEAR(simple.relative, 0.03, 1e-6);
  // Twice the error at twice the focal length is the same angle.
  EXPECT_NEAR(DepthCheckToleranceOf(ModelWithErrors(kSimplePinholeModelId, {1000, 320, 240}, {6.0})).relative,
              simple.relative, 1e-6);
}

TEST(DepthCheckTolerance, OnePercentWithoutPointsOrWithUnreadableErrors) {
  EXPECT_EQ(DepthCheckToleranceOf(ModelWithErrors(kPinholeModelId, {500, 500, 320, 240}, {})).relative,
            kDepthCheckBaseTolerance);
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double bad : {inf, nan, -5.0}) {
    EXPECT_EQ(DepthCheckToleranceOf(ModelWithErrors(kPinholeModelId, {500, 500, 320, 240}, {1.0, bad})).relative,
              kDepthCheckBaseTolerance)
        << bad;
  }
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
  SparseModel model = ReadSparseModel(sparse);
  ASSERT_FALSE(model.points.empty());
  ASSERT_FALSE(model.cameras.empty());
  const double focal = model.cameras[0].params[0];
  for (SparsePoint3D& point : model.points) point.error = 0.1;
  WriteSparseModelBinary(model, sparse);
  EXPECT_EQ(tolerances(), std::vector<float>(3, kDepthCheckBaseTolerance));
  // An error of 6 mrad: 3 %.
  for (SparsePoint3D& point : model.points) point.error = 0.006 * focal;
  WriteSparseModelBinary(model, sparse);
  const std::vector<float> wide = tolerances();
  ASSERT_EQ(wide.size(), 3u);
  for (float t : wide) EXPECT_NEAR(t, 0.03f, 1e-4f);
}

}  // namespace
}  // namespace mpmvs

// mPM's larger windows at half resolution (kernels/half_resolution.h): the halved images and
// cameras, the upsampled planes, the schedules it accepts, and a run on the tilted plane.
#include "kernels/half_resolution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/kernel_schedule_util.h"
#include "tests/plane_scene_util.h"

namespace mpmvs {
namespace kernels {
namespace {

TEST(HalfResolution, HalvedImageIsTheMeanOfEachTwoByTwoBlock) {
  // 5x3: the odd last column and row are dropped.
  const std::vector<float> grey = {10, 20, 30, 41, 99,  //
                                   10, 20, 30, 40, 99,  //
                                   99, 99, 99, 99, 99};
  const std::vector<float> half = HalveImage(ImageView{grey.data(), 5, 3});
  ASSERT_EQ(half.size(), 2u);
  EXPECT_EQ(half[0], 15.f);
  EXPECT_EQ(half[1], 35.f);  // 35.25, rounded: an 8-bit image stays integral
  const std::vector<float> fractional = {0.5f, 1.f, 1.f, 1.f};
  EXPECT_FLOAT_EQ(HalveImage(ImageView{fractional.data(), 2, 2})[0], 0.875f);
  const std::vector<float> chroma = {1, 2, 3, 4, 5, 6, 7, 8};  // 2x2 pixels, 2 channels
  const std::vector<float> half_chroma = HalveChroma(chroma.data(), 2, 2);
  ASSERT_EQ(half_chroma.size(), 2u);
  EXPECT_FLOAT_EQ(half_chroma[0], 4.f);
  EXPECT_FLOAT_EQ(half_chroma[1], 5.f);
  EXPECT_THROW(HalveImage(ImageView{grey.data(), 5, 1}), std::invalid_argument);
}

TEST(HalfResolution, HalvedCameraSeesEachPointAtTheCentreOfItsBlock) {
  const Camera full = test::LookAtCamera(161, 121, 0.9f, Vec3{0.f, 0.f, 0.f}, Vec3{0.2f, 0.1f, 4.f},
                                         Vec3{0.f, 1.f, 0.f});
  const Camera half = HalveCamera(full);
  EXPECT_EQ(half.width, 80);
  EXPECT_EQ(half.height, 60);
  for (const Vec3 X : {Vec3{0.3f, -0.2f, 4.f}, Vec3{-1.f, 0.7f, 6.f}}) {
    float u, v, hu, hv;
    ASSERT_TRUE(ProjectCameraPoint(full, X, &u, &v));
    ASSERT_TRUE(ProjectCameraPoint(half, X, &hu, &hv));
    // Full-resolution pixels 2i and 2i+1 average into pixel i, centred at 2i + 0.5.
    EXPECT_NEAR(2.f * hu + 0.5f, u, 1e-3f);
    EXPECT_NEAR(2.f * hv + 0.5f, v, 1e-3f);
  }
}

TEST(HalfResolution, EachPixelStartsFromThePlaneOfTheHalfResolutionPixelCoveringIt) {
  PatchMatchResult half;
  ResetResult(2, 2, &half);
  for (int i = 0; i < 4; ++i) {
    StorePlane(half.plane.data(), i, Plane{Vec3{0.f, 0.f, -1.f}, static_cast<float>(i + 1)});
    half.photo_cost[i] = 0.1f * i;
  }
  half.photo_cost[3] = kInvalidCost;  // no estimate: none upsampled
  std::vector<float> plane, cost;
  UpsampleHalfResolutionResult(half, 5, 4, &plane, &cost);  // odd width: the last column clamps
  ASSERT_EQ(plane.size(), 4u * 20);
  ASSERT_EQ(cost.size(), 20u);
  auto d = [&](int u, int v) { return LoadPlane(plane.data(), v * 5 + u).d; };
  EXPECT_EQ(d(0, 0), 1.f);
  EXPECT_EQ(d(1, 1), 1.f);
  EXPECT_EQ(d(2, 0), 2.f);
  EXPECT_EQ(d(4, 1), 2.f);
  EXPECT_EQ(d(1, 2), 3.f);
  EXPECT_EQ(d(3, 3), 0.f);
  EXPECT_EQ(cost[3 * 5 + 3], kInvalidCost);
  EXPECT_FLOAT_EQ(cost[2 * 5 + 0], 0.2f);
}

TEST(HalfResolution, SchedulesWithHalfResolutionIterationsAreChecked) {
  PatchMatchSchedule s = mpmvs::test::ScheduleWithOptionDefaults();
  s.iterations = {{0, 0, true}, {0, 0, false}};
  EXPECT_NO_THROW(s.Check());
  EXPECT_TRUE(HasHalfResolutionIterations(s));
  s.iterations = {{0, 0, false}, {0, 0, true}};  // not a prefix
  EXPECT_THROW(s.Check(), std::invalid_argument);
  s.iterations = {{0, 0, true}};  // nothing at full resolution
  EXPECT_THROW(s.Check(), std::invalid_argument);
  s.iterations = {{1, 0, true}, {0, 0, true}, {0, 0, false}};
  EXPECT_EQ(FirstFullResolutionScale(s), 2);  // a 21 px window at half resolution: the 41 px one
  EXPECT_DOUBLE_EQ(IterationWork(s), 1.5);     // a quarter of the pixels each
  s.iterations = {{1, 0, false}, {0, 0, false}};
  EXPECT_EQ(FirstFullResolutionScale(s), 1);
  s.iterations = {{0, 0, true}, {0, 0, false}};
  s.geometric = true;
  EXPECT_THROW(s.Check(), std::invalid_argument);
}

float Texture(float a, float b) {
  return 128.f + 40.f * std::sin(5.f * a) * std::cos(4.f * b) + 30.f * std::sin(12.f * a + 9.f * b) +
         20.f * std::cos(21.f * b - 16.f * a);
}

// Share of the pixels inside a margin whose depth is within 0.5 % of the plane's.
double DepthWithinHalfPercent(const test::PlaneScene& scene, const PatchMatchProblem& problem,
                              const PatchMatchResult& result) {
  std::vector<float> depth, normal;
  ExtractDepthNormalMaps(problem, result, &depth, &normal);
  const int W = problem.ref_camera.width, H = problem.ref_camera.height;
  int good = 0, all = 0;
  for (int v = 16; v < H - 16; ++v) {
    for (int u = 16; u < W - 16; ++u) {
      const float z = test::PlaneSceneDepth(scene, scene.cameras[0], u, v);
      ++all;
      if (std::abs(depth[static_cast<size_t>(v) * W + u] - z) < 0.005f * z) ++good;
    }
  }
  return static_cast<double>(good) / all;
}

TEST(HalfResolution, StartAtHalfResolutionRecoversThePlaneForLessWork) {
  test::PlaneScene scene;
  scene.plane_point = Vec3{0.f, 0.f, 4.f};
  scene.plane_normal = Normalize(Vec3{0.3f, -0.4f, -1.f});
  const Vec3 centres[3] = {{0.f, 0.f, 0.f}, {0.45f, 0.1f, 0.1f}, {-0.3f, -0.4f, 0.05f}};
  for (const Vec3& c : centres) {
    scene.cameras.push_back(test::LookAtCamera(160, 120, 0.9f, c, scene.plane_point, Vec3{0.f, 1.f, 0.f}));
  }
  test::RenderPlaneScene(Texture, 1.f, 3, &scene);
  PatchMatchProblem problem = test::MakePlaneSceneProblem(scene, 2.f, 8.f);
  for (std::vector<float>& image : scene.images) {
    for (float& g : image) g = std::nearbyint(g);  // 8-bit, as images read from disk
  }
  PatchMatchSchedule full = mpmvs::test::ScheduleWithOptionDefaults();
  full.seed = 7;
  full.iterations = {{1, 0}, {1, 1}, {0, 0}, {0, 1}};
  PatchMatchSchedule half = full;
  half.iterations = {{0, 0, true}, {0, 1, true}, {0, 0}, {0, 1}};
  EXPECT_THROW(
      {
        PatchMatchResult r;
        RunPatchMatchCpu(problem, half, &r);
      },
      std::invalid_argument);  // only through RunWithHalfResolutionStart

  PatchMatchResult full_result, half_result;
  RunPatchMatchCpu(problem, full, &full_result);
  int runs = 0, half_runs = 0;
  RunWithHalfResolutionStart(
      problem, half,
      [&](const PatchMatchProblem& p, const PatchMatchSchedule& s, PatchMatchResult* r, const ProgressCallback& pr,
          bool last) {
        ++runs;
        if (!last) {
          ++half_runs;
          EXPECT_EQ(p.ref_camera.width, 80);
          EXPECT_EQ(s.iterations.size(), 2u);
          EXPECT_FALSE(s.iterations.front().half_resolution);
        } else {
          EXPECT_NE(p.init_plane, nullptr);
        }
        RunPatchMatchCpu(p, s, r, pr);
      },
      &half_result);
  EXPECT_EQ(runs, 2);
  EXPECT_EQ(half_runs, 1);
  ASSERT_EQ(half_result.width, 160);
  ASSERT_EQ(half_result.iterations.size(), 4u);
  // The run statistics say which iterations ran at half resolution.
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(half_result.iterations[i].half_resolution, i < 2) << i;

  const double full_good = DepthWithinHalfPercent(scene, problem, full_result);
  const double half_good = DepthWithinHalfPercent(scene, problem, half_result);
  std::printf("tilted plane, depth within 0.5%%: %.3f at full resolution, %.3f with a half-resolution start\n",
              full_good, half_good);
  EXPECT_GE(half_good, 0.95);
  EXPECT_GE(half_good, full_good - 0.01);
  auto nccs = [](const PatchMatchResult& r) {
    uint64_t n = r.init_ncc_evaluations;
    for (const IterationStats& it : r.iterations) n += it.ncc_evaluations;
    return n;
  };
  // The two larger-window iterations cost a quarter: about 5/8 of the NCCs in all.
  EXPECT_LT(nccs(half_result), 0.75 * nccs(full_result));
}

}  // namespace
}  // namespace kernels
}  // namespace mpmvs

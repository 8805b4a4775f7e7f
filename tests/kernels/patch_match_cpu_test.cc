// The CPU PatchMatch engine on an analytic scene rendered inside the test: a textured plane
// tilted against every camera, seen by cameras rotated about several axes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "tests/kernel_schedule_util.h"
#include "kernels/median_filter.h"
#include "kernels/patch_match.h"
#include "tests/plane_scene_util.h"

namespace mpmvs {
namespace kernels {
namespace {

using test::PlaneScene;
using test::PlaneSceneDepth;

float Texture(float a, float b) {
  // Multi-scale smooth texture on plane coordinates (metres).
  return 128.f + 40.f * std::sin(5.f * a) * std::cos(4.f * b) + 30.f * std::sin(12.f * a + 9.f * b) +
         20.f * std::cos(21.f * b - 16.f * a) + 15.f * std::sin(33.f * a) * std::sin(29.f * b);
}

// A plane tilted ~40 degrees, seen by three cameras rotated about several axes.
PlaneScene MakeScene(int W, int H, float noise_sigma) {
  PlaneScene scene;
  scene.plane_point = Vec3{0.f, 0.f, 4.f};
  scene.plane_normal = Normalize(Vec3{0.45f, -0.5f, -1.f});
  const Vec3 centres[3] = {{0.f, 0.f, 0.f}, {0.5f, 0.1f, 0.1f}, {-0.3f, -0.45f, 0.05f}};
  const Vec3 ups[3] = {{0.f, 1.f, 0.f}, {0.2f, 1.f, 0.1f}, {-0.25f, 1.f, 0.f}};
  for (int c = 0; c < 3; ++c) {
    scene.cameras.push_back(test::LookAtCamera(
        W, H, 0.9f, centres[c], scene.plane_point + Vec3{0.1f * c, -0.05f * c, 0.f}, ups[c]));
  }
  test::RenderPlaneScene(Texture, noise_sigma, 5, &scene);
  return scene;
}

PatchMatchProblem MakeProblem(const PlaneScene& scene) { return test::MakePlaneSceneProblem(scene, 2.f, 8.f); }

// NCCs of a run's iterations (the initialisation left out).
uint64_t IterationNccs(const PatchMatchResult& result) {
  uint64_t n = 0;
  for (const IterationStats& it : result.iterations) n += it.ncc_evaluations;
  return n;
}

PatchMatchSchedule MultiScaleSchedule(int max_scale, int per_scale) {
  PatchMatchSchedule schedule = mpmvs::test::ScheduleWithOptionDefaults();
  for (int s = max_scale; s >= 0; --s) {
    for (int t = 0; t < per_scale; ++t) schedule.iterations.push_back({s, t});
  }
  schedule.seed = 42;
  return schedule;
}

struct PlaneRecovery {
  int considered = 0;   // pixels seen by at least one source view
  double depth_ratio = 0;   // of them, depth within 0.5 %
  double normal_ratio = 0;  // normal within 5 degrees
};

PlaneRecovery MeasureRecovery(const PlaneScene& scene, const PatchMatchProblem& problem,
                              const PatchMatchResult& result) {
  const int W = problem.ref_camera.width, H = problem.ref_camera.height;
  std::vector<float> depth, normal;
  ExtractDepthNormalMaps(problem, result, &depth, &normal);
  const Vec3 n_gt = MatVec(scene.cameras[0].R, scene.plane_normal);
  int considered = 0, good_depth = 0, good_normal = 0;
  for (int v = 12; v < H - 12; ++v) {
    for (int u = 12; u < W - 12; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      // Only pixels seen by at least one source view.
      const float z = PlaneSceneDepth(scene, scene.cameras[0], u, v);
      bool seen = false;
      for (int s = 1; s < static_cast<int>(scene.cameras.size()); ++s) {
        const Vec3 Xw = MatTVec(scene.cameras[0].R, z * PixelRay(scene.cameras[0], u, v) -
                                                        Vec3{scene.cameras[0].t[0], scene.cameras[0].t[1], scene.cameras[0].t[2]});
        const Camera& c = scene.cameras[s];
        float us, vs;
        if (ProjectCameraPoint(c, MatVec(c.R, Xw) + Vec3{c.t[0], c.t[1], c.t[2]}, &us, &vs) &&
            us > 5 && vs > 5 && us < W - 6 && vs < H - 6)
          seen = true;
      }
      if (!seen) continue;
      ++considered;
      if (std::abs(depth[i] - z) / z < 0.005f) ++good_depth;
      const Vec3 n{normal[i], normal[W * H + i], normal[2 * W * H + i]};
      if (Dot(n, n_gt) > std::cos(5.f * kPi / 180.f)) ++good_normal;
    }
  }
  PlaneRecovery r;
  r.considered = considered;
  r.depth_ratio = considered > 0 ? double(good_depth) / considered : 0.0;
  r.normal_ratio = considered > 0 ? double(good_normal) / considered : 0.0;
  return r;
}

TEST(PatchMatchCpu, TiltedTexturedPlaneIsRecovered) {
  const int W = 160, H = 120;
  const PlaneScene scene = MakeScene(W, H, 2.f);
  const PatchMatchProblem problem = MakeProblem(scene);
  PatchMatchResult result;
  RunPatchMatchCpu(problem, MultiScaleSchedule(2, 3), &result);
  const PlaneRecovery recovery = MeasureRecovery(scene, problem, result);
  const int considered = recovery.considered;
  const double depth_ratio = recovery.depth_ratio, normal_ratio = recovery.normal_ratio;
  ASSERT_GT(considered, W * H / 3);
  RecordProperty("depth_within_0.5pct", std::to_string(depth_ratio));
  std::printf("tilted plane: %.2f%% depth within 0.5%%, %.2f%% normals within 5 deg (%d px)\n",
              100 * depth_ratio, 100 * normal_ratio, considered);
  // Photometric stage alone, no median filter, on a small noisy scene: 97.2 % depths and
  // 95.2 % normals with sigma_c 2.5 (98.2 % / 96.8 % with ACMH's 3, kernels/DESIGN.md item
  // 11). Issue 4's 98 % / 98 % is held on the full pipeline in pipeline_test.cc.
  EXPECT_GE(depth_ratio, 0.965);
  EXPECT_GE(normal_ratio, 0.94);
  // Run statistics: 9 iterations, window sides 41, 41, 41, 21, ..., 11.
  ASSERT_EQ(result.iterations.size(), 9u);
  EXPECT_EQ(result.iterations[0].window_side, 41);
  EXPECT_EQ(result.iterations[3].window_side, 21);
  EXPECT_EQ(result.iterations[8].window_side, 11);
  EXPECT_FLOAT_EQ(result.iterations[3].tau, 0.8f);  // tau restarts per scale
}

TEST(PatchMatchCpu, DeterministicAcrossThreadCounts) {
  const int W = 64, H = 48;
  const PlaneScene scene = MakeScene(W, H, 1.f);
  const PatchMatchProblem problem = MakeProblem(scene);
  uint64_t nccs_without_skips = 0;
  for (int skips : {0, 2}) {
    PatchMatchSchedule schedule = MultiScaleSchedule(1, 2);
    schedule.settled_skips = skips;
    PatchMatchResult a, b;
    schedule.num_threads = 1;
    RunPatchMatchCpu(problem, schedule, &a);
    schedule.num_threads = 2;
    RunPatchMatchCpu(problem, schedule, &b);
    EXPECT_EQ(a.plane, b.plane) << "settled skips " << skips;
    EXPECT_EQ(a.cost, b.cost) << "settled skips " << skips;
    const uint64_t nccs = IterationNccs(a);
    if (skips == 0) nccs_without_skips = nccs;
    else EXPECT_LT(nccs, nccs_without_skips) << "the skipping run must skip";
    schedule.seed = 43;
    PatchMatchResult c;
    RunPatchMatchCpu(problem, schedule, &c);
    EXPECT_NE(a.plane, c.plane) << "settled skips " << skips;
  }
}

// The plane of MakeScene seen by the reference and `num_sources` cameras around it.
PlaneScene MakeManyViewScene(int W, int H, int num_sources) {
  PlaneScene scene;
  scene.plane_point = Vec3{0.f, 0.f, 4.f};
  scene.plane_normal = Normalize(Vec3{0.45f, -0.5f, -1.f});
  scene.cameras.push_back(test::LookAtCamera(W, H, 0.9f, Vec3{0.f, 0.f, 0.f}, scene.plane_point, Vec3{0.f, 1.f, 0.f}));
  for (int c = 0; c < num_sources; ++c) {
    const float a = 2.f * kPi * c / num_sources;
    const Vec3 centre{0.5f * std::cos(a), 0.4f * std::sin(a), 0.05f * c};
    scene.cameras.push_back(test::LookAtCamera(W, H, 0.9f, centre, scene.plane_point + Vec3{0.05f * c, 0.f, 0.f},
                                               Vec3{0.1f * std::sin(a), 1.f, 0.f}));
  }
  test::RenderPlaneScene(Texture, 2.f, 5, &scene);
  return scene;
}

// With costed_views = M below the number of sources, the propagated candidates are costed in
// M views, so the cost per update stops growing with the sources; the plane is still found
// (on this small scene after 6 photometric iterations: 96.8 % of the depths within 0.5 %
// against 99.4 % with every view), and the result still does not depend on the thread count.
TEST(PatchMatchCpu, CostedViewsBoundTheWorkPerUpdateAndKeepThePlane) {
  const int W = 128, H = 96;
  const PlaneScene scene = MakeManyViewScene(W, H, 6);
  const PatchMatchProblem problem = MakeProblem(scene);
  ASSERT_EQ(problem.sources.size(), 6u);
  PatchMatchSchedule schedule = MultiScaleSchedule(1, 3);
  PatchMatchResult all, three, three_one_thread;
  RunPatchMatchCpu(problem, schedule, &all);
  schedule.costed_views = 3;
  RunPatchMatchCpu(problem, schedule, &three);
  schedule.num_threads = 1;
  RunPatchMatchCpu(problem, schedule, &three_one_thread);
  EXPECT_EQ(three.plane, three_one_thread.plane);
  const PlaneRecovery a = MeasureRecovery(scene, problem, all);
  const PlaneRecovery b = MeasureRecovery(scene, problem, three);
  std::printf("6 sources, candidates costed in all views: %llu NCCs, %.2f%% depths; in 3: %llu NCCs, %.2f%%\n",
              static_cast<unsigned long long>(IterationNccs(all)), 100 * a.depth_ratio,
              static_cast<unsigned long long>(IterationNccs(three)), 100 * b.depth_ratio);
  EXPECT_LT(IterationNccs(three), 0.65 * IterationNccs(all));
  EXPECT_GE(b.depth_ratio, a.depth_ratio - 0.03);
  EXPECT_GE(b.depth_ratio, 0.95);
  // The initialisation costs every view either way.
  EXPECT_EQ(three.init_ncc_evaluations, all.init_ncc_evaluations);
}

TEST(CostedViews, MostSelectedNearbyFirstThenOneExploredInTurn) {
  PassParams params;
  params.num_sources = 8;
  const uint32_t masks[4] = {0b00000110, 0b00000100, 0b00010100, 0b00000010};
  // Every view with M = 0 or with no more sources than M.
  EXPECT_EQ(CostedViews(params, masks, 4, 0b1, 0), 0xffu);
  params.costed_views = 8;
  EXPECT_EQ(CostedViews(params, masks, 4, 0b1, 0), 0xffu);
  params.costed_views = 3;
  std::vector<int> explored(8, 0);
  for (int idx = 0; idx < 64; ++idx) {
    for (uint32_t it = 0; it < 4; ++it) {
      params.iteration = it;
      const uint32_t costed = CostedViews(params, masks, 4, 0b100, idx);
      EXPECT_EQ(__builtin_popcount(costed), 3);
      // View 2: own mask (2 votes) and three neighbours; view 1: two neighbours.
      EXPECT_EQ(costed & 0b110u, 0b110u) << idx;
      const uint32_t rest = costed & ~0b110u;
      ASSERT_EQ(__builtin_popcount(rest), 1);
      ++explored[__builtin_ctz(rest)];
    }
  }
  // The explored view turns over all the others.
  for (int s : {0, 3, 4, 5, 6, 7}) EXPECT_GT(explored[s], 0) << s;
}

TEST(SettledPlane, DepthWithinHalfAPercentAndNormalWithinThreeDegrees) {
  const Vec3 ray = Normalize(Vec3{0.1f, -0.2f, 1.f});
  const Vec3 n = Normalize(Vec3{0.2f, 0.1f, -1.f});
  const Plane before = PlaneFromDepthNormal(ray, 4.f, n);
  EXPECT_TRUE(SettledPlane(before, before, ray));
  EXPECT_TRUE(SettledPlane(before, PlaneFromDepthNormal(ray, 4.f * 1.0049f, n), ray));
  EXPECT_TRUE(SettledPlane(before, PlaneFromDepthNormal(ray, 4.f * 0.9951f, n), ray));
  EXPECT_FALSE(SettledPlane(before, PlaneFromDepthNormal(ray, 4.f * 1.0051f, n), ray));
  EXPECT_FALSE(SettledPlane(before, PlaneFromDepthNormal(ray, 4.f * 0.9949f, n), ray));
  // The normal turned about an axis perpendicular to it.
  const Vec3 axis = Normalize(Cross(n, Vec3{1.f, 0.f, 0.f}));
  auto turned = [&](float degrees) {
    const float a = degrees * kPi / 180.f;
    return Normalize(std::cos(a) * n + std::sin(a) * Cross(axis, n));
  };
  EXPECT_TRUE(SettledPlane(before, PlaneFromDepthNormal(ray, 4.f, turned(2.9f)), ray));
  EXPECT_FALSE(SettledPlane(before, PlaneFromDepthNormal(ray, 4.f, turned(3.1f)), ray));
}

// Settled pixels skip updates (kernels/DESIGN.md 27): fewer NCCs, the same plane recovered.
TEST(PatchMatchCpu, SettledPixelsSkipUpdatesWithoutLosingThePlane) {
  const int W = 160, H = 120;
  const PlaneScene scene = MakeScene(W, H, 2.f);
  const PatchMatchProblem problem = MakeProblem(scene);
  PatchMatchSchedule schedule = MultiScaleSchedule(2, 3);
  PatchMatchResult every, skipping;
  RunPatchMatchCpu(problem, schedule, &every);
  schedule.settled_skips = 2;
  RunPatchMatchCpu(problem, schedule, &skipping);
  const PlaneRecovery a = MeasureRecovery(scene, problem, every);
  const PlaneRecovery b = MeasureRecovery(scene, problem, skipping);
  std::printf("every pixel in every pass: %llu NCCs, %.2f%% depths; settled pixels skip 2: %llu NCCs, %.2f%%\n",
              static_cast<unsigned long long>(IterationNccs(every)), 100 * a.depth_ratio,
              static_cast<unsigned long long>(IterationNccs(skipping)), 100 * b.depth_ratio);
  EXPECT_LT(IterationNccs(skipping), 0.8 * IterationNccs(every));
  EXPECT_GE(b.depth_ratio, a.depth_ratio - 0.005);
  EXPECT_GE(b.normal_ratio, a.normal_ratio - 0.01);
  // The first iteration updates every pixel: nothing has settled before it.
  EXPECT_EQ(skipping.iterations[0].ncc_evaluations, every.iterations[0].ncc_evaluations);
}

// Skips never cross into a new window scale: its first iteration updates every pixel (the
// stored costs are the larger window's), however many skips a pixel had left.
TEST(PatchMatchCpu, ANewWindowScaleUpdatesEveryPixel) {
  const int W = 96, H = 72;
  const PlaneScene scene = MakeScene(W, H, 2.f);
  const PatchMatchProblem problem = MakeProblem(scene);
  PatchMatchSchedule schedule = MultiScaleSchedule(1, 3);  // scale 1 three times, then 0
  PatchMatchResult every, skipping;
  RunPatchMatchCpu(problem, schedule, &every);
  schedule.settled_skips = 255;  // a settled pixel would sit out every later pass
  RunPatchMatchCpu(problem, schedule, &skipping);
  auto ratio = [&](int it) {
    return static_cast<double>(skipping.iterations[it].ncc_evaluations) /
           static_cast<double>(every.iterations[it].ncc_evaluations);
  };
  std::printf("NCCs with skips / without, iterations 0-5: %.2f %.2f %.2f %.2f %.2f %.2f\n", ratio(0),
              ratio(1), ratio(2), ratio(3), ratio(4), ratio(5));
  // Measured: 1.00 0.99 0.89 1.00 0.66 0.14. Without the clear at the new scale, the pixels
  // that sat out iteration 2 would sit out iteration 3 as well.
  EXPECT_LT(ratio(2), 0.95);  // pixels settled at scale 1 sit out its last iteration
  EXPECT_GT(ratio(3), 0.97);  // and all come back at scale 0
  EXPECT_LT(ratio(5), 0.5);
}

// A 24x20 result whose every pixel holds the same slanted plane, with costs 0.5.
PatchMatchResult SlantedPlaneResult(const Camera& cam, const Plane& plane) {
  PatchMatchResult r;
  ResetResult(cam.width, cam.height, &r);
  for (int i = 0; i < cam.width * cam.height; ++i) {
    StorePlane(r.plane.data(), i, plane);
    r.cost[i] = 0.5f;
    r.photo_cost[i] = 0.5f;
  }
  return r;
}

float DepthAt(const PatchMatchResult& r, const Camera& cam, int u, int v) {
  return PlaneDepth(LoadPlane(r.plane.data(), v * cam.width + u), PixelRay(cam, float(u), float(v)));
}

TEST(MedianFilterDepthsCpu, KeepsSlantedPlaneAndRemovesOutliers) {
  Camera cam;
  cam.width = 24;
  cam.height = 20;
  cam.fx = cam.fy = 30.f;
  cam.cx = 12.f;
  cam.cy = 10.f;
  const Plane plane = PlaneFromDepthNormal(PixelRay(cam, 12.f, 10.f), 5.f, Normalize(Vec3{0.5f, 0.3f, -1.f}));
  PatchMatchResult r = SlantedPlaneResult(cam, plane);
  const Plane outlier_plane = PlaneFromDepthNormal(PixelRay(cam, 7.f, 6.f), 8.f, Vec3{0.f, 0.f, -1.f});
  StorePlane(r.plane.data(), 6 * cam.width + 7, outlier_plane);   // a wrong depth
  StorePlane(r.plane.data(), 12 * cam.width + 15, outlier_plane);  // a wrong depth, but cost ~0
  r.cost[12 * cam.width + 15] = 0.0005f;
  r.photo_cost[3 * cam.width + 20] = kInvalidCost;  // an invalid pixel: neither read nor changed
  StorePlane(r.plane.data(), 3 * cam.width + 20, outlier_plane);

  MedianFilterDepthsCpu(cam, 1.f, 20.f, 2, &r);
  // The outlier takes the surface depth; its normal is kept.
  EXPECT_NEAR(DepthAt(r, cam, 7, 6), PlaneDepth(plane, PixelRay(cam, 7.f, 6.f)), 1e-3f);
  EXPECT_FLOAT_EQ(LoadPlane(r.plane.data(), 6 * cam.width + 7).n.z, -1.f);
  // Near-perfect matches and invalid pixels are left alone.
  EXPECT_NEAR(DepthAt(r, cam, 15, 12), PlaneDepth(outlier_plane, PixelRay(cam, 15.f, 12.f)), 1e-5f);
  EXPECT_NEAR(DepthAt(r, cam, 20, 3), PlaneDepth(outlier_plane, PixelRay(cam, 20.f, 3.f)), 1e-5f);
  // Every other pixel still lies on the slanted plane, borders included: the median is taken
  // over the neighbours' planes on the pixel's own ray, not over raw neighbour depths.
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      if ((u == 15 && v == 12) || (u == 20 && v == 3)) continue;
      EXPECT_NEAR(DepthAt(r, cam, u, v), PlaneDepth(plane, PixelRay(cam, float(u), float(v))), 1e-3f)
          << "u=" << u << " v=" << v;
    }
  }
}

// The branch-free rank selection gives the sorted-array median for every number of values
// (1..21: the centre and 0..20 valid neighbours), ties included.
TEST(MedianFilterPixel, EqualsTheSortedMedian) {
  Camera cam;
  cam.width = cam.height = 11;
  cam.fx = cam.fy = 20.f;
  cam.cx = cam.cy = 5.f;
  const Vec3 ray = PixelRay(cam, 5.f, 5.f);
  const int du[20] = {0, 0, 0, 0, 0, 0, 1, -1, 3, -3, 5, -5, 2, 2, -2, -2, 1, 1, -1, -1};
  const int dv[20] = {1, -1, 3, -3, 5, -5, 0, 0, 0, 0, 0, 0, 1, -1, 1, -1, 2, -2, 2, -2};
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> level(0, 5);  // few distinct depths: many ties
  for (int trial = 0; trial < 21 * 4; ++trial) {
    const int valid_neighbours = trial % 21;
    std::vector<float> plane(4 * 121), cost(121, 0.5f), photo(121, 0.5f);
    for (int i = 0; i < 121; ++i) {
      const Vec3 r = PixelRay(cam, float(i % 11), float(i / 11));
      StorePlane(plane.data(), i, PlaneFromDepthNormal(r, 4.f + 0.5f * level(rng), Vec3{0.f, 0.f, -1.f}));
    }
    std::vector<int> order(20);
    for (int k = 0; k < 20; ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<float> expected = {PlaneDepth(LoadPlane(plane.data(), 60), ray)};
    for (int n = 0; n < 20; ++n) {
      const int q = (5 + dv[order[n]]) * 11 + 5 + du[order[n]];
      if (n < valid_neighbours) {
        expected.push_back(PlaneDepth(LoadPlane(plane.data(), q), ray));
      } else {
        photo[q] = kInvalidCost;
      }
    }
    std::sort(expected.begin(), expected.end());
    const size_t n = expected.size();
    ASSERT_EQ(n, static_cast<size_t>(valid_neighbours + 1));
    const float median = n % 2 ? expected[n / 2] : 0.5f * (expected[n / 2 - 1] + expected[n / 2]);
    MedianFilterInput in;
    in.camera = cam;
    in.depth_min = 1.f;
    in.depth_max = 20.f;
    in.plane = plane.data();
    in.cost = cost.data();
    in.photo_cost = photo.data();
    MedianFilterPixel(in, 5, 5);
    EXPECT_NEAR(PlaneDepth(LoadPlane(plane.data(), 60), ray), median, 1e-5f) << "trial " << trial << ", " << n << " values";
  }
}

}  // namespace
}  // namespace kernels
}  // namespace mpmvs

// The CPU PatchMatch engine on an analytic scene rendered inside the test: a textured plane
// tilted against every camera, seen by cameras rotated about several axes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {
namespace {

struct Scene {
  Vec3 plane_point{0.f, 0.f, 4.f};
  Vec3 plane_normal;  // world frame
  Vec3 axis_u, axis_v;
  std::vector<Camera> cameras;
  std::vector<std::vector<float>> images;
};

float Texture(float a, float b) {
  // Multi-scale smooth texture on plane coordinates (metres).
  return 128.f + 40.f * std::sin(5.f * a) * std::cos(4.f * b) + 30.f * std::sin(12.f * a + 9.f * b) +
         20.f * std::cos(21.f * b - 16.f * a) + 15.f * std::sin(33.f * a) * std::sin(29.f * b);
}

void LookAt(Vec3 centre, Vec3 target, Vec3 up, float R[9], float t[3]) {
  const Vec3 z = Normalize(target - centre);
  const Vec3 x = Normalize(Cross(z, up));
  const Vec3 y = Cross(z, x);
  const float M[9] = {x.x, x.y, x.z, y.x, y.y, y.z, z.x, z.y, z.z};
  for (int i = 0; i < 9; ++i) R[i] = M[i];
  const Vec3 tc = -MatVec(R, centre);
  t[0] = tc.x, t[1] = tc.y, t[2] = tc.z;
}

Scene MakeScene(int W, int H, float noise_sigma) {
  Scene scene;
  // Plane tilted ~40 degrees.
  scene.plane_normal = Normalize(Vec3{0.45f, -0.5f, -1.f});
  scene.axis_u = Normalize(Cross(scene.plane_normal, Vec3{0.f, 1.f, 0.f}));
  scene.axis_v = Cross(scene.plane_normal, scene.axis_u);
  const Vec3 centres[3] = {{0.f, 0.f, 0.f}, {0.5f, 0.1f, 0.1f}, {-0.3f, -0.45f, 0.05f}};
  const Vec3 ups[3] = {{0.f, 1.f, 0.f}, {0.2f, 1.f, 0.1f}, {-0.25f, 1.f, 0.f}};
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.f, noise_sigma);
  for (int c = 0; c < 3; ++c) {
    Camera cam;
    cam.width = W;
    cam.height = H;
    cam.fx = cam.fy = 0.9f * W;
    cam.cx = W / 2.f - 0.3f;
    cam.cy = H / 2.f + 0.2f;
    LookAt(centres[c], scene.plane_point + Vec3{0.1f * c, -0.05f * c, 0.f}, ups[c], cam.R, cam.t);
    std::vector<float> img(static_cast<size_t>(W) * H);
    const Vec3 C = -MatTVec(cam.R, Vec3{cam.t[0], cam.t[1], cam.t[2]});
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u < W; ++u) {
        float acc = 0.f;
        for (int sy = 0; sy < 2; ++sy) {
          for (int sx = 0; sx < 2; ++sx) {
            const Vec3 ray_cam = PixelRay(cam, u - 0.25f + 0.5f * sx, v - 0.25f + 0.5f * sy);
            const Vec3 dir = MatTVec(cam.R, ray_cam);
            const float lambda = Dot(scene.plane_point - C, scene.plane_normal) / Dot(dir, scene.plane_normal);
            const Vec3 X = C + lambda * dir - scene.plane_point;
            acc += Texture(Dot(X, scene.axis_u), Dot(X, scene.axis_v));
          }
        }
        img[static_cast<size_t>(v) * W + u] = 0.25f * acc + noise(rng);
      }
    }
    scene.cameras.push_back(cam);
    scene.images.push_back(std::move(img));
  }
  return scene;
}

// GT depth of reference pixel (u, v).
float GtDepth(const Scene& scene, const Camera& cam, int u, int v) {
  const Vec3 n_cam = MatVec(cam.R, scene.plane_normal);
  const Vec3 p_cam = MatVec(cam.R, scene.plane_point) + Vec3{cam.t[0], cam.t[1], cam.t[2]};
  const Vec3 ray = PixelRay(cam, static_cast<float>(u), static_cast<float>(v));
  return Dot(p_cam, n_cam) / Dot(ray, n_cam);
}

PatchMatchProblem MakeProblem(const Scene& scene) {
  PatchMatchProblem problem;
  problem.ref_camera = scene.cameras[0];
  problem.ref_image = ImageView{scene.images[0].data(), scene.cameras[0].width, scene.cameras[0].height};
  for (int s = 1; s < 3; ++s) {
    PatchMatchSource src;
    src.camera = scene.cameras[s];
    src.image = ImageView{scene.images[s].data(), scene.cameras[s].width, scene.cameras[s].height};
    problem.sources.push_back(src);
  }
  problem.depth_min = 2.0f;
  problem.depth_max = 8.0f;
  return problem;
}

PatchMatchSchedule MultiScaleSchedule(int max_scale, int per_scale) {
  PatchMatchSchedule schedule;
  for (int s = max_scale; s >= 0; --s) {
    for (int t = 0; t < per_scale; ++t) schedule.iterations.push_back({s, t});
  }
  schedule.seed = 42;
  return schedule;
}

TEST(PatchMatchCpu, TiltedTexturedPlaneIsRecovered) {
  const int W = 160, H = 120;
  const Scene scene = MakeScene(W, H, 2.f);
  const PatchMatchProblem problem = MakeProblem(scene);
  PatchMatchResult result;
  RunPatchMatchCpu(problem, MultiScaleSchedule(2, 3), &result);
  std::vector<float> depth, normal;
  ExtractDepthNormalMaps(problem, result, &depth, &normal);
  const Vec3 n_gt = MatVec(scene.cameras[0].R, scene.plane_normal);
  int considered = 0, good_depth = 0, good_normal = 0;
  for (int v = 12; v < H - 12; ++v) {
    for (int u = 12; u < W - 12; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      // Only pixels seen by at least one source view.
      const float z = GtDepth(scene, scene.cameras[0], u, v);
      bool seen = false;
      for (int s = 1; s < 3; ++s) {
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
  ASSERT_GT(considered, W * H / 3);
  const double depth_ratio = double(good_depth) / considered;
  const double normal_ratio = double(good_normal) / considered;
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
  const Scene scene = MakeScene(W, H, 1.f);
  const PatchMatchProblem problem = MakeProblem(scene);
  PatchMatchSchedule schedule = MultiScaleSchedule(1, 1);
  PatchMatchResult a, b;
  schedule.num_threads = 1;
  RunPatchMatchCpu(problem, schedule, &a);
  schedule.num_threads = 2;
  RunPatchMatchCpu(problem, schedule, &b);
  EXPECT_EQ(a.plane, b.plane);
  EXPECT_EQ(a.cost, b.cost);
  schedule.seed = 43;
  PatchMatchResult c;
  RunPatchMatchCpu(problem, schedule, &c);
  EXPECT_NE(a.plane, c.plane);
}

}  // namespace
}  // namespace kernels
}  // namespace mpmvs

namespace mpmvs {
namespace kernels {
namespace {

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

}  // namespace
}  // namespace kernels
}  // namespace mpmvs

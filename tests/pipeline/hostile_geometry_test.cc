// Hostile but valid geometry (issue 12): sources turned sideways so that reference rays run
// in their image plane, cameras behind, beside and inside the scene, extreme but finite
// intrinsics and translations, geo-referenced world offsets, absurd thread counts. Each
// must either run correctly or stop with a clear error: never a crash, never a silently
// wrong map.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"
#include "colmap_ext/plan/kernel_camera.h"
#include "colmap_ext/synthetic/scene_renderer.h"
#include "colmap_ext/synthetic/synthetic_layouts.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/synthetic/synthetic_sparse.h"
#include "kernels/patch_match.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

// ---------------------------------------------------------------------------------------
// Kernels: coordinates far outside the int range are rejected before any conversion.

// A source turned 90 degrees to the reference (its optical axis along the reference's x
// axis), centred on the reference's optical axis: the reference rays near the principal
// point run in the source's image plane, where projections leave every int range.
kernels::Camera SidewaysSource() {
  kernels::Camera src;
  src.width = 160;
  src.height = 120;
  src.fx = src.fy = 200.f;
  src.cx = 80.f;
  src.cy = 60.f;
  const float R[9] = {0, 0, -1, 0, 1, 0, 1, 0, 0};  // x_s = -z, y_s = y, z_s = x
  for (int i = 0; i < 9; ++i) src.R[i] = R[i];
  src.t[0] = 2.f;  // centre (0, 0, 2)
  return src;
}

TEST(HostileGeometry, GeometricErrorNearASourceImagePlaneIsClampedNotRead) {
  kernels::Camera ref;
  ref.width = 160;
  ref.height = 120;
  ref.fx = ref.fy = 100.f;
  ref.cx = 80.f - 1.f / 131072.f;  // column 80's ray meets the source image plane at z_s ~ 1e-7
  ref.cy = 60.f;
  const kernels::Camera src = SidewaysSource();
  std::vector<float> src_depth(static_cast<size_t>(src.width) * src.height, 1.f);
  kernels::SourceView view;
  view.camera = src;
  view.rel = kernels::ComputeRelativePose(ref, src);
  view.depth = src_depth.data();
  kernels::PassParams params;
  params.ref_camera = ref;
  params.geom_max_error = 2.f;
  for (int u = 78; u <= 82; ++u) {
    const kernels::Vec3 ray = kernels::PixelRay(ref, static_cast<float>(u), 60.f);
    for (float depth : {0.5f, 1.f, 1.5f, 3.f, 1e-30f, 1e30f}) {
      const float e = kernels::GeometricError(params, view, u, 60, ray, depth);
      EXPECT_TRUE(e >= 0.f && e <= params.geom_max_error) << u << " " << depth << ": " << e;
    }
  }
  // The pixel whose projection is ~2.6e9 px to the right: clamped, no depth map read.
  const kernels::Vec3 ray = kernels::PixelRay(ref, 80.f, 60.f);
  EXPECT_EQ(kernels::GeometricError(params, view, 80, 60, ray, 1.f), params.geom_max_error);
}

TEST(HostileGeometry, BilinearSampleOfANonFiniteCoordinateStaysInTheImage) {
  const std::vector<float> data = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  const kernels::ImageView img{data.data(), 4, 3};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(kernels::SampleBilinear(img, nan, 1.f), kernels::SampleBilinear(img, 0.f, 1.f));
  EXPECT_EQ(kernels::SampleBilinear(img, 2.f, nan), kernels::SampleBilinear(img, 2.f, 0.f));
  EXPECT_EQ(kernels::SampleBilinear(img, inf, -inf), 4.f);
  EXPECT_EQ(kernels::SampleBilinear(img, -3e9f, 3e9f), 9.f);
}

// A window whose centre maps into the source but one column of samples onto its principal
// plane (homogeneous z = 0): those samples are 0 * inf = NaN. Scalar (device) and CPU forms
// must stay finite and agree.
TEST(HostileGeometry, NccOfAWindowCrossingTheSourcePrincipalPlaneIsFinite) {
  const int W = 64, H = 48;
  std::vector<float> ref_data(W * H), src_data(W * H);
  for (int i = 0; i < W * H; ++i) {
    ref_data[i] = static_cast<float>((i * 37) % 251);
    src_data[i] = static_cast<float>((i * 53) % 241);
  }
  const kernels::ImageView ref{ref_data.data(), W, H};
  const kernels::ImageView src{src_data.data(), W, H};
  const int u = 30, v = 20;
  const kernels::WindowSpec window = kernels::WindowForScale(0);
  kernels::RefPatch patch;
  kernels::ComputeRefPatch(ref, u, v, window, &patch);
  // x' = 0, y' = 0, z' = x - (u - 5): the leftmost sample column has z' = 0.
  const float Hm[9] = {0, 0, 0, 0, 0, 0, 1, 0, -static_cast<float>(u - window.radius)};
  const float scalar = kernels::ComputeNccCost(patch, src, Hm, u, v, window);
  const float cpu = kernels::CpuBackendNccCost(patch, src, Hm, u, v, window);
  EXPECT_TRUE(scalar >= 0.f && scalar <= 2.f) << scalar;
  EXPECT_TRUE(cpu >= 0.f && cpu <= 2.f) << cpu;
}

// ---------------------------------------------------------------------------------------
// Pipeline: workspaces of the synthetic plane (160 x 120) with hand-placed cameras.

constexpr int kWidth = 160, kHeight = 120;

SyntheticLayout PlaneLayout(int num_views) {
  LayoutParams p;
  p.scene = "plane";
  p.width = kWidth;
  p.height = kHeight;
  p.num_views = num_views;
  p.plane_tilt_deg = 35;
  return BuildSyntheticLayout(p);
}

RenderedView Render(const SyntheticLayout& layout, const SyntheticCamera& camera, int index) {
  RenderOptions o;
  o.supersampling = 2;
  o.noise_sigma = 2.0;
  o.noise_seed = 1000 + index;
  return RenderView(layout.world, camera, o);
}

std::string ViewName(size_t i) { return "view_0" + std::to_string(i) + ".png"; }

// A workspace of these views (image i is cameras[i]) with a simulated sparse model.
SyntheticScene MakeScene(const std::vector<SyntheticCamera>& cameras,
                         const std::vector<RenderedView>& renders) {
  SyntheticScene scene;
  scene.options.write_gt_points = false;
  std::vector<std::string> names;
  for (size_t i = 0; i < cameras.size(); ++i) {
    SyntheticView view;
    view.name = ViewName(i);
    view.camera = cameras[i];
    view.render = renders[i];
    names.push_back(view.name);
    scene.views.push_back(view);
  }
  scene.model = SimulateSparseModel(cameras, names, renders, SparseSimulationOptions());
  return scene;
}

// Share of view i's surface pixels whose geometric depth is within 1 % of the truth.
double DepthAccuracy(const std::string& dir, const SyntheticScene& scene, size_t i) {
  const FloatMap depth = ReadFloatMap(dir + "/stereo/depth_maps/" + ViewName(i) + ".geometric.bin", 1);
  const FloatMap& gt = scene.views[i].render.depth;
  int total = 0, good = 0;
  for (int row = 0; row < gt.height; ++row) {
    for (int col = 0; col < gt.width; ++col) {
      const float z = gt.At(row, col);
      if (!(z > 0.f)) continue;
      ++total;
      if (std::abs(depth.At(row, col) - z) < 0.01f * z) ++good;
    }
  }
  return total > 0 ? double(good) / total : 0.0;
}

MpPatchMatchSummary RunQuietly(const std::string& dir, std::string* log = nullptr) {
  MpPatchMatchRun run;
  run.workspace_path = dir;
  run.options.write_pictures = "none";
  run.colmap_options.num_threads = 2;
  testing::internal::CaptureStderr();
  const MpPatchMatchSummary summary = RunMpPatchMatchStereo(run);
  const std::string err = testing::internal::GetCapturedStderr();
  if (log) *log = err;
  return summary;
}

// Views 0 and 1 of the plane layout, rendered once: the maps of a degenerate scene must be
// as good for them as in the scene of these two views alone.
struct TwoViewBaseline {
  SyntheticLayout layout = PlaneLayout(3);
  std::vector<SyntheticCamera> cameras;
  std::vector<RenderedView> renders;
  double accuracy[2] = {0, 0};

  explicit TwoViewBaseline(const test::TempDir& tmp) {
    for (int i = 0; i < 2; ++i) {
      cameras.push_back(layout.cameras[i]);
      renders.push_back(Render(layout, cameras[i], i));
    }
    const SyntheticScene scene = MakeScene(cameras, renders);
    WriteSyntheticScene(scene, tmp / "baseline");
    RunQuietly(tmp / "baseline");
    for (int i = 0; i < 2; ++i) accuracy[i] = DepthAccuracy(tmp / "baseline", scene, i);
    std::printf("two-view baseline: %.1f %% / %.1f %% within 1 %%\n", 100 * accuracy[0], 100 * accuracy[1]);
  }

  // Views 0 and 1 plus `third` (rendered as it is) as view 2.
  SyntheticScene WithThird(const SyntheticCamera& third) const {
    std::vector<SyntheticCamera> c = cameras;
    std::vector<RenderedView> r = renders;
    c.push_back(third);
    r.push_back(Render(layout, third, 2));
    return MakeScene(c, r);
  }

  void ExpectAsGood(const std::string& dir, const SyntheticScene& scene) const {
    for (size_t i = 0; i < 2; ++i) {
      const double a = DepthAccuracy(dir, scene, i);
      std::printf("%s: %.1f %% within 1 %% (baseline %.1f %%)\n", ViewName(i).c_str(), 100 * a, 100 * accuracy[i]);
      EXPECT_GE(a, accuracy[i] - 0.03) << ViewName(i);
    }
  }
};

// The reported crash: a source turned 90 degrees to view 0 (optical axis along view 0's x
// axis), centred in view 0's y-z plane, chosen by __auto__; default options.
TEST(HostileGeometry, SidewaysSourceRunsWithAWarningAndDoesNotSpoilTheOthers) {
  test::TempDir tmp;
  const TwoViewBaseline base(tmp);
  const SyntheticCamera& ref = base.cameras[0];
  const Eigen::Vector3d x_axis = ref.R.row(0).transpose(), y_axis = ref.R.row(1).transpose(),
                        z_axis = ref.R.row(2).transpose();
  const Eigen::Vector3d centre = ref.Center() + 2.6 * z_axis;
  const SyntheticCamera sideways = LookAtCamera(centre, centre - x_axis, -y_axis, 0.0, kWidth, kHeight,
                                                ref.fx, ref.fy, ref.cx, ref.cy);
  const SyntheticScene scene = base.WithThird(sideways);
  WriteSyntheticScene(scene, tmp / "sideways");
  std::string log;
  const MpPatchMatchSummary summary = RunQuietly(tmp / "sideways", &log);
  EXPECT_EQ(summary.num_written + summary.num_skipped_no_sources + summary.num_skipped_no_depth_range, 3);
  EXPECT_NE(log.find("view_02.png"), std::string::npos) << log;
  EXPECT_NE(log.find("image plane"), std::string::npos) << log;
  base.ExpectAsGood(tmp / "sideways", scene);
}

// One image given a camera of its own with a focal length of 1e12 px: every projection into
// it is far beyond the int range.
TEST(HostileGeometry, HugeFocalLengthSourceRunsWithAWarning) {
  test::TempDir tmp;
  const TwoViewBaseline base(tmp);
  SyntheticScene scene = base.WithThird(base.layout.cameras[2]);
  SparseCamera huge = scene.model.cameras.front();
  huge.camera_id = 77;
  huge.params[0] = huge.params[1] = 1e12;
  scene.model.cameras.push_back(huge);
  scene.model.images[2].camera_id = huge.camera_id;
  WriteSyntheticScene(scene, tmp / "huge");
  std::string log;
  RunQuietly(tmp / "huge", &log);
  EXPECT_NE(log.find("view_02.png"), std::string::npos) << log;
  EXPECT_NE(log.find("intrinsics"), std::string::npos) << log;
  base.ExpectAsGood(tmp / "huge", scene);
}

// Sources behind the reference, facing away from the scene, inside the scene (between the
// reference and the plane, looking back), a million metres away, with a tiny focal length
// and with a principal point far outside the image; all of them sources of every image
// (__all__) and a depth range given, so nothing is skipped.
TEST(HostileGeometry, CamerasBehindBesideAndInsideTheSceneDoNotSpoilTheOthers) {
  test::TempDir tmp;
  const TwoViewBaseline base(tmp);
  const SyntheticCamera& ref = base.cameras[0];
  const Eigen::Vector3d C = ref.Center(), z_axis = ref.R.row(2).transpose(), up(0, 0, 1);
  std::vector<SyntheticCamera> hostile;
  hostile.push_back(LookAtCamera(C - 2.0 * z_axis, Eigen::Vector3d::Zero(), up, 0, kWidth, kHeight, ref.fx,
                                 ref.fy, ref.cx, ref.cy));  // behind the reference
  hostile.push_back(LookAtCamera(C, C - z_axis, up, 0, kWidth, kHeight, ref.fx, ref.fy, ref.cx,
                                 ref.cy));  // at the reference, facing away
  hostile.push_back(LookAtCamera(0.5 * C, C, up, 0, kWidth, kHeight, ref.fx, ref.fy, ref.cx,
                                 ref.cy));  // inside the scene, looking back
  hostile.push_back(LookAtCamera(C - 1e6 * z_axis, Eigen::Vector3d::Zero(), up, 0, kWidth, kHeight,
                                 ref.fx, ref.fy, ref.cx, ref.cy));  // a million metres away
  hostile.push_back(LookAtCamera(C + 0.3 * z_axis, Eigen::Vector3d::Zero(), up, 0, kWidth, kHeight, 1e-3,
                                 1e-3, ref.cx, ref.cy));  // tiny focal length
  hostile.push_back(LookAtCamera(C + 0.3 * z_axis, Eigen::Vector3d::Zero(), up, 0, kWidth, kHeight, ref.fx,
                                 ref.fy, 1e7, -1e7));  // principal point far outside
  for (size_t h = 0; h < hostile.size(); ++h) {
    SyntheticScene scene = base.WithThird(hostile[h]);
    const std::string dir = tmp / ("hostile" + std::to_string(h));
    WriteSyntheticScene(scene, dir);
    {
      std::ofstream cfg(dir + "/stereo/patch-match.cfg");
      for (int i = 0; i < 3; ++i) cfg << ViewName(i) << "\n__all__\n";
    }
    MpPatchMatchRun run;
    run.workspace_path = dir;
    run.options.write_pictures = "none";
    run.colmap_options.num_threads = 2;
    run.colmap_options.depth_min = 0.5;
    run.colmap_options.depth_max = 8;
    testing::internal::CaptureStderr();
    const MpPatchMatchSummary summary = RunMpPatchMatchStereo(run);
    testing::internal::GetCapturedStderr();
    EXPECT_EQ(summary.num_written, 3) << h;
    std::printf("hostile camera %zu:\n", h);
    // A depth range much wider than the sparse one costs some accuracy in both views;
    // compare with the same wide range rather than with the default baseline.
    for (size_t i = 0; i < 2; ++i) {
      const double a = DepthAccuracy(dir, scene, i);
      std::printf("  %s: %.1f %% within 1 %%\n", ViewName(i).c_str(), 100 * a);
      EXPECT_GE(a, 0.8) << h << " " << ViewName(i);
    }
  }
}

// Moves the scene's world by offset (cameras and sparse points), as a georeferenced model is.
void ShiftWorld(const std::array<double, 3>& offset, SyntheticScene* scene) {
  for (SparseImage& image : scene->model.images) {
    double R[9];
    QuaternionToRotationMatrix(image.qvec, R);
    for (int i = 0; i < 3; ++i) {
      image.tvec[i] -= R[3 * i] * offset[0] + R[3 * i + 1] * offset[1] + R[3 * i + 2] * offset[2];
    }
  }
  for (SparsePoint3D& point : scene->model.points) {
    for (int i = 0; i < 3; ++i) point.xyz[i] += offset[i];
  }
}

// The same scene with the world shifted by a few million metres (as UTM/ECEF-registered
// models are) must give the same maps up to float rounding.
// Issue 35, defect 8: at a world offset of 1e9 the sparse depths are lost in COLMAP's float
// arithmetic. The log said the images "see no sparse points" while they see all of them;
// now it says why, and the summary accounts for every image.
TEST(HostileGeometry, DepthRangeLostFarFromTheOriginIsExplained) {
  test::TempDir tmp;
  SyntheticSceneOptions options;
  options.scene = "plane";
  options.width = 64;
  options.height = 48;
  options.num_views = 3;
  options.write_gt_points = false;
  SyntheticScene shifted = RenderSyntheticScene(options);
  ShiftWorld({1e9, 1e9, 1e9}, &shifted);
  WriteSyntheticScene(shifted, tmp / "far");
  std::string log;
  const MpPatchMatchSummary summary = RunQuietly(tmp / "far", &log);
  EXPECT_EQ(log.find("sees no sparse points"), std::string::npos) << log;
  EXPECT_NE(log.find("far from the world origin"), std::string::npos) << log;
  EXPECT_EQ(summary.num_references, 3);
  EXPECT_EQ(summary.num_written + summary.num_skipped_no_depth_range + summary.num_skipped_no_sources, 3) << log;
}

TEST(HostileGeometry, GeoreferencedWorldOffsetKeepsAccuracy) {
  test::TempDir tmp;
  SyntheticSceneOptions options;
  options.scene = "plane";
  options.width = kWidth;
  options.height = kHeight;
  options.num_views = 3;
  options.plane_tilt_deg = 35;
  options.write_gt_points = false;
  const SyntheticScene scene = RenderSyntheticScene(options);
  WriteSyntheticScene(scene, tmp / "origin");
  SyntheticScene shifted = scene;
  ShiftWorld({3.5e6, 5.1e6, 200.0}, &shifted);
  WriteSyntheticScene(shifted, tmp / "shifted");
  RunQuietly(tmp / "origin");
  RunQuietly(tmp / "shifted");
  for (size_t i = 0; i < scene.views.size(); ++i) {
    const double a = DepthAccuracy(tmp / "origin", scene, i);
    const double b = DepthAccuracy(tmp / "shifted", scene, i);
    std::printf("%s: %.2f %% within 1 %% at the origin, %.2f %% shifted\n", ViewName(i).c_str(), 100 * a,
                100 * b);
    EXPECT_GE(a, 0.85);
    EXPECT_NEAR(a, b, 0.01) << ViewName(i);
  }
}

// Ordinary pairs (the small plane scene, a rectified stereo pair, whose reference centre
// lies in the source's image plane but whose rays do not run along it) keep the world frame
// and raise no warning; the same scene a few million metres from the origin is re-centred.
TEST(HostileGeometry, OrdinaryPairsKeepTheWorldFrameAndRaiseNoWarning) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 96, 72, 3);
  DenseWorkspace ws = LoadDenseWorkspace(tmp.path(), -1);
  const std::vector<int> all = {0, 1, 2};
  for (int r = 0; r < 3; ++r) {
    const DenseView& ref = ws.views[r];
    EXPECT_FALSE(ChooseKernelFrame(ws, r, all, ref.depth_min).recentred) << r;
    for (int s = 0; s < 3; ++s) {
      if (s != r) EXPECT_EQ(DegenerateSourceReason(ref, ws.views[s], ref.depth_min, ref.depth_max), "");
    }
  }
  DenseView left = ws.views[0], right = ws.views[0];
  const double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int i = 0; i < 9; ++i) left.R[i] = right.R[i] = R[i];
  for (int i = 0; i < 3; ++i) left.T[i] = right.T[i] = 0;
  right.T[0] = -0.3;
  EXPECT_EQ(DegenerateSourceReason(left, right, 1.0, 10.0), "");
  EXPECT_EQ(DegenerateSourceReason(right, left, 1.0, 10.0), "");

  for (DenseView& view : ws.views) {  // world shifted by (3.5e6, 5.1e6, 200)
    const double offset[3] = {3.5e6, 5.1e6, 200.0};
    for (int i = 0; i < 3; ++i) {
      view.T[i] -= view.R[3 * i] * offset[0] + view.R[3 * i + 1] * offset[1] + view.R[3 * i + 2] * offset[2];
    }
  }
  const KernelFrame frame = ChooseKernelFrame(ws, 0, {1, 2}, ws.views[0].depth_min);
  EXPECT_TRUE(frame.recentred);
  const kernels::Camera ref = ToKernelCamera(ws.views[0], frame);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(ref.t[i], 0.f, 1e-6f);
}

// ---------------------------------------------------------------------------------------
// Threads: an absurd count runs (capped, with a warning); when threads cannot be created at
// all the run stops with a clear error instead of aborting.

struct CliRun {
  int code;
  std::string output;
};

CliRun ColmapMp(const std::string& shell_prefix, const std::string& args, const std::string& log) {
  CliRun r;
  r.code = test::RunCommand(shell_prefix + "'" + test::ColmapMpExecutable() + "' " + args, log);
  r.output = test::ReadTextFile(log);
  return r;
}

TEST(HostileGeometry, AbsurdThreadCountIsCappedWithAWarning) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp / "ws", 64, 48, 2);
  const CliRun r = ColmapMp("", "mp_patch_match_stereo --workspace_path " + (tmp / "ws") +
                                    " --PatchMatchStereo.num_threads 100000",
                            tmp / "log");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("--PatchMatchStereo.num_threads"), std::string::npos) << r.output;
}

TEST(HostileGeometry, ThreadCreationFailureIsAClearError) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp / "ws", 64, 48, 2);
  // 1 GB thread stacks in a 1.5 GB address space: the first worker starts, the second not.
  const CliRun r = ColmapMp("ulimit -s 1000000 && ulimit -v 1500000 && ",
                            "mp_patch_match_stereo --workspace_path " + (tmp / "ws") +
                                " --PatchMatchStereo.num_threads 3",
                            tmp / "log");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("thread"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace mpmvs

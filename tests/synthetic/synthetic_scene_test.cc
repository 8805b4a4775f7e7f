// Synthetic scenes: geometry/photometry consistency of images and GT, the written
// workspace, determinism, untextured masks and the SfM-like sparse model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/ply_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

SyntheticSceneOptions SmallOptions(const std::string& scene, int num_views = 3) {
  SyntheticSceneOptions o;
  o.scene = scene;
  o.width = 160;
  o.height = 120;
  o.num_views = num_views;
  o.supersampling = 2;
  return o;
}

float Grey(const RgbImage& img, int row, int col) {
  const size_t i = 3 * (static_cast<size_t>(row) * img.width + col);
  return 0.299f * img.data[i] + 0.587f * img.data[i + 1] + 0.114f * img.data[i + 2];
}

// Bilinear grey value at image coordinate (x, y) (pixel centres at integers).
float SampleGrey(const RgbImage& img, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  const float a = Grey(img, y0, x0), b = Grey(img, y0, x0 + 1);
  const float c = Grey(img, y0 + 1, x0), d = Grey(img, y0 + 1, x0 + 1);
  return static_cast<float>((1 - fy) * ((1 - fx) * a + fx * b) + fy * ((1 - fx) * c + fx * d));
}

Eigen::Vector3d BackProject(const SyntheticCamera& cam, int row, int col, double z) {
  const Eigen::Vector3d Xc(z * (col - cam.cx) / cam.fx, z * (row - cam.cy) / cam.fy, z);
  return cam.R.transpose() * (Xc - cam.t);
}

TEST(SyntheticScene, GtDepthReprojectsOntoMatchingIntensities) {
  SyntheticSceneOptions o = SmallOptions("indoor");
  o.noise_sigma = 0;  // isolate geometry from sensor noise
  const SyntheticScene scene = RenderSyntheticScene(o);
  ASSERT_EQ(scene.views.size(), 3u);
  uint64_t state = 12345;
  auto random_unit = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  // Half-pixel shifts of the source position: the GT position must beat all of them,
  // which pins down the pixel-centre convention of images and GT alike.
  const double shift_x[5] = {0, 0.5, -0.5, 0, 0}, shift_y[5] = {0, 0, 0, 0.5, -0.5};
  for (int ref = 0; ref < 2; ++ref) {
    const SyntheticView& r = scene.views[ref];
    const SyntheticView& s = scene.views[ref + 1];
    double sum[5] = {0, 0, 0, 0, 0}, sum_random = 0;
    int n_gt = 0, n_random = 0;
    for (int row = 0; row < o.height; ++row) {
      for (int col = 0; col < o.width; ++col) {
        const double z = r.render.depth.At(row, col);
        ASSERT_GT(z, 0) << "the room is closed: every pixel sees a surface";
        if (r.render.untextured[static_cast<size_t>(row) * o.width + col]) continue;
        // Undo each view's exposure so that only geometry decides the residual.
        const double ref_value = (Grey(r.render.image, row, col) - r.offset) / r.gain;
        auto residual = [&](double x, double y) {
          return std::abs(ref_value - (SampleGrey(s.render.image, x, y) - s.offset) / s.gain);
        };
        double x, y, zs;
        if (s.camera.Project(BackProject(r.camera, row, col, z), &x, &y, &zs) && x >= 2 &&
            y >= 2 && x < o.width - 3 && y < o.height - 3) {
          const double src_z = s.render.depth.At(static_cast<int>(std::lround(y)),
                                                 static_cast<int>(std::lround(x)));
          if (std::abs(src_z - zs) < 0.005 * zs) {  // not occluded in the source view
            for (int k = 0; k < 5; ++k) sum[k] += residual(x + shift_x[k], y + shift_y[k]);
            ++n_gt;
          }
        }
        // Baseline: a random depth in the scene's range.
        const double zr = 1.0 + 4.0 * random_unit();
        if (s.camera.Project(BackProject(r.camera, row, col, zr), &x, &y, &zs) && x >= 1 &&
            y >= 1 && x < o.width - 2 && y < o.height - 2) {
          sum_random += residual(x, y);
          ++n_random;
        }
      }
    }
    ASSERT_GT(n_gt, 1000);
    ASSERT_GT(n_random, 1000);
    // Without sensor noise the residual is bilinear interpolation of fine texture only
    // (about 3.5 grey levels at 160x120); a random depth gives several times more.
    const double mean_gt = sum[0] / n_gt, mean_random = sum_random / n_random;
    EXPECT_LT(mean_gt, 5.0) << "ref " << ref;
    EXPECT_LT(mean_gt, 0.25 * mean_random) << "ref " << ref << " random " << mean_random;
    for (int k = 1; k < 5; ++k) {
      EXPECT_LT(mean_gt, 0.8 * sum[k] / n_gt) << "ref " << ref << " shift " << k;
    }
  }
}

TEST(SyntheticScene, GtDepthIsConsistentAcrossViews) {
  const SyntheticScene scene = RenderSyntheticScene(SmallOptions("plane"));
  // On a single plane every pixel of one view that lands in another must have the same
  // 3-D point there: compare projected z with the other view's GT, bilinearly sampled.
  const SyntheticView& a = scene.views[0];
  const SyntheticView& b = scene.views[2];
  std::vector<double> errors;
  for (int row = 0; row < a.camera.height; row += 3) {
    for (int col = 0; col < a.camera.width; col += 3) {
      double x, y, z;
      if (!b.camera.Project(BackProject(a.camera, row, col, a.render.depth.At(row, col)), &x, &y, &z)) continue;
      if (x < 0 || y < 0 || x >= b.camera.width - 1 || y >= b.camera.height - 1) continue;
      const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
      const double fx = x - x0, fy = y - y0;
      const FloatMap& d = b.render.depth;
      // Inverse depth is affine in image coordinates on a plane: interpolate 1/z.
      const double inv = (1 - fy) * ((1 - fx) / d.At(y0, x0) + fx / d.At(y0, x0 + 1)) +
                         fy * ((1 - fx) / d.At(y0 + 1, x0) + fx / d.At(y0 + 1, x0 + 1));
      errors.push_back(std::abs(1.0 / inv - z) / z);
    }
  }
  ASSERT_GT(errors.size(), 500u);
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 1e-5);
  EXPECT_LT(errors.back(), 1e-4);
}

TEST(SyntheticScene, WritesWorkspaceAndCamerasRoundTrip) {
  test::TempDir dir;
  const SyntheticScene scene = GenerateSyntheticScene(SmallOptions("indoor"), dir.path());
  for (const char* sub : {"images", "sparse", "stereo/depth_maps", "stereo/normal_maps",
                          "stereo/consistency_graphs", "gt/depth_maps", "gt/normal_maps"}) {
    EXPECT_TRUE(DirectoryExists(dir / sub)) << sub;
  }
  const std::string cfg = test::ReadTextFile(dir / "stereo/patch-match.cfg");
  EXPECT_EQ(cfg, "view_00.png\n__auto__, 20\nview_01.png\n__auto__, 20\nview_02.png\n__auto__, 20\n");
  EXPECT_EQ(test::ReadTextFile(dir / "stereo/fusion.cfg"), "view_00.png\nview_01.png\nview_02.png\n");

  const SparseModel& expected = scene.model;
  for (const SparseModel& read : {ReadSparseModelBinary(dir / "sparse"), ReadSparseModelText(dir / "sparse")}) {
    ASSERT_EQ(read.cameras.size(), expected.cameras.size());
    for (size_t i = 0; i < read.cameras.size(); ++i) {
      EXPECT_EQ(read.cameras[i].camera_id, expected.cameras[i].camera_id);
      EXPECT_EQ(read.cameras[i].model_id, kPinholeModelId);
      EXPECT_EQ(read.cameras[i].width, 160u);
      EXPECT_EQ(read.cameras[i].height, 120u);
      ASSERT_EQ(read.cameras[i].params.size(), 4u);
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(read.cameras[i].params[k], expected.cameras[i].params[k], 1e-9);
    }
    ASSERT_EQ(read.images.size(), 3u);
    for (size_t i = 0; i < read.images.size(); ++i) {
      const SparseImage& a = read.images[i];
      const SparseImage& b = expected.images[i];
      EXPECT_EQ(a.name, b.name);
      EXPECT_EQ(a.image_id, b.image_id);
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(a.qvec[k], b.qvec[k], 1e-9);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.tvec[k], b.tvec[k], 1e-9);
      ASSERT_EQ(a.points2D.size(), b.points2D.size());
      // The written pose is the rendering camera's pose.
      double R[9];
      QuaternionToRotationMatrix(a.qvec, R);
      const SyntheticCamera& cam = scene.views[i].camera;
      for (int k = 0; k < 9; ++k) EXPECT_NEAR(R[k], cam.R(k / 3, k % 3), 1e-9);
      // Cameras are rotated about several axes, never identity.
      EXPECT_LT(std::abs(a.qvec[0]), 0.999);
      EXPECT_GT(std::abs(a.qvec[1]) + std::abs(a.qvec[3]), 0.01);
    }
    EXPECT_EQ(read.points.size(), expected.points.size());
  }

  // GT files are the rendered maps.
  for (const SyntheticView& v : scene.views) {
    const std::string stem = v.name.substr(0, v.name.size() - 4);
    const PfmImage pfm = ReadPfm(dir / ("gt/depth_" + stem + ".pfm"));
    ASSERT_EQ(pfm.width, 160);
    EXPECT_EQ(pfm.data, v.render.depth.data);
    const FloatMap depth = ReadFloatMap(dir / ("gt/depth_maps/" + v.name + ".bin"), 1);
    EXPECT_EQ(depth.data, v.render.depth.data);
    const FloatMap normal = ReadFloatMap(dir / ("gt/normal_maps/" + v.name + ".bin"), 3);
    EXPECT_EQ(normal.data, v.render.normal.data);
    const GrayImage image = ReadGrayImage(dir / ("images/" + v.name));
    EXPECT_EQ(image.width, 160);
    EXPECT_EQ(image.height, 120);
    const GrayImage mask = ReadGrayImage(dir / ("gt/untextured_" + stem + ".png"));
    for (size_t p = 0; p < mask.data.size(); ++p) {
      ASSERT_EQ(mask.data[p] > 127, v.render.untextured[p] != 0);
    }
    // Normals face the camera and are unit length.
    for (int row = 0; row < 120; row += 7) {
      for (int col = 0; col < 160; col += 7) {
        const Eigen::Vector3d n(v.render.normal.At(row, col, 0), v.render.normal.At(row, col, 1),
                                v.render.normal.At(row, col, 2));
        const Eigen::Vector3d ray((col - v.camera.cx) / v.camera.fx, (row - v.camera.cy) / v.camera.fy, 1);
        EXPECT_NEAR(n.norm(), 1.0, 1e-5);
        EXPECT_LE(n.dot(ray), 0.0);
      }
    }
  }
  const PlyPointCloud cloud = ReadPlyPointCloud(dir / "gt/gt_points.ply");
  EXPECT_EQ(cloud.points.size(), 3u * 160 * 120);
  EXPECT_TRUE(cloud.has_normals);
  EXPECT_TRUE(cloud.has_colors);
  EXPECT_TRUE(FileExists(dir / "gt/scene_info.json"));
}

TEST(SyntheticScene, DeterministicForSeedRegardlessOfThreads) {
  SyntheticSceneOptions o = SmallOptions("facade", 2);
  o.num_threads = 1;
  const SyntheticScene a = RenderSyntheticScene(o);
  o.num_threads = 3;
  const SyntheticScene b = RenderSyntheticScene(o);
  ASSERT_EQ(a.views.size(), b.views.size());
  for (size_t v = 0; v < a.views.size(); ++v) {
    EXPECT_EQ(a.views[v].render.image.data, b.views[v].render.image.data);
    EXPECT_EQ(a.views[v].render.depth.data, b.views[v].render.depth.data);
    EXPECT_EQ(a.views[v].render.normal.data, b.views[v].render.normal.data);
  }
  ASSERT_EQ(a.model.points.size(), b.model.points.size());
  for (size_t i = 0; i < a.model.points.size(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.model.points[i].xyz[k], b.model.points[i].xyz[k]);
  }
  // Outdoors the sky has no surface: no GT depth, no normal, not "untextured material".
  int sky = 0;
  const RenderedView& r = a.views[0].render;
  for (size_t i = 0; i < r.depth.data.size(); ++i) {
    if (r.depth.data[i] > 0) continue;
    ++sky;
    EXPECT_EQ(r.untextured[i], 0);
    EXPECT_EQ(r.normal.data[i], 0.f);
  }
  EXPECT_GT(sky, 0);
  EXPECT_LT(sky, static_cast<int>(r.depth.data.size() / 3));
  o.seed = 2;
  const SyntheticScene c = RenderSyntheticScene(o);
  EXPECT_NE(a.views[0].render.image.data, c.views[0].render.image.data);
}

TEST(SyntheticScene, IndoorIsMostlyUntexturedByMaterial) {
  const SyntheticScene scene = RenderSyntheticScene(SmallOptions("indoor", 5));
  for (const SyntheticView& v : scene.views) {
    EXPECT_GT(v.stats.untextured_fraction, 0.4) << v.name;
    EXPECT_LT(v.stats.untextured_fraction, 0.95) << v.name;  // some textured objects too
    EXPECT_DOUBLE_EQ(v.stats.gt_valid_fraction, 1.0);
    // Untextured pixels are plain: their local image variation is only shading + noise,
    // far below the textured pixels' (checks that the mask follows the material).
    double var_plain = 0, var_textured = 0;
    int n_plain = 0, n_textured = 0;
    const RgbImage& img = v.render.image;
    for (int r = 1; r < img.height - 1; ++r) {
      for (int c = 1; c < img.width - 1; ++c) {
        bool uniform = true;  // all 3x3 neighbours have the same mask value
        const size_t i = static_cast<size_t>(r) * img.width + c;
        for (int dr = -1; dr <= 1; ++dr) {
          for (int dc = -1; dc <= 1; ++dc) {
            uniform = uniform && v.render.untextured[i + dr * img.width + dc] == v.render.untextured[i];
          }
        }
        if (!uniform) continue;
        const float g = std::abs(Grey(img, r, c + 1) - Grey(img, r, c - 1)) +
                        std::abs(Grey(img, r + 1, c) - Grey(img, r - 1, c));
        if (v.render.untextured[i]) {
          var_plain += g;
          ++n_plain;
        } else {
          var_textured += g;
          ++n_textured;
        }
      }
    }
    ASSERT_GT(n_plain, 0);
    ASSERT_GT(n_textured, 0);
    EXPECT_LT(var_plain / n_plain, 0.5 * var_textured / n_textured) << v.name;
  }
}

TEST(SyntheticScene, SparsePointsLieOnTexturedSurfacesAndAreSeenTwice) {
  const SyntheticScene scene = RenderSyntheticScene(SmallOptions("indoor", 4));
  const SparseModel& m = scene.model;
  EXPECT_GE(m.points.size(), 100u);
  EXPECT_LE(m.points.size(), 2000u);
  std::vector<double> rel_depth_errors;
  std::vector<double> reprojection_errors;
  int on_textured = 0;
  for (const SparsePoint3D& p : m.points) {
    ASSERT_GE(p.track.size(), 2u);
    const Eigen::Vector3d X(p.xyz[0], p.xyz[1], p.xyz[2]);
    for (const SparseTrackElement& t : p.track) {
      const int image_index = m.FindImageById(t.image_id);
      ASSERT_GE(image_index, 0);
      const SparseImage& image = m.images[image_index];
      ASSERT_LT(t.point2D_idx, image.points2D.size());
      const SparsePoint2D& obs = image.points2D[t.point2D_idx];
      EXPECT_EQ(obs.point3D_id, p.point3D_id);
      const SyntheticView& v = scene.views[image_index];
      double x, y, z;
      ASSERT_TRUE(v.camera.Project(X, &x, &y, &z));
      // Observations use the +0.5 pixel-centre convention of SfM.
      reprojection_errors.push_back(std::hypot(obs.x - 0.5 - x, obs.y - 0.5 - y));
      const int col = static_cast<int>(std::lround(obs.x - 0.5));
      const int row = static_cast<int>(std::lround(obs.y - 0.5));
      ASSERT_TRUE(col >= 0 && row >= 0 && col < v.camera.width && row < v.camera.height);
      const double gt = v.render.depth.At(row, col);
      rel_depth_errors.push_back(std::abs(z - gt) / gt);
      on_textured += v.render.untextured[static_cast<size_t>(row) * v.camera.width + col] == 0;
    }
  }
  std::sort(rel_depth_errors.begin(), rel_depth_errors.end());
  std::sort(reprojection_errors.begin(), reprojection_errors.end());
  const size_t n = rel_depth_errors.size();
  // Triangulated from 0.5 px noisy observations at 160x120 (f = 144 px): depth noise of
  // about 2 % (it halves at the default 320x240).
  EXPECT_LT(rel_depth_errors[n / 2], 0.03);
  EXPECT_LT(rel_depth_errors[n * 9 / 10], 0.1);
  EXPECT_GT(on_textured, 0.9 * n);             // features come from textured materials
  EXPECT_GT(reprojection_errors[n / 2], 0.1);  // the observations are noisy ...
  EXPECT_LT(reprojection_errors[n / 2], 1.0);  // ... by about half a pixel
  // Every image sees points, and their depth range covers most of the GT.
  for (const SyntheticView& v : scene.views) {
    EXPECT_GT(v.stats.num_sparse_points, 20) << v.name;
    EXPECT_GT(v.stats.gt_in_sparse_range, 0.8) << v.name;
  }
}

TEST(SyntheticScene, PlaneTiltedAwayFromEveryCamera) {
  SyntheticSceneOptions o = SmallOptions("plane", 4);
  o.plane_tilt_deg = 35;
  const SyntheticScene scene = RenderSyntheticScene(o);
  ASSERT_EQ(scene.plane_view_angles_deg.size(), 4u);
  for (double a : scene.plane_view_angles_deg) EXPECT_GE(a, 35.0);
  for (const SyntheticView& v : scene.views) {
    // The GT normal at the image centre agrees: angle to the optical axis >= tilt.
    const int r = v.camera.height / 2, c = v.camera.width / 2;
    const double nz = v.render.normal.At(r, c, 2);
    EXPECT_GE(std::acos(-nz) * 180 / 3.14159265358979, 34.0);
    EXPECT_DOUBLE_EQ(v.stats.untextured_fraction, 0.0);
  }
  EXPECT_GT(scene.model.points.size(), 200u);
}

TEST(SyntheticScene, PoseNoiseTurnsTheWrittenPosesAboutTheirCentresOnly) {
  SyntheticSceneOptions o = SmallOptions("indoor", 4);
  const SyntheticScene exact = RenderSyntheticScene(o);
  o.pose_noise_px = 2.0;
  const SyntheticScene noisy = RenderSyntheticScene(o);
  double sum_sq = 0;
  for (size_t v = 0; v < exact.views.size(); ++v) {
    // The images and the GT are those of the true poses.
    EXPECT_EQ(noisy.views[v].render.image.data, exact.views[v].render.image.data);
    EXPECT_EQ(noisy.views[v].render.depth.data, exact.views[v].render.depth.data);
    const SparseImage& a = exact.model.images[v];
    const SparseImage& b = noisy.model.images[v];
    double Ra[9], Rb[9];
    QuaternionToRotationMatrix(a.qvec, Ra);
    QuaternionToRotationMatrix(b.qvec, Rb);
    // Same centre C = -R^T t; the turn between the two rotations is the noise.
    double trace = 0;
    for (int k = 0; k < 3; ++k) {
      double ca = 0, cb = 0;
      for (int j = 0; j < 3; ++j) {
        ca -= Ra[3 * j + k] * a.tvec[j];
        cb -= Rb[3 * j + k] * b.tvec[j];
        trace += Ra[3 * k + j] * Rb[3 * k + j];
      }
      EXPECT_NEAR(ca, cb, 1e-9);
    }
    const double angle = std::acos(std::min(1.0, (trace - 1) / 2));
    EXPECT_LT(angle * exact.views[v].camera.fx, 5 * o.pose_noise_px);
    sum_sq += angle * angle * exact.views[v].camera.fx * exact.views[v].camera.fx;
  }
  // Turns of sigma px (RMS) about random axes.
  const double rms_px = std::sqrt(sum_sq / exact.views.size());
  EXPECT_GT(rms_px, 0.2 * o.pose_noise_px);
  EXPECT_LT(rms_px, 4 * o.pose_noise_px);
}

TEST(SyntheticScene, OptionsCheckRejectsBadValues) {
  SyntheticSceneOptions o;
  EXPECT_NO_THROW(o.Check());
  o.scene = "castle";
  EXPECT_THROW(o.Check(), Error);
  o = SyntheticSceneOptions();
  o.num_views = 1;
  EXPECT_THROW(o.Check(), Error);
  o = SyntheticSceneOptions();
  o.supersampling = 0;
  EXPECT_THROW(o.Check(), Error);
  o = SyntheticSceneOptions();
  o.plane_tilt_deg = 85;
  EXPECT_THROW(o.Check(), Error);
  o = SyntheticSceneOptions();
  o.num_threads = 0;
  EXPECT_THROW(o.Check(), Error);
  o = SyntheticSceneOptions();
  o.pose_noise_px = -1;
  EXPECT_THROW(o.Check(), Error);
}

}  // namespace
}  // namespace mpmvs

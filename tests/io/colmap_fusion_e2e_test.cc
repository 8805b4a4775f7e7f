// End-to-end checks of our COLMAP I/O against the real `colmap` binary (3.8 on Debian):
// COLMAP undistorts and fuses, we write the depth/normal maps in between. If the map layout,
// the pixel convention, the pose/quaternion handling or the normal frame were wrong, the
// fused points would leave the true surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <tuple>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/util/file_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

using test::TempDir;
using Vec3 = std::array<double, 3>;

Vec3 Add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 Sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 Scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 Normalized(const Vec3& a) { return Scale(a, 1.0 / std::sqrt(Dot(a, a))); }
// Row-major 3x3 times vector, and transpose times vector.
Vec3 Mul(const double R[9], const Vec3& v) {
  return {R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
          R[6] * v[0] + R[7] * v[1] + R[8] * v[2]};
}
Vec3 MulTransposed(const double R[9], const Vec3& v) {
  return {R[0] * v[0] + R[3] * v[1] + R[6] * v[2], R[1] * v[0] + R[4] * v[1] + R[7] * v[2],
          R[2] * v[0] + R[5] * v[1] + R[8] * v[2]};
}

double Median(std::vector<double> values) {
  if (values.empty()) return NAN;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  return values[mid];
}

// ---- fused.ply ---------------------------------------------------------------------------

struct FusedPoint {
  Vec3 position;
  Vec3 normal;
  uint8_t rgb[3];
};

// Reads exactly the layout COLMAP 3.8's stereo_fusion writes (docs/colmap_interface.md §2).
std::vector<FusedPoint> ReadFusedPly(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  EXPECT_TRUE(file.is_open()) << path;
  std::vector<std::string> header;
  std::string line;
  while (std::getline(file, line) && line != "end_header") header.push_back(line);
  const std::vector<std::string> expected_properties = {
      "property float x",  "property float y",  "property float z",
      "property float nx", "property float ny", "property float nz",
      "property uchar red", "property uchar green", "property uchar blue"};
  size_t num_points = 0;
  std::vector<std::string> properties;
  for (const std::string& h : header) {
    if (h.rfind("element vertex ", 0) == 0) num_points = std::stoul(h.substr(15));
    if (h.rfind("property", 0) == 0) properties.push_back(h);
  }
  EXPECT_EQ(header.at(0), "ply");
  EXPECT_EQ(header.at(1), "format binary_little_endian 1.0");
  EXPECT_EQ(properties, expected_properties);
  std::vector<FusedPoint> points(num_points);
  for (FusedPoint& point : points) {
    float values[6];
    file.read(reinterpret_cast<char*>(values), sizeof(values));
    file.read(reinterpret_cast<char*>(point.rgb), 3);
    for (int k = 0; k < 3; ++k) {
      point.position[k] = values[k];
      point.normal[k] = values[3 + k];
    }
  }
  EXPECT_TRUE(file.good()) << path << " is shorter than its header says";
  return points;
}

// fused.ply.vis: uint64 number of points, then per point uint32 count and that many
// uint32 model image indices.
std::vector<std::vector<uint32_t>> ReadFusedVisibility(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  EXPECT_TRUE(file.is_open()) << path;
  uint64_t num_points = 0;
  file.read(reinterpret_cast<char*>(&num_points), sizeof(num_points));
  std::vector<std::vector<uint32_t>> visibility(static_cast<size_t>(num_points));
  for (std::vector<uint32_t>& images : visibility) {
    uint32_t count = 0;
    file.read(reinterpret_cast<char*>(&count), sizeof(count));
    images.resize(count);
    file.read(reinterpret_cast<char*>(images.data()), 4 * static_cast<std::streamsize>(count));
  }
  EXPECT_TRUE(file.good()) << path;
  return visibility;
}

void RunColmap(const std::string& colmap, const std::string& args, const std::string& log) {
  const int status = test::RunCommand("'" + colmap + "' " + args, log);
  ASSERT_EQ(status, 0) << "colmap " << args << " failed:\n" << test::ReadTextFile(log);
}

// stereo_fusion on workspace/stereo geometric maps into workspace/output_name,
// single-threaded (deterministic output).
std::string FusionArgs(const std::string& workspace, const std::string& output_name,
                       int min_num_pixels, int max_num_pixels = 10000) {
  return "stereo_fusion --workspace_path '" + workspace +
         "' --workspace_format COLMAP --input_type geometric --output_path '" + workspace + "/" +
         output_name + "' --StereoFusion.num_threads 1 --StereoFusion.min_num_pixels " +
         std::to_string(min_num_pixels) + " --StereoFusion.max_num_pixels " +
         std::to_string(max_num_pixels);
}

// Camera-frame point of depth-map pixel (col, row): MVS back-projects through image
// coordinate (col, row), without +0.5.
Vec3 BackProject(const DenseView& view, int col, int row, double depth) {
  return {depth * (col - view.K[2]) / view.K[0], depth * (row - view.K[5]) / view.K[4], depth};
}

// ---- case 1: Middlebury 2005 Dolls, GT depth ----------------------------------------------

// Normals of a GT depth map: cross product of central differences over +-2 pixels, in the
// camera frame, towards the camera. Where undefined (border, hole, depth jump) both the
// normal and the depth are cleared so that fusion never sees a depth without a normal.
void NormalsFromDepth(const DenseView& view, FloatMap* depth, FloatMap* normals) {
  constexpr int kStep = 2;
  const FloatMap gt = *depth;
  *normals = FloatMap(gt.width, gt.height, 3, 0.f);
  for (int row = 0; row < gt.height; ++row) {
    for (int col = 0; col < gt.width; ++col) {
      const float z = gt.At(row, col);
      bool defined = z > 0 && row >= kStep && col >= kStep && row + kStep < gt.height &&
                     col + kStep < gt.width;
      const int offsets[4][2] = {{0, -kStep}, {0, kStep}, {-kStep, 0}, {kStep, 0}};
      Vec3 neighbours[4];
      for (int k = 0; k < 4 && defined; ++k) {
        const int r = row + offsets[k][0], c = col + offsets[k][1];
        const float zn = gt.At(r, c);
        defined = zn > 0 && std::abs(zn - z) < 0.02f * z;
        neighbours[k] = BackProject(view, c, r, zn);
      }
      Vec3 normal = {0, 0, 0};
      if (defined) {
        normal = Cross(Sub(neighbours[1], neighbours[0]), Sub(neighbours[3], neighbours[2]));
        defined = Dot(normal, normal) > 0;
      }
      if (!defined) {
        depth->At(row, col) = 0;
        continue;
      }
      normal = Normalized(normal);
      if (Dot(normal, BackProject(view, col, row, z)) > 0) normal = Scale(normal, -1);
      for (int k = 0; k < 3; ++k) normals->At(row, col, k) = static_cast<float>(normal[k]);
    }
  }
}

TEST(ColmapFusionE2E, DollsGroundTruthMapsFuseOntoTheSurface) {
  MPMVS_REQUIRE_DATASET(dataset, "middlebury2005_dolls");
  MPMVS_REQUIRE_COLMAP(colmap);
  TempDir dir;
  const std::string ws_path = dir / "dense";
  RunColmap(colmap,
            "image_undistorter --image_path '" + dataset + "/images' --input_path '" + dataset +
                "/sparse' --output_path '" + ws_path + "' --output_type COLMAP",
            dir / "undistort.log");
  if (HasFatalFailure()) return;

  // Our reader on COLMAP's binary output: same cameras as the text input.
  const DenseWorkspace ws = LoadDenseWorkspace(ws_path, -1);
  const SparseModel input = ReadSparseModel(dataset + "/sparse");
  ASSERT_EQ(ws.views.size(), 2u);
  std::vector<FloatMap> gt_depths;
  for (size_t i = 0; i < ws.views.size(); ++i) {
    const DenseView& view = ws.views[i];
    const SparseCamera& camera =
        input.cameras[input.FindCamera(input.images[input.FindImageByName(view.name)].camera_id)];
    EXPECT_NEAR(view.K[0], camera.params[0], 1e-9);
    EXPECT_NEAR(view.K[2], camera.params[2], 1e-9);
    EXPECT_EQ(view.width, static_cast<int>(camera.width));

    const std::string stem = view.name.substr(0, view.name.rfind('.'));
    const PfmImage pfm = ReadPfm(dataset + "/gt/depth_" + stem + ".pfm");
    ASSERT_EQ(pfm.width, view.width);
    ASSERT_EQ(pfm.height, view.height);
    FloatMap depth(pfm.width, pfm.height, 1);
    depth.data = pfm.data;
    gt_depths.push_back(depth);
    FloatMap normals;
    NormalsFromDepth(view, &depth, &normals);
    WriteFloatMap(ws.DepthMapPath(static_cast<int>(i), "geometric"), depth);
    WriteFloatMap(ws.NormalMapPath(static_cast<int>(i), "geometric"), normals);
  }

  RunColmap(colmap, FusionArgs(ws_path, "fused.ply", 1), dir / "fusion.log");
  if (HasFatalFailure()) return;
  const std::vector<FusedPoint> points = ReadFusedPly(ws_path + "/fused.ply");
  ASSERT_GT(points.size(), 20000u) << test::ReadTextFile(dir / "fusion.log");

  // Project into view 1 and compare z with the GT depth there. Points that view 1 fused
  // alone reproduce its own map trivially, so the points that used view 5 (model index 1;
  // pose, K and map of the second image) are also judged on their own.
  const std::vector<std::vector<uint32_t>> visibility =
      ReadFusedVisibility(ws_path + "/fused.ply.vis");
  ASSERT_EQ(visibility.size(), points.size());
  const DenseView& view = ws.views[0];
  const FloatMap& gt = gt_depths[0];
  std::vector<double> all_errors, view5_errors, view5_only_errors;
  size_t num_merged = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const std::vector<uint32_t>& images = visibility[i];
    const bool uses_view5 = std::count(images.begin(), images.end(), 1u) > 0;
    num_merged += uses_view5 && std::count(images.begin(), images.end(), 0u) > 0;
    const Vec3 X = Add(Mul(view.R, points[i].position), {view.T[0], view.T[1], view.T[2]});
    if (X[2] <= 0) continue;
    const int col = static_cast<int>(std::lround(view.K[0] * X[0] / X[2] + view.K[2]));
    const int row = static_cast<int>(std::lround(view.K[4] * X[1] / X[2] + view.K[5]));
    if (col < 0 || row < 0 || col >= gt.width || row >= gt.height) continue;
    const float gt_depth = gt.At(row, col);
    if (gt_depth <= 0) continue;
    const double error = std::abs(X[2] - gt_depth) / gt_depth;
    all_errors.push_back(error);
    if (uses_view5) view5_errors.push_back(error);
    if (images.size() == 1 && images[0] == 1) view5_only_errors.push_back(error);
  }
  const auto fraction_below = [](const std::vector<double>& errors, double limit) {
    return std::count_if(errors.begin(), errors.end(), [&](double e) { return e < limit; }) /
           static_cast<double>(errors.size());
  };
  std::cout << "[   INFO   ] dolls: " << points.size() << " fused points, " << num_merged
            << " from both views; median relative depth error " << Median(all_errors)
            << " (points using view5: " << view5_errors.size() << ", median "
            << Median(view5_errors) << ", " << 100 * fraction_below(view5_errors, 0.01)
            << "% within 1%); view5 only: " << view5_only_errors.size() << ", median "
            << Median(view5_only_errors) << "\n";
  ASSERT_GT(all_errors.size(), points.size() / 2);
  EXPECT_LT(Median(all_errors), 0.005);
  // Merging needs agreeing depth (1%), reprojection (2 px) and normals (10 degrees).
  EXPECT_GT(num_merged, points.size() / 4);
  ASSERT_GT(view5_errors.size(), 20000u);
  EXPECT_LT(Median(view5_errors), 0.005);
  EXPECT_GT(fraction_below(view5_errors, 0.01), 0.8);
  ASSERT_GT(view5_only_errors.size(), 5000u);
  EXPECT_LT(Median(view5_only_errors), 0.005);
}

// ---- case 2: synthetic tilted plane, rotated cameras -------------------------------------

struct PlaneScene {
  Vec3 normal;   // unit, world frame
  double offset;  // plane: normal . X = offset
  Vec3 u_axis, v_axis;
};

// Smooth random texture on plane coordinates (sum of random sinusoids), 8-bit.
class PlaneTexture {
 public:
  explicit PlaneTexture(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> angle(0, 2 * M_PI), frequency(3, 25);
    for (auto& wave : waves_) wave = {frequency(rng), angle(rng), angle(rng)};
  }
  uint8_t At(double a, double b) const {
    double value = 0;
    for (const auto& [f, direction, phase] : waves_) {
      value += std::sin(f * (a * std::cos(direction) + b * std::sin(direction)) + phase);
    }
    return static_cast<uint8_t>(std::clamp(128 + 127 * value / 3.0, 0.0, 255.0));
  }

 private:
  std::array<std::tuple<double, double, double>, 12> waves_;
};

struct SyntheticCamera {
  double R[9];  // world to camera, row-major
  Vec3 t;
  Vec3 centre;
};

// Looks from centre at target, then rolls about the viewing axis: a rotation about all
// three axes in general.
SyntheticCamera LookAt(const Vec3& centre, const Vec3& target, double roll_deg) {
  const Vec3 z = Normalized(Sub(target, centre));
  const Vec3 x0 = Normalized(Cross({0, 1, 0}, z));
  const Vec3 y0 = Cross(z, x0);
  const double roll = roll_deg * M_PI / 180;
  const Vec3 x = Add(Scale(x0, std::cos(roll)), Scale(y0, std::sin(roll)));
  const Vec3 y = Cross(z, x);
  SyntheticCamera camera;
  for (int k = 0; k < 3; ++k) {
    camera.R[k] = x[k];
    camera.R[3 + k] = y[k];
    camera.R[6 + k] = z[k];
  }
  camera.centre = centre;
  camera.t = Scale(Mul(camera.R, centre), -1);
  return camera;
}

// Camera-frame z-depth of the plane along the ray of image coordinate (col, row); <= 0 if
// the ray misses it.
double PlaneDepth(const PlaneScene& plane, const SyntheticCamera& camera, const double K[9],
                  double col, double row) {
  const Vec3 ray_cam = {(col - K[2]) / K[0], (row - K[5]) / K[4], 1};
  const Vec3 ray_world = MulTransposed(camera.R, ray_cam);
  const double denominator = Dot(plane.normal, ray_world);
  if (std::abs(denominator) < 1e-12) return -1;
  return (plane.offset - Dot(plane.normal, camera.centre)) / denominator;
}

TEST(ColmapFusionE2E, RotatedCamerasFuseOntoTiltedPlane) {
  MPMVS_REQUIRE_COLMAP(colmap);
  TempDir dir;
  constexpr int kWidth = 160, kHeight = 120;
  const double K[9] = {150, 0, 79.3, 0, 146, 60.6, 0, 0, 1};

  PlaneScene plane;
  const Vec3 plane_point = {0.2, -0.1, 6};
  plane.normal = Normalized({0.35, -0.25, -1});
  plane.offset = Dot(plane.normal, plane_point);
  plane.u_axis = Normalized(Cross(plane.normal, {0, 1, 0}));
  plane.v_axis = Cross(plane.normal, plane.u_axis);
  const PlaneTexture texture(7);

  const std::vector<SyntheticCamera> cameras = {
      LookAt({-0.7, 0.2, 0}, Add(plane_point, {0.1, 0, 0}), 12),
      LookAt({0.6, -0.35, 0.3}, Add(plane_point, {-0.1, 0.1, 0}), -20),
      LookAt({0.1, 0.6, -0.4}, Add(plane_point, {0, -0.1, 0.1}), 35)};

  // Input model (text) and images.
  const std::string input = dir / "input";
  CreateDirectories(input + "/images");
  CreateDirectories(input + "/sparse");
  SparseModel model;
  SparseCamera camera;
  camera.camera_id = 1;
  camera.model_id = kPinholeModelId;
  camera.width = kWidth;
  camera.height = kHeight;
  camera.params = {K[0], K[4], K[2], K[5]};
  model.cameras = {camera};
  for (size_t i = 0; i < cameras.size(); ++i) {
    SparseImage image;
    image.image_id = static_cast<uint32_t>(i + 1);
    image.camera_id = 1;
    image.name = "cam" + std::to_string(i) + ".png";
    RotationMatrixToQuaternion(cameras[i].R, image.qvec);
    ASSERT_GT(std::abs(image.qvec[1]) + std::abs(image.qvec[2]), 0.05);  // not about z only
    for (int k = 0; k < 3; ++k) image.tvec[k] = cameras[i].t[k];
    model.images.push_back(image);

    RgbImage rgb;
    rgb.width = kWidth;
    rgb.height = kHeight;
    for (int row = 0; row < kHeight; ++row) {
      for (int col = 0; col < kWidth; ++col) {
        const double depth = PlaneDepth(plane, cameras[i], K, col, row);
        ASSERT_GT(depth, 0);
        const Vec3 X_cam = {depth * (col - K[2]) / K[0], depth * (row - K[5]) / K[4], depth};
        const Vec3 X = MulTransposed(cameras[i].R, Sub(X_cam, cameras[i].t));
        const Vec3 local = Sub(X, plane_point);
        const uint8_t value = texture.At(Dot(local, plane.u_axis), Dot(local, plane.v_axis));
        rgb.data.insert(rgb.data.end(), {value, static_cast<uint8_t>(255 - value / 2), value});
      }
    }
    WriteRgbPng(input + "/images/" + image.name, rgb);
  }
  // Sparse points on the plane seen by all cameras (fusion uses them for image overlap).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> spread(-0.6, 0.6);
  while (model.points.size() < 40) {
    const Vec3 X = Add(plane_point, Add(Scale(plane.u_axis, spread(rng)),
                                        Scale(plane.v_axis, spread(rng))));
    SparsePoint3D point;
    point.point3D_id = model.points.size() + 1;
    bool seen_by_all = true;
    for (size_t i = 0; i < cameras.size(); ++i) {
      const Vec3 x = Add(Mul(cameras[i].R, X), cameras[i].t);
      const double u = K[0] * x[0] / x[2] + K[2], v = K[4] * x[1] / x[2] + K[5];
      seen_by_all = seen_by_all && x[2] > 0 && u > 1 && v > 1 && u < kWidth - 1 && v < kHeight - 1;
      point.track.push_back({model.images[i].image_id,
                             static_cast<uint32_t>(model.images[i].points2D.size())});
      model.images[i].points2D.push_back({u, v, point.point3D_id});
    }
    if (!seen_by_all) {
      for (SparseImage& image : model.images) image.points2D.pop_back();
      continue;
    }
    for (int k = 0; k < 3; ++k) point.xyz[k] = X[k];
    model.points.push_back(point);
  }
  WriteSparseModelText(model, input + "/sparse");

  const std::string ws_path = dir / "dense";
  RunColmap(colmap,
            "image_undistorter --image_path '" + input + "/images' --input_path '" + input +
                "/sparse' --output_path '" + ws_path + "' --output_type COLMAP",
            dir / "undistort.log");
  if (HasFatalFailure()) return;
  const DenseWorkspace ws = LoadDenseWorkspace(ws_path, -1);
  ASSERT_EQ(ws.views.size(), 3u);

  for (size_t i = 0; i < ws.views.size(); ++i) {
    const DenseView& view = ws.views[i];
    const SyntheticCamera& cam = cameras[static_cast<size_t>(view.name[3] - '0')];
    // COLMAP's binary model read back: pose and intrinsics survive the round trip.
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(view.R[k], cam.R[k], 1e-9);
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(view.K[k], K[k], 1e-9);
    ASSERT_EQ(view.width, kWidth);

    // Analytic maps; the normal is the world plane normal rotated into the camera frame.
    FloatMap depth(kWidth, kHeight, 1), normals(kWidth, kHeight, 3);
    Vec3 normal_cam = Mul(cam.R, plane.normal);
    for (int row = 0; row < kHeight; ++row) {
      for (int col = 0; col < kWidth; ++col) {
        const double z = PlaneDepth(plane, cam, K, col, row);
        depth.At(row, col) = static_cast<float>(z);
        const Vec3 ray = {(col - K[2]) / K[0], (row - K[5]) / K[4], 1};
        const Vec3 n = Dot(normal_cam, ray) > 0 ? Scale(normal_cam, -1) : normal_cam;
        for (int k = 0; k < 3; ++k) normals.At(row, col, k) = static_cast<float>(n[k]);
      }
    }
    WriteFloatMap(ws.DepthMapPath(static_cast<int>(i), "geometric"), depth);
    WriteFloatMap(ws.NormalMapPath(static_cast<int>(i), "geometric"), normals);
  }

  RunColmap(colmap, FusionArgs(ws_path, "fused.ply", 3), dir / "fusion.log");
  if (HasFatalFailure()) return;
  const std::vector<FusedPoint> points = ReadFusedPly(ws_path + "/fused.ply");
  ASSERT_GT(points.size(), 1000u) << test::ReadTextFile(dir / "fusion.log");

  // Plane normal oriented towards the cameras (all are on the same side).
  const Vec3 normal_towards_cameras =
      Dot(plane.normal, Sub(cameras[0].centre, plane_point)) > 0 ? plane.normal
                                                                 : Scale(plane.normal, -1);
  std::vector<double> relative_distances, normal_errors_deg;
  for (const FusedPoint& point : points) {
    const double distance = std::abs(Dot(plane.normal, point.position) - plane.offset);
    const double depth = Add(Mul(cameras[0].R, point.position), cameras[0].t)[2];
    relative_distances.push_back(distance / depth);
    const double cosine = Dot(Normalized(point.normal), normal_towards_cameras);
    normal_errors_deg.push_back(std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / M_PI);
  }
  std::cout << "[   INFO   ] plane: " << points.size() << " fused points, median relative "
            << "distance " << Median(relative_distances) << ", max normal error "
            << *std::max_element(normal_errors_deg.begin(), normal_errors_deg.end())
            << " deg\n";
  EXPECT_LT(Median(relative_distances), 1e-3);
  EXPECT_LT(*std::max_element(relative_distances.begin(), relative_distances.end()), 5e-3);
  EXPECT_LT(*std::max_element(normal_errors_deg.begin(), normal_errors_deg.end()), 2.0);

  // Single-pixel points are plain back-projections of our depths, so they lie on the plane
  // up to float precision. This is what catches a pixel-centre (+0.5) mistake, which moves
  // points off a tilted plane by only ~5e-4 of the depth, below the median bound above.
  RunColmap(colmap, FusionArgs(ws_path, "single.ply", 1, 1), dir / "fusion_single.log");
  if (HasFatalFailure()) return;
  const std::vector<FusedPoint> single = ReadFusedPly(ws_path + "/single.ply");
  ASSERT_GT(single.size(), 10000u);
  double max_single_distance = 0;
  for (const FusedPoint& point : single) {
    const double depth = Add(Mul(cameras[0].R, point.position), cameras[0].t)[2];
    max_single_distance = std::max(
        max_single_distance, std::abs(Dot(plane.normal, point.position) - plane.offset) / depth);
  }
  std::cout << "[   INFO   ] plane, single-pixel points: " << single.size()
            << ", max relative distance " << max_single_distance << "\n";
  EXPECT_LT(max_single_distance, 1e-5);
}

}  // namespace
}  // namespace mpmvs

// The native front end (COLMAP's mvs::Workspace/Model, Bitmap and map writers) against
// mp-mvs's own I/O on one synthetic scene with grey PNGs: same views, cameras and depth
// ranges, same grey values, same sparse points' reprojection errors (and so the same depth
// check tolerance), and byte-equal depth/normal maps and consistency graphs.
// Built only where an installed COLMAP is found.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "colmap/mvs/model.h"
#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/native/colmap_workspace_io.h"
#include "colmap_ext/native/mp_patch_match_stereo_native.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"
#include "colmap_ext/plan/depth_check_tolerance.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "tests/io_test_util.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;

class TempFolder {
 public:
  TempFolder() {
    const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
    path_ = (fs::temp_directory_path() /
             ("mpmvs_native_" + std::string(info->name()) + "_" + std::to_string(::getpid())))
                .string();
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempFolder() {
    if (std::getenv("MPMVS_KEEP_TEST_DIRS") == nullptr) fs::remove_all(path_);
  }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

std::vector<char> Bytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

// A small tilted-plane scene whose images are rewritten as 8-bit grey PNGs.
void MakeGreyScene(const std::string& dir) {
  SyntheticSceneOptions scene;
  scene.scene = "plane";
  scene.width = 96;
  scene.height = 72;
  scene.num_views = 3;
  scene.plane_tilt_deg = 35;
  GenerateSyntheticScene(scene, dir);
  for (const auto& entry : fs::directory_iterator(dir + "/images")) {
    const GrayImage gray = ReadGrayImage(entry.path().string());
    std::vector<uint8_t> bytes(gray.data.begin(), gray.data.end());
    WriteGrayPng(entry.path().string(), gray.width, gray.height, bytes);
  }
}

// Each point's position (as float, mvs::Model's precision) and error, sorted.
std::vector<std::pair<std::array<float, 3>, double>> PointErrors(const DenseWorkspace& workspace) {
  std::vector<std::pair<std::array<float, 3>, double>> errors;
  for (const SparsePoint3D& point : workspace.model.points) {
    errors.push_back({{static_cast<float>(point.xyz[0]), static_cast<float>(point.xyz[1]),
                       static_cast<float>(point.xyz[2])}, point.error});
  }
  std::sort(errors.begin(), errors.end());
  return errors;
}

// Runs colmap-mp on <tmp>/ours and the native command on a copy, <tmp>/colmap, and expects
// byte-equal maps and consistency graphs.
void ExpectBothFrontEndsWriteTheSameMaps(const TempFolder& tmp) {
  fs::copy(tmp / "ours", tmp / "colmap", fs::copy_options::recursive);
  MpPatchMatchRun run;
  run.colmap_options.write_consistency_graph = true;
  run.options.write_pictures = "none";
  run.workspace_path = tmp / "ours";
  const MpPatchMatchSummary sa = RunMpPatchMatchStereo(run);
  // The native command as COLMAP's command table calls it (argv[0] = program).
  std::vector<std::string> args = {"colmap", "--workspace_path", tmp / "colmap",
                                   "--PatchMatchStereo.write_consistency_graph", "1",
                                   "--MPMVS.write_pictures", "none"};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  ASSERT_EQ(RunColmapMpPatchMatchStereo(static_cast<int>(argv.size()), argv.data()), EXIT_SUCCESS);
  EXPECT_EQ(sa.num_written, 3);
  int compared = 0;
  for (const char* sub : {"depth_maps", "normal_maps", "consistency_graphs"}) {
    for (const auto& entry : fs::directory_iterator(tmp / ("ours/stereo/" + std::string(sub)))) {
      const std::string name = entry.path().filename().string();
      const std::string other = tmp / ("colmap/stereo/" + std::string(sub) + "/" + name);
      ASSERT_TRUE(fs::exists(other)) << other;
      EXPECT_TRUE(Bytes(entry.path().string()) == Bytes(other)) << sub << "/" << name;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 3 * 2 * 3);  // 3 images x {photometric, geometric} x 3 kinds
}

TEST(ColmapNative, LoadsTheSameViewsCamerasAndDepthRanges) {
  TempFolder tmp;
  MakeGreyScene(tmp / "ws");
  MpMvsWorkspaceIo ours;
  const std::unique_ptr<WorkspaceIo> colmap = MakeColmapWorkspaceIo();
  const DenseWorkspace a = ours.Load(tmp / "ws", -1);
  const DenseWorkspace b = colmap->Load(tmp / "ws", -1);
  ASSERT_EQ(a.views.size(), b.views.size());
  colmap::mvs::Model model;
  model.Read(tmp / "ws", "COLMAP");
  const auto colmap_ranges = model.ComputeDepthRanges();
  for (size_t i = 0; i < a.views.size(); ++i) {
    const DenseView& va = a.views[i];
    const DenseView& vb = b.views[i];
    EXPECT_EQ(va.name, vb.name);
    EXPECT_EQ(va.width, vb.width);
    EXPECT_EQ(va.height, vb.height);
    for (int k = 0; k < 9; ++k) EXPECT_EQ(float(va.K[k]), float(vb.K[k])) << va.name << " K" << k;
    for (int k = 0; k < 9; ++k) EXPECT_EQ(float(va.R[k]), float(vb.R[k])) << va.name << " R" << k;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(float(va.T[k]), float(vb.T[k])) << va.name << " T" << k;
    EXPECT_EQ(va.depth_min, vb.depth_min) << va.name;
    EXPECT_EQ(va.depth_max, vb.depth_max) << va.name;
    // mp-mvs's float replica is COLMAP's Model::ComputeDepthRanges.
    EXPECT_EQ(float(va.depth_min), colmap_ranges[i].first) << va.name;
    EXPECT_EQ(float(va.depth_max), colmap_ranges[i].second) << va.name;
    const GrayImage ga = ours.ReadGray(a, static_cast<int>(i));
    const GrayImage gb = colmap->ReadGray(b, static_cast<int>(i));
    EXPECT_EQ(ga.data, gb.data) << va.name;
  }
  EXPECT_EQ(SelectSourcesAuto(a, 0, 20, 1.0), SelectSourcesAuto(b, 0, 20, 1.0));
}

TEST(ColmapNative, MapsAreByteEqualToColmapMp) {
  TempFolder tmp;
  MakeGreyScene(tmp / "ours");
  ExpectBothFrontEndsWriteTheSameMaps(tmp);
}

// mvs::Model keeps no reprojection errors; the native loader takes them from the model files,
// each with its own point, so a model of less exact poses widens the depth check alike in both
// front ends. On this scene the widened check writes other maps than 1 % would (without the
// errors the native maps differed).
TEST(ColmapNative, ReadsThePointsReprojectionErrorsLikeColmapMp) {
  TempFolder tmp;
  MakeGreyScene(tmp / "ours");
  // Less exact poses, a different error for each point (2 to 3 px).
  test::SetSparsePointErrors(tmp / "ours/sparse", [](size_t i) { return 2.0 + static_cast<double>(i % 100) / 100; });
  const DenseWorkspace a = MpMvsWorkspaceIo().Load(tmp / "ours", -1);
  const DenseWorkspace b = MakeColmapWorkspaceIo()->Load(tmp / "ours", -1);
  ASSERT_GT(a.model.points.size(), 10u);
  EXPECT_EQ(PointErrors(a), PointErrors(b));
  const DepthCheckTolerance ta = DepthCheckToleranceOf(a);
  EXPECT_GT(ta.relative, 0.02f);
  EXPECT_EQ(ta.relative, DepthCheckToleranceOf(b).relative);
  ExpectBothFrontEndsWriteTheSameMaps(tmp);
}

}  // namespace
}  // namespace mpmvs

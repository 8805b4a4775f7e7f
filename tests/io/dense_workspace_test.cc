#include "colmap_ext/io/dense_workspace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "colmap_ext/util/file_util.h"
#include "tests/io_test_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;
using test::TempDir;
using test::WriteText;

// Hand-made scene with known __auto__ answers. All cameras look along +z (R = I), centres
// on the x axis: image 0 at x=0, image 1 at x=0.01 (baseline too small: ~0.1 degrees),
// image 2 at x=1 (~11 degrees), image 3 at x=2 (~22 degrees), image 4 far away and sees
// nothing. Points lie at depth 5 around the z axis.
//   points 0..9:   seen by 0, 1, 2, 3
//   points 10..14: seen by 0, 2
//   points 15..17: seen by 0 and 3, with image 0 listed twice in the track. COLMAP counts
//                  each pair of track entries, so each such point adds 2 to shared(0,3).
// shared(0,1) = 10, shared(0,2) = 15, shared(0,3) = 10 + 3 * 2 = 16: image 3 ranks first,
// which it would not if repeated observations counted once (13).
SparseModel MakeOverlapModel() {
  SparseModel model;
  SparseCamera camera;
  camera.camera_id = 1;
  camera.model_id = kPinholeModelId;
  camera.width = 40;
  camera.height = 30;
  camera.params = {50, 50, 20, 15};
  model.cameras = {camera};
  const double centres_x[5] = {0, 0.01, 1, 2, 100};
  for (int i = 0; i < 5; ++i) {
    SparseImage image;
    image.image_id = 10 + i;  // ids differ from model indices on purpose
    image.camera_id = 1;
    image.tvec[0] = -centres_x[i];
    image.name = "img" + std::to_string(i) + ".png";
    model.images.push_back(image);
  }
  const auto add_point = [&](double x, double y, double z, std::vector<int> views) {
    SparsePoint3D point;
    point.point3D_id = model.points.size() + 1;
    point.xyz[0] = x;
    point.xyz[1] = y;
    point.xyz[2] = z;
    for (int view : views) point.track.push_back({static_cast<uint32_t>(10 + view), 0});
    model.points.push_back(point);
  };
  for (int i = 0; i < 10; ++i) add_point(0.1 * i, 0.05 * i, 5 + 0.1 * i, {0, 1, 2, 3});
  for (int i = 0; i < 5; ++i) add_point(-0.1 * i, 0, 4.5 + 0.1 * i, {0, 2});
  add_point(0.2, 0.1, 5, {0, 0, 3});
  add_point(0.3, 0.1, 5, {0, 3, 0});
  add_point(0.4, 0.1, 5, {3, 0, 0});
  return model;
}

// A workspace folder with images/, sparse/ (binary), stereo/ and grey PNGs of the camera
// sizes.
void MakeWorkspace(const std::string& path, const SparseModel& model) {
  CreateDirectories(path + "/images");
  CreateDirectories(path + "/sparse");
  CreateDirectories(path + "/stereo/depth_maps");
  WriteSparseModelBinary(model, path + "/sparse");
  for (const SparseImage& image : model.images) {
    const SparseCamera& camera = model.cameras[model.FindCamera(image.camera_id)];
    const int w = static_cast<int>(camera.width), h = static_cast<int>(camera.height);
    std::vector<uint8_t> gray(static_cast<size_t>(w) * h);
    for (int r = 0; r < h; ++r) {
      for (int c = 0; c < w; ++c) gray[r * w + c] = static_cast<uint8_t>((r * 7 + c * 3) % 256);
    }
    CreateDirectories(ParentPath(path + "/images/" + image.name));
    WriteGrayPng(path + "/images/" + image.name, w, h, gray);
  }
}

TEST(DenseWorkspace, LoadsViewsInImagesBinOrder) {
  TempDir dir;
  SparseModel model = MakeOverlapModel();
  model.images[2].name = "sub/img2.png";
  // Rotated image: 90 degrees about z.
  model.images[1].qvec[0] = std::sqrt(0.5);
  model.images[1].qvec[3] = std::sqrt(0.5);
  MakeWorkspace(dir.path(), model);
  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), -1);
  ASSERT_EQ(ws.views.size(), 5u);
  EXPECT_EQ(ws.path, dir.path());
  EXPECT_EQ(ws.views[2].name, "sub/img2.png");
  EXPECT_EQ(ws.views[2].image_path, dir / "images/sub/img2.png");
  EXPECT_EQ(ws.FindView("sub/img2.png"), 2);
  EXPECT_EQ(ws.FindView("nope"), -1);
  EXPECT_EQ(ws.views[0].width, 40);
  EXPECT_EQ(ws.views[0].original_height, 30);
  const double K[9] = {50, 0, 20, 0, 50, 15, 0, 0, 1};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(ws.views[0].K[i], K[i]);
  EXPECT_NEAR(ws.views[1].R[1], -1, 1e-15);
  EXPECT_NEAR(ws.views[1].R[3], 1, 1e-15);
  EXPECT_EQ(ws.views[3].T[0], -2);
  EXPECT_EQ(ws.DepthMapPath(2, "geometric"),
            dir / "stereo/depth_maps/sub/img2.png.geometric.bin");
  EXPECT_EQ(ws.NormalMapPath(0, "photometric"),
            dir / "stereo/normal_maps/img0.png.photometric.bin");
  EXPECT_EQ(ws.ConsistencyGraphPath(0, "geometric"),
            dir / "stereo/consistency_graphs/img0.png.geometric.bin");
  EXPECT_EQ(ws.IntermediateDir(), dir / "stereo/mpmvs");
  const GrayImage gray = ws.ReadGray(2);
  EXPECT_EQ(gray.width, 40);
  EXPECT_EQ(gray.At(2, 3), (2 * 7 + 3 * 3) % 256);
}

TEST(DenseWorkspace, AutoSourceSelectionKnownAnswers) {
  TempDir dir;
  MakeWorkspace(dir.path(), MakeOverlapModel());
  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), -1);
  // Image 1 is dropped (angle below 1 degree); 3 (16 shared) before 2 (15 shared).
  EXPECT_EQ(SelectSourcesAuto(ws, 0, 20, 1.0), (std::vector<int>{3, 2}));
  EXPECT_EQ(SelectSourcesAuto(ws, 0, 1, 1.0), (std::vector<int>{3}));
  // Angle threshold 0: image 1 is kept too (10 shared).
  EXPECT_EQ(SelectSourcesAuto(ws, 0, 20, 0.0), (std::vector<int>{3, 2, 1}));
  // 15 degrees: only image 3 (~22 degrees) passes.
  EXPECT_EQ(SelectSourcesAuto(ws, 0, 20, 15.0), (std::vector<int>{3}));
  // Image 1 shares 10 points with 0, 2, 3; ties are broken by index; 0 is too close.
  EXPECT_EQ(SelectSourcesAuto(ws, 1, 20, 1.0), (std::vector<int>{2, 3}));
  EXPECT_TRUE(SelectSourcesAuto(ws, 4, 20, 1.0).empty());
  EXPECT_THROW(SelectSourcesAuto(ws, 5, 20, 1.0), Error);
}

TEST(DenseWorkspace, DepthRangesFromSparsePoints) {
  TempDir dir;
  MakeWorkspace(dir.path(), MakeOverlapModel());
  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), -1);
  // Image 0 sees depths 4.5 .. 5.9 (< 100 entries: first and last element).
  EXPECT_NEAR(ws.views[0].depth_min, 0.75 * 4.5, 1e-12);
  // In float like COLMAP's mvs::Model::ComputeDepthRanges (5.9f * 1.25f, not 5.9 * 1.25).
  EXPECT_EQ(ws.views[0].depth_max, 5.9f * 1.25f);
  EXPECT_NEAR(ws.views[1].depth_min, 0.75 * 5.0, 1e-12);
  EXPECT_EQ(ws.views[4].depth_min, -1);
  EXPECT_EQ(ws.views[4].depth_max, -1);
}

TEST(DenseWorkspace, DepthRangePercentilesLikeColmap) {
  // 100 points at depths 1..100 plus 3 behind the camera (ignored). COLMAP indexes with
  // size * 0.99f in float: 99 (depth 100), not 98 as exact arithmetic would give.
  TempDir dir;
  SparseModel model = MakeOverlapModel();
  model.points.clear();
  for (int i = 1; i <= 100; ++i) {
    SparsePoint3D point;
    point.point3D_id = i;
    point.xyz[2] = i;
    point.track = {{10, 0}};
    model.points.push_back(point);
  }
  for (int i = 1; i <= 3; ++i) {
    SparsePoint3D point;
    point.point3D_id = 1000 + i;
    point.xyz[2] = -i;
    point.track = {{10, 0}};
    model.points.push_back(point);
  }
  MakeWorkspace(dir.path(), model);
  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), -1);
  EXPECT_NEAR(ws.views[0].depth_min, 0.75 * 2, 1e-12);  // index floor(100 * 0.01f) = 1
  EXPECT_NEAR(ws.views[0].depth_max, 1.25 * 100, 1e-12);
}

TEST(DenseWorkspace, MaxImageSizeScalesSizesAndK) {
  TempDir dir;
  SparseModel model = MakeOverlapModel();
  model.cameras[0].width = 463;
  model.cameras[0].height = 370;
  model.cameras[0].params = {1246.5, 1240.25, 198.25, 185.5};
  SparseCamera simple;
  simple.camera_id = 2;
  simple.model_id = kSimplePinholeModelId;
  simple.width = 120;
  simple.height = 300;
  simple.params = {100, 60, 150};
  model.cameras.push_back(simple);
  model.images[1].camera_id = 2;
  MakeWorkspace(dir.path(), model);

  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), 200);
  const DenseView& view = ws.views[0];
  EXPECT_EQ(view.original_width, 463);
  EXPECT_EQ(view.original_height, 370);
  EXPECT_EQ(view.width, 200);
  EXPECT_EQ(view.height, 160);  // round(370 * 200 / 463) = round(159.83)
  EXPECT_NEAR(view.K[0], 1246.5 * 200 / 463, 1e-9);
  EXPECT_NEAR(view.K[2], 198.25 * 200 / 463, 1e-9);
  EXPECT_NEAR(view.K[4], 1240.25 * 160 / 370, 1e-9);
  EXPECT_NEAR(view.K[5], 185.5 * 160 / 370, 1e-9);
  EXPECT_EQ(view.K[8], 1);
  // SIMPLE_PINHOLE, portrait: height is the limit.
  const DenseView& portrait = ws.views[1];
  EXPECT_EQ(portrait.width, 80);
  EXPECT_EQ(portrait.height, 200);
  EXPECT_NEAR(portrait.K[0], 100 * 80.0 / 120, 1e-9);
  EXPECT_NEAR(portrait.K[4], 100 * 200.0 / 300, 1e-9);
  EXPECT_NEAR(portrait.K[2], 60 * 80.0 / 120, 1e-9);
  EXPECT_NEAR(portrait.K[5], 150 * 200.0 / 300, 1e-9);
  // ReadGray resizes to the scaled size.
  const GrayImage gray = ws.ReadGray(0);
  EXPECT_EQ(gray.width, 200);
  EXPECT_EQ(gray.height, 160);
  EXPECT_EQ(ws.ReadGray(1).height, 200);
  // ReadRgb (chroma guide) the same way; a grey file gives R = G = B.
  const RgbImage rgb = ws.ReadRgb(0);
  EXPECT_EQ(rgb.width, 200);
  EXPECT_EQ(rgb.height, 160);
  ASSERT_EQ(rgb.data.size(), 3u * 200 * 160);
  for (size_t i = 0; i < rgb.data.size(); i += 3) {
    ASSERT_EQ(rgb.data[i], rgb.data[i + 1]);
    ASSERT_EQ(rgb.data[i + 2], rgb.data[i + 1]);
  }

  // Limits at or above the image size, or <= 0, change nothing.
  for (int max_size : {463, 1000, 0, -1}) {
    const DenseWorkspace same = LoadDenseWorkspace(dir.path(), max_size);
    EXPECT_EQ(same.views[0].width, 463);
    EXPECT_EQ(same.views[0].K[0], 1246.5);
    EXPECT_EQ(same.ReadGray(0).width, 463);
  }
}

// ---- errors ------------------------------------------------------------------------------

TEST(DenseWorkspaceError, MissingWorkspaceAndSubFolders) {
  TempDir dir;
  EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir / "nope", -1),
                     dir / "nope: dense workspace folder does not exist");
  MakeWorkspace(dir.path(), MakeOverlapModel());
  for (const std::string sub : {"images", "sparse", "stereo"}) {
    fs::rename(dir / sub, dir / (sub + "_moved"));
    EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1), dir / sub + ": folder is missing");
    EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1), "colmap image_undistorter");
    fs::rename(dir / (sub + "_moved"), dir / sub);
  }
  fs::remove(dir / "sparse/points3D.bin");
  EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1), "points3D.bin: file does not exist");
  EXPECT_NO_THROW(WriteSparseModelText(MakeOverlapModel(), dir / "sparse"));
  EXPECT_EQ(LoadDenseWorkspace(dir.path(), -1).views.size(), 5u);  // text fallback
}

TEST(DenseWorkspaceError, DistortedCameraNeedsUndistortion) {
  TempDir dir;
  SparseModel model = MakeOverlapModel();
  SparseCamera radial;
  radial.camera_id = 9;
  radial.model_id = CameraModelIdFromName("SIMPLE_RADIAL");
  radial.width = 40;
  radial.height = 30;
  radial.params = {50, 20, 15, 0.01};
  model.cameras.push_back(radial);
  model.images[3].camera_id = 9;
  MakeWorkspace(dir.path(), model);
  EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1),
                     dir / "sparse/cameras.bin: camera 9 of image 'img3.png' has model SIMPLE_RADIAL");
  EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1),
                     "must be undistorted first with `colmap image_undistorter");
}

// Issue 35, defect 6: an image name that climbs out of images/ ("../x/view.png") or is
// absolute would put maps and states outside stereo/ (a depth and a normal map could even
// resolve to one file): refused, naming the file and the name.
TEST(DenseWorkspaceError, ImageNameOutsideTheWorkspaceIsRefused) {
  for (const std::string name : {"../x/view.png", "sub/../../view.png", "/tmp/view.png", "sub/../view.png"}) {
    TempDir dir;
    SparseModel model = MakeOverlapModel();
    model.images[1].name = name;
    MakeWorkspace(dir.path(), model);
    EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1), dir / "sparse/images.bin: image '" + name + "'");
    EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1), "outside the workspace");
  }
  // Names with sub-folders and dots inside them stay valid.
  TempDir dir;
  SparseModel model = MakeOverlapModel();
  model.images[1].name = "sub/..dots../view.1.png";
  MakeWorkspace(dir.path(), model);
  EXPECT_NO_THROW(LoadDenseWorkspace(dir.path(), -1));
}

TEST(DenseWorkspaceError, BadCameraOrPose) {
  TempDir dir;
  SparseModel model = MakeOverlapModel();
  model.cameras[0].params[1] = 0;
  MakeWorkspace(dir.path(), model);
  EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1), "cameras.bin: camera 1 has a non-positive focal length");
  model = MakeOverlapModel();
  model.images[2].qvec[0] = 0;
  WriteSparseModelBinary(model, dir / "sparse");
  EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1), "images.bin: image 'img2.png' has an invalid pose");
  model = MakeOverlapModel();
  model.images.clear();
  model.points.clear();
  WriteSparseModelBinary(model, dir / "sparse");
  EXPECT_MPMVS_ERROR(LoadDenseWorkspace(dir.path(), -1), "images.bin: the sparse model has no images");
}

TEST(DenseWorkspaceError, BadImagesAreReportedByReadGray) {
  TempDir dir;
  MakeWorkspace(dir.path(), MakeOverlapModel());
  // Images are only checked when read, so loading succeeds.
  fs::remove(dir / "images/img1.png");
  test::WriteText(dir / "images/img2.png", "this is not a PNG file at all, just some bytes");
  WriteGrayPng(dir / "images/img3.png", 41, 30, std::vector<uint8_t>(41 * 30, 9));
  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), -1);
  EXPECT_NO_THROW(ws.ReadGray(0));
  EXPECT_MPMVS_ERROR(ws.ReadGray(1), dir / "images/img1.png: image file is missing");
  EXPECT_MPMVS_ERROR(ws.ReadGray(2), dir / "images/img2.png: ");
  EXPECT_MPMVS_ERROR(ws.ReadGray(3),
                     dir / "images/img3.png: image is 41x30 but its camera in the sparse model is 40x30");
  EXPECT_THROW(ws.ReadGray(17), Error);
  EXPECT_MPMVS_ERROR(ws.ReadRgb(1), dir / "images/img1.png: image file is missing");
  EXPECT_MPMVS_ERROR(ws.ReadRgb(3),
                     dir / "images/img3.png: image is 41x30 but its camera in the sparse model is 40x30");
}

// ---- patch-match.cfg ---------------------------------------------------------------------

TEST(PatchMatchConfig, AllAutoAndExplicitLists) {
  TempDir dir;
  MakeWorkspace(dir.path(), MakeOverlapModel());
  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), -1);
  const std::string cfg = dir / "stereo/patch-match.cfg";
  WriteText(cfg,
            "# comment\n"
            "\n"
            "  img0.png  \r\n"
            "__auto__, 20\n"
            "img1.png\n"
            "__all__\n"
            "   # indented comment between reference and sources\n"
            "img2.png\n"
            " img3.png ,img0.png,  img2.png, img3.png\n"
            "img4.png\n"
            "__auto__,1\n");
  const std::vector<StereoProblem> problems = ReadPatchMatchConfig(cfg, ws, 1.0);
  ASSERT_EQ(problems.size(), 4u);
  EXPECT_EQ(problems[0].ref, 0);
  EXPECT_EQ(problems[0].src, (std::vector<int>{3, 2}));
  EXPECT_EQ(problems[1].ref, 1);
  EXPECT_EQ(problems[1].src, (std::vector<int>{0, 2, 3, 4}));
  EXPECT_EQ(problems[2].ref, 2);
  EXPECT_EQ(problems[2].src, (std::vector<int>{3, 0}));  // self and repeats dropped
  EXPECT_EQ(problems[3].ref, 4);
  EXPECT_TRUE(problems[3].src.empty());  // kept; the caller warns and skips
  // The min triangulation angle is passed through to __auto__.
  EXPECT_EQ(ReadPatchMatchConfig(cfg, ws, 0.0)[0].src, (std::vector<int>{3, 2, 1}));
  WriteText(cfg, "# nothing\n\n");
  EXPECT_TRUE(ReadPatchMatchConfig(cfg, ws, 1.0).empty());
}

TEST(PatchMatchConfig, MalformedConfigNamesFileAndLine) {
  TempDir dir;
  MakeWorkspace(dir.path(), MakeOverlapModel());
  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), -1);
  const std::string cfg = dir / "stereo/patch-match.cfg";
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {"unknown.png\n__all__\n", "line 1: reference image 'unknown.png' is not in the sparse model"},
      {"img0.png\nimg1.png, other.png\n", "line 2: source image 'other.png' is not in the sparse model"},
      {"img0.png\nimg1.png,,img2.png\n", "line 2: empty image name"},
      {"img0.png\n__all__\n\nimg1.png\n# only a comment\n",
       "line 4: reference image 'img1.png' has no source line"},
      {"img0.png\n", "line 1: reference image 'img0.png' has no source line"},
      {"img0.png\n__auto__\n", "line 2: expected '__auto__, N'"},
      {"img0.png\n__auto__, x\n", "line 2: expected '__auto__, N'"},
      {"img0.png\n__auto__, 0\n", "line 2: expected '__auto__, N'"},
      {"img0.png\n__auto__, -5\n", "line 2: expected '__auto__, N'"},
      {"img0.png\n__auto__, 5x\n", "line 2: expected '__auto__, N'"},
      {"img0.png\n__auto__, 5, 6\n", "line 2: expected '__auto__, N'"},
      {"img0.png\n__auto__, 2.5\n", "line 2: expected '__auto__, N'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    WriteText(cfg, c.text);
    EXPECT_MPMVS_ERROR(ReadPatchMatchConfig(cfg, ws, 1.0), cfg + ": " + c.expected);
  }
  EXPECT_MPMVS_ERROR(ReadPatchMatchConfig(dir / "stereo/none.cfg", ws, 1.0),
                     "none.cfg: file does not exist");
}

// ---- real data ---------------------------------------------------------------------------

TEST(DenseWorkspaceDataset, DollsAsWorkspace) {
  MPMVS_REQUIRE_DATASET(dataset, "middlebury2005_dolls");
  TempDir dir;
  // File by file: the dataset is read-only and fs::copy of a folder keeps its permissions.
  for (const std::string sub : {"images", "sparse"}) {  // sparse/ is a text model
    CreateDirectories(dir / sub);
    for (const auto& entry : fs::directory_iterator(dataset + "/" + sub)) {
      fs::copy_file(entry.path(), dir / (sub + "/" + entry.path().filename().string()));
    }
  }
  CreateDirectories(dir / "stereo");
  const DenseWorkspace ws = LoadDenseWorkspace(dir.path(), -1);
  ASSERT_EQ(ws.views.size(), 2u);
  EXPECT_EQ(ws.views[1].name, "view5.png");
  EXPECT_EQ(ws.views[1].T[0], -0.16);
  // GT depth covers 1.40 .. 2.34 m (gt/depth_range.txt); the sparse range, stretched by
  // 0.75 / 1.25, must contain it.
  for (const DenseView& view : ws.views) {
    EXPECT_GT(view.depth_min, 0.5);
    EXPECT_LT(view.depth_min, 1.40);
    EXPECT_GT(view.depth_max, 2.34);
    EXPECT_LT(view.depth_max, 4.0);
  }
  WriteText(dir / "stereo/patch-match.cfg", "view1.png\n__auto__, 20\nview5.png\n__auto__, 20\n");
  const std::vector<StereoProblem> problems =
      ReadPatchMatchConfig(dir / "stereo/patch-match.cfg", ws, 1.0);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].src, std::vector<int>{1});
  EXPECT_EQ(problems[1].src, std::vector<int>{0});
  const DenseWorkspace small = LoadDenseWorkspace(dir.path(), 200);
  const GrayImage gray = small.ReadGray(0);
  EXPECT_EQ(gray.width, 200);
  EXPECT_EQ(gray.height, 160);
}

}  // namespace
}  // namespace mpmvs

#include "colmap_ext/io/sparse_model.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>

#include "colmap_ext/util/file_util.h"
#include "tests/io_test_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

using test::ExpectModelsEqual;
using test::MakeSampleModel;
using test::TempDir;
using test::WriteText;

TEST(CameraModel, TableOfColmap38Models) {
  const char* names[] = {"SIMPLE_PINHOLE", "PINHOLE",          "SIMPLE_RADIAL",
                         "RADIAL",         "OPENCV",           "OPENCV_FISHEYE",
                         "FULL_OPENCV",    "FOV",              "SIMPLE_RADIAL_FISHEYE",
                         "RADIAL_FISHEYE", "THIN_PRISM_FISHEYE"};
  const int num_params[] = {3, 4, 4, 5, 8, 8, 12, 5, 4, 5, 12};
  for (int id = 0; id <= 10; ++id) {
    EXPECT_EQ(CameraModelName(id), names[id]);
    EXPECT_EQ(CameraModelIdFromName(names[id]), id);
    EXPECT_EQ(CameraModelNumParams(id), num_params[id]) << names[id];
  }
  EXPECT_EQ(kSimplePinholeModelId, 0);
  EXPECT_EQ(kPinholeModelId, 1);
  EXPECT_EQ(CameraModelName(-1), "UNKNOWN");
  EXPECT_EQ(CameraModelName(1000), "UNKNOWN");
  EXPECT_EQ(CameraModelIdFromName("pinhole"), -1);
  EXPECT_EQ(CameraModelNumParams(99), -1);
}

TEST(SparseModel, BinaryRoundTrip) {
  TempDir dir;
  const SparseModel model = MakeSampleModel();
  WriteSparseModelBinary(model, dir.path());
  ExpectModelsEqual(model, ReadSparseModelBinary(dir.path()));
  ExpectModelsEqual(model, ReadSparseModel(dir.path()));
  EXPECT_TRUE(HasBinarySparseModel(dir.path()));
}

TEST(SparseModel, TextRoundTripIsExact) {
  TempDir dir;
  const SparseModel model = MakeSampleModel();
  WriteSparseModelText(model, dir.path());
  ExpectModelsEqual(model, ReadSparseModelText(dir.path()));
  ExpectModelsEqual(model, ReadSparseModel(dir.path()));
  EXPECT_FALSE(HasBinarySparseModel(dir.path()));
  EXPECT_EQ(SparseModelFilePath(dir.path(), "cameras"), dir / "cameras.txt");
}

TEST(SparseModel, BinaryIsPreferredOverText) {
  TempDir dir;
  SparseModel text_model = MakeSampleModel();
  text_model.images[0].name = "from_text.png";
  WriteSparseModelText(text_model, dir.path());
  WriteSparseModelBinary(MakeSampleModel(), dir.path());
  EXPECT_EQ(ReadSparseModel(dir.path()).images[0].name, "a.png");
  EXPECT_EQ(SparseModelFilePath(dir.path(), "images"), dir / "images.bin");
  // Without a complete binary model the text files are read.
  std::filesystem::remove(dir / "points3D.bin");
  EXPECT_EQ(ReadSparseModel(dir.path()).images[0].name, "from_text.png");
}

TEST(SparseModel, TextFormatDetails) {
  TempDir dir;
  WriteText(dir / "cameras.txt",
            "# comment\n\n  # indented comment\n"
            "1 SIMPLE_PINHOLE 100 80 90 50 40\r\n"
            "2 PINHOLE 100 80 90 91 50 40\n");
  // Second line of image 1 is empty; image 2 has -1 entries; image 3 has no second line
  // at the end of the file.
  WriteText(dir / "images.txt",
            "# IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
            "1 1 0 0 0 0 0 0 1 first image.png\n"
            "\n"
            "2 1 0 0 0 1 0 0 2 dir/second.png\n"
            "1.5 2.5 -1 3 4 7\n"
            "3 1 0 0 0 2 0 0 2 third.png");
  WriteText(dir / "points3D.txt", "# no track\n7 1 2 3 255 128 0 0.5\n8 0 0 1 1 2 3 0 2 1\n");
  const SparseModel model = ReadSparseModel(dir.path());
  ASSERT_EQ(model.cameras.size(), 2u);
  EXPECT_EQ(model.cameras[0].model_id, kSimplePinholeModelId);
  EXPECT_EQ(model.cameras[0].params, (std::vector<double>{90, 50, 40}));
  ASSERT_EQ(model.images.size(), 3u);
  EXPECT_EQ(model.images[0].name, "first image.png");
  EXPECT_TRUE(model.images[0].points2D.empty());
  EXPECT_EQ(model.images[1].name, "dir/second.png");
  ASSERT_EQ(model.images[1].points2D.size(), 2u);
  EXPECT_EQ(model.images[1].points2D[0].point3D_id, UINT64_MAX);
  EXPECT_EQ(model.images[1].points2D[1].point3D_id, 7u);
  EXPECT_EQ(model.images[1].points2D[1].x, 3);
  EXPECT_EQ(model.images[2].name, "third.png");
  EXPECT_EQ(model.images[2].tvec[0], 2);
  ASSERT_EQ(model.points.size(), 2u);
  EXPECT_TRUE(model.points[0].track.empty());
  EXPECT_EQ(model.points[0].rgb[1], 128);
  ASSERT_EQ(model.points[1].track.size(), 1u);
  EXPECT_EQ(model.points[1].track[0].image_id, 2u);
  EXPECT_EQ(model.points[1].track[0].point2D_idx, 1u);
  EXPECT_EQ(model.FindImageByName("third.png"), 2);
  EXPECT_EQ(model.FindImageById(2), 1);
  EXPECT_EQ(model.FindCamera(2), 1);
  EXPECT_EQ(model.FindCamera(5), -1);
  EXPECT_EQ(model.FindImageByName("nope"), -1);
}

// ---- quaternions -----------------------------------------------------------------------

void ExpectRotation(const double R[9]) {
  // Orthonormal with determinant +1.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += R[3 * i + k] * R[3 * j + k];
      EXPECT_NEAR(dot, i == j ? 1 : 0, 1e-12);
    }
  }
  const double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                     R[2] * (R[3] * R[7] - R[4] * R[6]);
  EXPECT_NEAR(det, 1, 1e-12);
}

TEST(Quaternion, KnownRotations) {
  // 90 degrees about z: x axis -> y axis (Hamilton convention, active rotation).
  const double qz[4] = {std::sqrt(0.5), 0, 0, std::sqrt(0.5)};
  double R[9];
  QuaternionToRotationMatrix(qz, R);
  const double expected_z[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(R[i], expected_z[i], 1e-15) << i;
  // 90 degrees about x: y -> z.
  const double qx[4] = {std::sqrt(0.5), std::sqrt(0.5), 0, 0};
  QuaternionToRotationMatrix(qx, R);
  const double expected_x[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(R[i], expected_x[i], 1e-15) << i;
  // Not normalised: scaled quaternion gives the same matrix.
  const double q_scaled[4] = {2 * std::sqrt(0.5), 2 * std::sqrt(0.5), 0, 0};
  double R_scaled[9];
  QuaternionToRotationMatrix(q_scaled, R_scaled);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(R_scaled[i], expected_x[i], 1e-15);
  // Identity.
  const double q_identity[4] = {1, 0, 0, 0};
  QuaternionToRotationMatrix(q_identity, R);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(R[i], i % 4 == 0 ? 1 : 0);
}

TEST(Quaternion, MatrixRoundTripCoversAllBranches) {
  std::mt19937 rng(42);
  std::normal_distribution<double> normal;
  std::vector<std::array<double, 4>> quaternions = {
      {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1},  // 180 degree turns
      {0.01, 0.99, 0.1, 0}, {0.01, 0.1, 0.99, 0}, {0.01, 0, 0.1, 0.99}};
  for (int i = 0; i < 200; ++i) {
    quaternions.push_back({normal(rng), normal(rng), normal(rng), normal(rng)});
  }
  for (auto q : quaternions) {
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const double sign = q[0] < 0 ? -1 : 1;
    for (double& v : q) v *= sign / norm;
    double R[9];
    QuaternionToRotationMatrix(q.data(), R);
    ExpectRotation(R);
    double q2[4];
    RotationMatrixToQuaternion(R, q2);
    EXPECT_GE(q2[0], 0);
    if (q[0] > 1e-9) {
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(q2[k], q[k], 1e-12);
    } else {
      // w = 0: q and -q are the same rotation; compare the matrices.
      double R2[9];
      QuaternionToRotationMatrix(q2, R2);
      for (int k = 0; k < 9; ++k) EXPECT_NEAR(R2[k], R[k], 1e-12);
    }
  }
}

// ---- bad input ---------------------------------------------------------------------------

TEST(SparseModelError, MissingFolderAndFiles) {
  TempDir dir;
  EXPECT_MPMVS_ERROR(ReadSparseModel(dir / "nope"), "nope");
  EXPECT_MPMVS_ERROR(ReadSparseModel(dir.path()), "no sparse model");
  WriteSparseModelBinary(MakeSampleModel(), dir.path());
  std::filesystem::remove(dir / "images.bin");
  EXPECT_MPMVS_ERROR(ReadSparseModel(dir.path()), "images.bin");
  EXPECT_MPMVS_ERROR(ReadSparseModelText(dir.path()), "cameras.txt");
}

TEST(SparseModelError, TruncatedBinaryFilesThrow) {
  TempDir dir;
  WriteSparseModelBinary(MakeSampleModel(), dir.path());
  for (const std::string name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    const std::vector<uint8_t> bytes = ReadFileBytes(dir / name);
    const size_t n = bytes.size();
    for (size_t cut : {size_t{0}, size_t{3}, size_t{8}, size_t{9}, size_t{20}, n / 3, n / 2,
                       n - 9, n - 1}) {
      SCOPED_TRACE(name + " cut at " + std::to_string(cut));
      test::WriteBytes(dir / name, std::vector<uint8_t>(bytes.begin(), bytes.begin() + cut));
      EXPECT_MPMVS_ERROR(ReadSparseModelBinary(dir.path()), name);
    }
    // Extra bytes after the last record are corruption too.
    std::vector<uint8_t> longer = bytes;
    longer.push_back(0);
    test::WriteBytes(dir / name, longer);
    EXPECT_MPMVS_ERROR(ReadSparseModelBinary(dir.path()), name);
    test::WriteBytes(dir / name, bytes);
  }
  ExpectModelsEqual(MakeSampleModel(), ReadSparseModelBinary(dir.path()));
}

// Byte offsets in the sample model's files (see io_test_util.h).
constexpr size_t kFirstCameraModelOffset = 8 + 4;
constexpr size_t kFirstImageNumPoints2DOffset = 8 + 4 + 56 + 4 + 6;  // after "a.png\0"
constexpr size_t kFirstPointTrackLengthOffset = 8 + 8 + 24 + 3 + 8;

TEST(SparseModelError, AbsurdCountsThrowWithoutAllocating) {
  TempDir dir;
  WriteSparseModelBinary(MakeSampleModel(), dir.path());
  struct Case {
    std::string file;
    size_t offset;
    uint64_t value;
  };
  const Case cases[] = {
      {"cameras.bin", 0, uint64_t{1} << 60},
      {"cameras.bin", 0, UINT64_MAX},
      {"images.bin", 0, uint64_t{1} << 60},
      {"images.bin", kFirstImageNumPoints2DOffset, uint64_t{1} << 62},
      {"points3D.bin", 0, uint64_t{1} << 63},
      {"points3D.bin", kFirstPointTrackLengthOffset, uint64_t{1} << 61},
      {"points3D.bin", kFirstPointTrackLengthOffset, 1000},  // plausible but too long
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file + " offset " + std::to_string(c.offset));
    const std::vector<uint8_t> original = ReadFileBytes(dir / c.file);
    std::vector<uint8_t> bytes = original;
    test::PutValue<uint64_t>(&bytes, c.offset, c.value);
    test::WriteBytes(dir / c.file, bytes);
    const auto start = std::chrono::steady_clock::now();
    EXPECT_MPMVS_ERROR(ReadSparseModelBinary(dir.path()), c.file);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
    test::WriteBytes(dir / c.file, original);
  }
}

TEST(SparseModelError, RandomCorruptionThrowsErrorOrReads) {
  // Flipped bytes must either give a model or an mpmvs::Error, never a crash, a hang or
  // another exception type (run under ASan to see out-of-bounds reads).
  TempDir dir;
  WriteSparseModelBinary(MakeSampleModel(), dir.path());
  std::mt19937 rng(11);
  for (const std::string name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    const std::vector<uint8_t> original = ReadFileBytes(dir / name);
    for (int trial = 0; trial < 100; ++trial) {
      std::vector<uint8_t> bytes = original;
      const int num_flips = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < num_flips; ++k) {
        bytes[rng() % bytes.size()] = static_cast<uint8_t>(rng());
      }
      test::WriteBytes(dir / name, bytes);
      try {
        ReadSparseModelBinary(dir.path());
      } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find(dir.path()), std::string::npos) << error.what();
      }
    }
    test::WriteBytes(dir / name, original);
  }
}

TEST(SparseModelError, UnknownBinaryCameraModel) {
  TempDir dir;
  WriteSparseModelBinary(MakeSampleModel(), dir.path());
  std::vector<uint8_t> bytes = ReadFileBytes(dir / "cameras.bin");
  test::PutValue<int32_t>(&bytes, kFirstCameraModelOffset, 77);
  test::WriteBytes(dir / "cameras.bin", bytes);
  EXPECT_MPMVS_ERROR(ReadSparseModelBinary(dir.path()), "cameras.bin: camera 3 has unknown model id 77");
}

TEST(SparseModelError, BadTextLinesNameFileAndLine) {
  TempDir dir;
  const std::string good_cameras = "1 PINHOLE 100 80 90 91 50 40\n";
  const std::string good_images = "1 1 0 0 0 0 0 0 1 a.png\n1 2 -1\n";
  const std::string good_points = "5 0 0 1 1 2 3 0.1 1 0\n";
  struct Case {
    std::string cameras, images, points, expected;
  };
  const Case cases[] = {
      {"1 PINHOLEX 100 80 90 91 50 40\n", good_images, good_points,
       "cameras.txt: line 1: unknown camera model 'PINHOLEX'"},
      {"# c\n1 PINHOLE 100 80 90 91 50\n", good_images, good_points,
       "cameras.txt: line 2: camera model PINHOLE needs 4 parameters, found 3"},
      {"1 PINHOLE 100x 80 90 91 50 40\n", good_images, good_points, "cameras.txt: line 1: bad width"},
      {"1 PINHOLE 100 80 90 91 50 4o\n", good_images, good_points, "cameras.txt: line 1"},
      {"-1 PINHOLE 100 80 90 91 50 40\n", good_images, good_points, "cameras.txt: line 1: bad camera id"},
      {"1 PINHOLE\n", good_images, good_points, "cameras.txt: line 1"},
      {good_cameras, "1 1 0 0 0 0 0 0 1\n\n", good_points, "images.txt: line 1"},
      {good_cameras, "1 1 0 zero 0 0 0 0 1 a.png\n\n", good_points,
       "images.txt: line 1: bad quaternion 'zero'"},
      {good_cameras, "1 1 0 0 0 0 0 0 1 a.png\n1 2\n", good_points,
       "images.txt: line 2: 2D point line of image 'a.png' must hold X Y POINT3D_ID triples"},
      {good_cameras, "1 1 0 0 0 0 0 0 1 a.png\n1 2 -2\n", good_points,
       "images.txt: line 2: bad POINT3D_ID '-2'"},
      {good_cameras, "1 1 0 0 0 0 0 0 1 a.png\n# comment\n", good_points, "images.txt: line 2"},
      {good_cameras, good_images, "5 0 0 1 256 2 3 0.1 1 0\n", "points3D.txt: line 1: bad colour"},
      {good_cameras, good_images, "5 0 0 1 1 2 3 0.1 1\n", "points3D.txt: line 1"},
      {good_cameras, good_images, "5 0 0 1 1 2 3\n", "points3D.txt: line 1"},
      // Cross-file consistency.
      {good_cameras, "1 1 0 0 0 0 0 0 2 a.png\n\n", good_points,
       "images.txt: image 'a.png' refers to camera id 2"},
      {good_cameras, good_images, "5 0 0 1 1 2 3 0.1 4 0\n",
       "points3D.txt: 3D point 5 is observed by image id 4"},
      {good_cameras + good_cameras, good_images, good_points, "cameras.txt: camera id 1 appears"},
      {good_cameras, good_images + "2 1 0 0 0 0 0 0 1 a.png\n\n", good_points,
       "images.txt: image name 'a.png' appears more than once"},
      {good_cameras, good_images, good_points + good_points, "points3D.txt: 3D point id 5 appears"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.expected);
    WriteText(dir / "cameras.txt", c.cameras);
    WriteText(dir / "images.txt", c.images);
    WriteText(dir / "points3D.txt", c.points);
    EXPECT_MPMVS_ERROR(ReadSparseModel(dir.path()), dir / c.expected);
  }
  WriteText(dir / "cameras.txt", good_cameras);
  WriteText(dir / "images.txt", good_images);
  WriteText(dir / "points3D.txt", good_points);
  EXPECT_EQ(ReadSparseModel(dir.path()).points.size(), 1u);
}

TEST(SparseModelError, WriterRejectsWrongParameterCount) {
  TempDir dir;
  SparseModel model = MakeSampleModel();
  model.cameras[0].params.pop_back();
  EXPECT_MPMVS_ERROR(WriteSparseModelBinary(model, dir.path()), "needs 4 parameters");
  EXPECT_MPMVS_ERROR(WriteSparseModelText(model, dir.path()), "cameras.txt");
  EXPECT_FALSE(FileExists(dir / "cameras.bin"));
}

// ---- real data ---------------------------------------------------------------------------

TEST(SparseModelDataset, ReadsMiddlebury2005DollsTextModel) {
  MPMVS_REQUIRE_DATASET(dataset, "middlebury2005_dolls");
  const SparseModel model = ReadSparseModel(dataset + "/sparse");
  ASSERT_EQ(model.cameras.size(), 2u);
  for (const SparseCamera& camera : model.cameras) {
    EXPECT_EQ(camera.model_id, kPinholeModelId);
    EXPECT_EQ(camera.width, 463u);
    EXPECT_EQ(camera.height, 370u);
    EXPECT_NEAR(camera.params[0], 1246.666667, 1e-6);
  }
  ASSERT_EQ(model.images.size(), 2u);
  EXPECT_EQ(model.images[0].name, "view1.png");
  EXPECT_EQ(model.images[1].name, "view5.png");
  EXPECT_DOUBLE_EQ(model.images[1].tvec[0], -0.16);
  EXPECT_GT(model.points.size(), 100u);
  for (const SparsePoint3D& point : model.points) {
    EXPECT_GT(point.xyz[2], 1.0);
    EXPECT_LT(point.xyz[2], 3.5);
    for (const SparseTrackElement& element : point.track) {
      const int image = model.FindImageById(element.image_id);
      ASSERT_GE(image, 0);
      ASSERT_LT(element.point2D_idx, model.images[image].points2D.size());
      EXPECT_EQ(model.images[image].points2D[element.point2D_idx].point3D_id, point.point3D_id);
    }
  }
  // Binary round trip of real data.
  TempDir dir;
  WriteSparseModelBinary(model, dir.path());
  ExpectModelsEqual(model, ReadSparseModel(dir.path()));
}

}  // namespace
}  // namespace mpmvs

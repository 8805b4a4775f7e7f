#pragma once
// Helpers shared by the I/O tests: error assertions, raw file access, a sample model.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/util/error.h"

// Asserts that `statement` throws mpmvs::Error whose message contains `substring`.
#define EXPECT_MPMVS_ERROR(statement, substring)                                        \
  do {                                                                                  \
    try {                                                                               \
      statement;                                                                        \
      ADD_FAILURE() << "expected mpmvs::Error containing '" << (substring)             \
                    << "' from: " #statement;                                           \
    } catch (const ::mpmvs::Error& error) {                                             \
      EXPECT_NE(std::string(error.what()).find(substring), std::string::npos)           \
          << "message: " << error.what() << "\nexpected to contain: " << (substring);  \
    }                                                                                   \
  } while (0)

namespace mpmvs {
namespace test {

inline void WriteBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

inline void WriteText(const std::string& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file << text;
}

template <typename T>
void PutValue(std::vector<uint8_t>* bytes, size_t offset, T value) {
  std::memcpy(bytes->data() + offset, &value, sizeof(T));
}

// Two cameras of different models, three images (one without 2D points, one with a name
// containing a sub-folder), three points with tracks. Values chosen to need all 17 digits.
inline SparseModel MakeSampleModel() {
  SparseModel model;
  SparseCamera pinhole;
  pinhole.camera_id = 3;
  pinhole.model_id = kPinholeModelId;
  pinhole.width = 640;
  pinhole.height = 480;
  pinhole.params = {500.123456789012345, 501.1 / 3.0, 320.5, 239.25};
  SparseCamera radial;
  radial.camera_id = 7;
  radial.model_id = CameraModelIdFromName("OPENCV");
  radial.width = 1024;
  radial.height = 768;
  radial.params = {800, 801, 512, 384, -0.1, 0.01, 1e-4, -2e-5};
  model.cameras = {pinhole, radial};

  SparseImage a;
  a.image_id = 1;
  a.qvec[0] = 0.9238795325112867;
  a.qvec[1] = 0.0;
  a.qvec[2] = 0.3826834323650898;
  a.qvec[3] = 0.0;
  a.tvec[0] = -1.0 / 3.0;
  a.tvec[1] = 0.5;
  a.tvec[2] = 2.0;
  a.camera_id = 3;
  a.name = "a.png";
  a.points2D = {{10.25, 20.5, 100}, {30.0 / 7.0, 40.0, UINT64_MAX}, {50, 60, 101}};
  SparseImage b;
  b.image_id = 5;
  b.camera_id = 7;
  b.name = "sub/b.jpg";
  b.points2D = {{1, 2, 101}, {3, 4, 102}};
  SparseImage c;
  c.image_id = 9;
  c.camera_id = 3;
  c.name = "c.png";
  model.images = {a, b, c};

  SparsePoint3D p0;
  p0.point3D_id = 100;
  p0.xyz[0] = 0.1;
  p0.xyz[1] = -0.2;
  p0.xyz[2] = 5.0 / 3.0;
  p0.rgb[0] = 255;
  p0.rgb[1] = 0;
  p0.rgb[2] = 17;
  p0.error = 0.123;
  p0.track = {{1, 0}};
  SparsePoint3D p1;
  p1.point3D_id = 101;
  p1.xyz[2] = 4;
  p1.track = {{1, 2}, {5, 0}};
  SparsePoint3D p2;
  p2.point3D_id = 102;
  p2.xyz[2] = 3;
  p2.track = {{5, 1}};
  model.points = {p0, p1, p2};
  return model;
}

inline void ExpectModelsEqual(const SparseModel& a, const SparseModel& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    EXPECT_EQ(a.cameras[i].camera_id, b.cameras[i].camera_id);
    EXPECT_EQ(a.cameras[i].model_id, b.cameras[i].model_id);
    EXPECT_EQ(a.cameras[i].width, b.cameras[i].width);
    EXPECT_EQ(a.cameras[i].height, b.cameras[i].height);
    EXPECT_EQ(a.cameras[i].params, b.cameras[i].params);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (size_t i = 0; i < a.images.size(); ++i) {
    const SparseImage& x = a.images[i];
    const SparseImage& y = b.images[i];
    EXPECT_EQ(x.image_id, y.image_id);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(x.qvec[k], y.qvec[k]);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(x.tvec[k], y.tvec[k]);
    EXPECT_EQ(x.camera_id, y.camera_id);
    EXPECT_EQ(x.name, y.name);
    ASSERT_EQ(x.points2D.size(), y.points2D.size());
    for (size_t k = 0; k < x.points2D.size(); ++k) {
      EXPECT_EQ(x.points2D[k].x, y.points2D[k].x);
      EXPECT_EQ(x.points2D[k].y, y.points2D[k].y);
      EXPECT_EQ(x.points2D[k].point3D_id, y.points2D[k].point3D_id);
    }
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    const SparsePoint3D& x = a.points[i];
    const SparsePoint3D& y = b.points[i];
    EXPECT_EQ(x.point3D_id, y.point3D_id);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(x.xyz[k], y.xyz[k]);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(x.rgb[k], y.rgb[k]);
    EXPECT_EQ(x.error, y.error);
    ASSERT_EQ(x.track.size(), y.track.size());
    for (size_t k = 0; k < x.track.size(); ++k) {
      EXPECT_EQ(x.track[k].image_id, y.track[k].image_id);
      EXPECT_EQ(x.track[k].point2D_idx, y.track[k].point2D_idx);
    }
  }
}

// Rewrites the sparse model in dir (binary and text files) with point i's reprojection error
// set to error_of(i): the errors of a model of more or less exact poses.
template <typename ErrorOf>
inline void SetSparsePointErrors(const std::string& dir, ErrorOf error_of) {
  SparseModel model = ReadSparseModel(dir);
  for (size_t i = 0; i < model.points.size(); ++i) model.points[i].error = error_of(i);
  WriteSparseModelBinary(model, dir);
  WriteSparseModelText(model, dir);
}

}  // namespace test
}  // namespace mpmvs

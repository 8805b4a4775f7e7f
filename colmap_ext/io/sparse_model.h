#pragma once
// COLMAP sparse model (cameras, images, points3D) in plain data types, read from and
// written to COLMAP's binary (.bin) and text (.txt) layouts (docs/colmap_interface.md §3).
#include <cstdint>
#include <string>
#include <vector>

namespace mpmvs {

// COLMAP camera model ids used in dense workspaces.
constexpr int kSimplePinholeModelId = 0;
constexpr int kPinholeModelId = 1;

// Name of a COLMAP camera model id ("PINHOLE", ...), or "UNKNOWN".
std::string CameraModelName(int model_id);
// Id of a model name, or -1.
int CameraModelIdFromName(const std::string& name);
// Number of parameters of a model id, or -1 when unknown.
int CameraModelNumParams(int model_id);

struct SparseCamera {
  uint32_t camera_id = 0;
  int model_id = kPinholeModelId;
  uint64_t width = 0;
  uint64_t height = 0;
  std::vector<double> params;  // in COLMAP's order for the model
};

struct SparsePoint2D {
  double x = 0, y = 0;
  uint64_t point3D_id = UINT64_MAX;  // UINT64_MAX = none (text: -1)
};

struct SparseImage {
  uint32_t image_id = 0;
  double qvec[4] = {1, 0, 0, 0};  // qw qx qy qz, cam_from_world rotation (Hamilton)
  double tvec[3] = {0, 0, 0};     // cam_from_world translation: X_cam = R X_world + t
  uint32_t camera_id = 0;
  std::string name;
  std::vector<SparsePoint2D> points2D;
};

struct SparseTrackElement {
  uint32_t image_id = 0;
  uint32_t point2D_idx = 0;
};

struct SparsePoint3D {
  uint64_t point3D_id = 0;
  double xyz[3] = {0, 0, 0};
  uint8_t rgb[3] = {0, 0, 0};
  double error = 0;
  std::vector<SparseTrackElement> track;
};

// Images are kept in file order: that order defines COLMAP's "model image index".
struct SparseModel {
  std::vector<SparseCamera> cameras;
  std::vector<SparseImage> images;
  std::vector<SparsePoint3D> points;

  // Index into cameras / images, or -1.
  int FindCamera(uint32_t camera_id) const;
  int FindImageByName(const std::string& name) const;
  int FindImageById(uint32_t image_id) const;
};

// Reads dir/{cameras,images,points3D}.bin when all three exist, else the three .txt files
// (COLMAP's rule). Throws Error naming the offending file on anything missing, truncated or
// corrupt (absurd counts are rejected before allocating).
SparseModel ReadSparseModel(const std::string& dir);
// True when dir holds all three .bin files (then ReadSparseModel reads those).
bool HasBinarySparseModel(const std::string& dir);
// dir/stem.bin or dir/stem.txt, whichever ReadSparseModel reads (for error messages).
std::string SparseModelFilePath(const std::string& dir, const std::string& stem);
SparseModel ReadSparseModelBinary(const std::string& dir);
SparseModel ReadSparseModelText(const std::string& dir);

// Writes the three files atomically (temporary + rename).
void WriteSparseModelBinary(const SparseModel& model, const std::string& dir);
void WriteSparseModelText(const SparseModel& model, const std::string& dir);

// Row-major 3x3 rotation from a (w, x, y, z) quaternion (normalised first).
void QuaternionToRotationMatrix(const double q[4], double R[9]);
// Inverse of the above for a proper rotation (w >= 0).
void RotationMatrixToQuaternion(const double R[9], double q[4]);

}  // namespace mpmvs

#pragma once
// Minimal float 3-vector and row-major 3x3 matrix math usable on host and device.
#include <math.h>

#include "kernels/common.h"

namespace mpmvs {
namespace kernels {

struct Vec3 {
  float x, y, z;
};

MPMVS_HD MPMVS_FORCE_INLINE Vec3 MakeVec3(float x, float y, float z) { return Vec3{x, y, z}; }
MPMVS_HD MPMVS_FORCE_INLINE Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
MPMVS_HD MPMVS_FORCE_INLINE Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
MPMVS_HD MPMVS_FORCE_INLINE Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
MPMVS_HD MPMVS_FORCE_INLINE Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
MPMVS_HD MPMVS_FORCE_INLINE float Dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
MPMVS_HD MPMVS_FORCE_INLINE Vec3 Cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
MPMVS_HD MPMVS_FORCE_INLINE float Norm(Vec3 a) { return sqrtf(Dot(a, a)); }
MPMVS_HD MPMVS_FORCE_INLINE Vec3 Normalize(Vec3 a) {
  const float n = Norm(a);
  return n > 0.f ? (1.f / n) * a : a;
}

// Row-major 3x3 matrix times vector.
MPMVS_HD MPMVS_FORCE_INLINE Vec3 MatVec(const float* M, Vec3 v) {
  return {M[0] * v.x + M[1] * v.y + M[2] * v.z, M[3] * v.x + M[4] * v.y + M[5] * v.z,
          M[6] * v.x + M[7] * v.y + M[8] * v.z};
}
// Transposed row-major 3x3 matrix times vector.
MPMVS_HD MPMVS_FORCE_INLINE Vec3 MatTVec(const float* M, Vec3 v) {
  return {M[0] * v.x + M[3] * v.y + M[6] * v.z, M[1] * v.x + M[4] * v.y + M[7] * v.z,
          M[2] * v.x + M[5] * v.y + M[8] * v.z};
}

// Rotation by Euler angles (X then Y then Z, R = Rz Ry Rx) applied to v.
MPMVS_HD inline Vec3 RotateEulerXYZ(Vec3 v, float ax, float ay, float az) {
  const float cx = cosf(ax), sx = sinf(ax), cy = cosf(ay), sy = sinf(ay), cz = cosf(az),
              sz = sinf(az);
  // Rx
  Vec3 a{v.x, cx * v.y - sx * v.z, sx * v.y + cx * v.z};
  // Ry
  Vec3 b{cy * a.x + sy * a.z, a.y, -sy * a.x + cy * a.z};
  // Rz
  return Vec3{cz * b.x - sz * b.y, sz * b.x + cz * b.y, b.z};
}

}  // namespace kernels
}  // namespace mpmvs

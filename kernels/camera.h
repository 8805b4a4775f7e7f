#pragma once
// Pinhole cameras, plane hypotheses and the plane-induced homography (docs/algorithm.md §2).
// Pixel convention of COLMAP's MVS: pixel (col,row) is image coordinate (col,row).
#include "kernels/vec3.h"

namespace mpmvs {
namespace kernels {

struct Camera {
  int width = 0, height = 0;
  float fx = 1, fy = 1, cx = 0, cy = 0;
  float R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // world -> camera, row-major
  float t[3] = {0, 0, 0};                    // X_cam = R X_world + t
};

// Viewing ray of pixel (u, v) scaled to z = 1: K^-1 (u, v, 1).
MPMVS_HD MPMVS_FORCE_INLINE Vec3 PixelRay(const Camera& cam, float u, float v) {
  return Vec3{(u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.f};
}

// A plane n . X + d = 0 in the reference camera frame, |n| = 1, n facing the camera.
struct Plane {
  Vec3 n;
  float d;
};

// z-depth at which the ray of (u, v) meets the plane; <= 0 or non-finite when it does not.
MPMVS_HD MPMVS_FORCE_INLINE float PlaneDepth(const Plane& p, Vec3 ray) {
  const float denom = Dot(p.n, ray);
  return denom != 0.f ? -p.d / denom : -1.f;
}

// The plane with normal n through the point at depth z on ray.
MPMVS_HD MPMVS_FORCE_INLINE Plane PlaneFromDepthNormal(Vec3 ray, float depth, Vec3 n) {
  return Plane{n, -Dot(n, depth * ray)};
}

// Flips n so it faces the camera along ray (n . ray < 0).
MPMVS_HD MPMVS_FORCE_INLINE Vec3 FaceCamera(Vec3 n, Vec3 ray) { return Dot(n, ray) > 0.f ? -n : n; }

// Relative geometry of a source camera w.r.t. the reference camera, precomputed once per
// (reference, source) pair so each homography costs 9 multiply-adds:
//   H(n, d) = A - b m^T with A = Ks Rrel Kr^-1, b = Ks trel, m = Kr^-T n / d,
// where X_src = Rrel X_ref + trel.
struct RelativePose {
  float A[9];
  float b[3];
  float R[9];  // ref camera -> src camera
  float t[3];
  float Rinv[9];  // src camera -> ref camera
  float tinv[3];
};

// Homography of plane p from reference pixels to source pixels, row-major.
MPMVS_HD MPMVS_FORCE_INLINE void PlaneHomography(const RelativePose& rel, Vec3 m, float H[9]) {
  for (int r = 0; r < 3; ++r) {
    H[3 * r + 0] = rel.A[3 * r + 0] - rel.b[r] * m.x;
    H[3 * r + 1] = rel.A[3 * r + 1] - rel.b[r] * m.y;
    H[3 * r + 2] = rel.A[3 * r + 2] - rel.b[r] * m.z;
  }
}

// m = Kr^-T n / d: the per-hypothesis part of the homography shared by all sources.
MPMVS_HD MPMVS_FORCE_INLINE Vec3 HomographyPlaneVector(const Camera& ref, const Plane& p) {
  const float inv_d = 1.f / p.d;
  const float mx = p.n.x / ref.fx;
  const float my = p.n.y / ref.fy;
  const float mz = p.n.z - p.n.x * ref.cx / ref.fx - p.n.y * ref.cy / ref.fy;
  return Vec3{mx * inv_d, my * inv_d, mz * inv_d};
}

// Projects a point in a camera frame to pixel coordinates; returns false behind the camera.
MPMVS_HD MPMVS_FORCE_INLINE bool ProjectCameraPoint(const Camera& cam, Vec3 X, float* u, float* v) {
  if (X.z <= 0.f) return false;
  *u = cam.fx * X.x / X.z + cam.cx;
  *v = cam.fy * X.y / X.z + cam.cy;
  return true;
}

// Host-side setup of RelativePose (also usable on device).
MPMVS_HD inline RelativePose ComputeRelativePose(const Camera& ref, const Camera& src) {
  RelativePose rel;
  // Rrel = Rs Rr^T, trel = ts - Rrel tr.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      float s = 0.f;
      for (int k = 0; k < 3; ++k) s += src.R[3 * i + k] * ref.R[3 * j + k];
      rel.R[3 * i + j] = s;
    }
  }
  for (int i = 0; i < 3; ++i) {
    rel.t[i] = src.t[i] - (rel.R[3 * i] * ref.t[0] + rel.R[3 * i + 1] * ref.t[1] +
                           rel.R[3 * i + 2] * ref.t[2]);
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rel.Rinv[3 * i + j] = rel.R[3 * j + i];
  }
  for (int i = 0; i < 3; ++i) {
    rel.tinv[i] = -(rel.Rinv[3 * i] * rel.t[0] + rel.Rinv[3 * i + 1] * rel.t[1] +
                    rel.Rinv[3 * i + 2] * rel.t[2]);
  }
  // A = Ks Rrel Kr^-1; Kr^-1 = [[1/fx,0,-cx/fx],[0,1/fy,-cy/fy],[0,0,1]].
  float KsR[9];
  for (int j = 0; j < 3; ++j) {
    KsR[0 + j] = src.fx * rel.R[j] + src.cx * rel.R[6 + j];
    KsR[3 + j] = src.fy * rel.R[3 + j] + src.cy * rel.R[6 + j];
    KsR[6 + j] = rel.R[6 + j];
  }
  for (int i = 0; i < 3; ++i) {
    rel.A[3 * i + 0] = KsR[3 * i + 0] / ref.fx;
    rel.A[3 * i + 1] = KsR[3 * i + 1] / ref.fy;
    rel.A[3 * i + 2] = -KsR[3 * i + 0] * ref.cx / ref.fx - KsR[3 * i + 1] * ref.cy / ref.fy +
                       KsR[3 * i + 2];
  }
  rel.b[0] = src.fx * rel.t[0] + src.cx * rel.t[2];
  rel.b[1] = src.fy * rel.t[1] + src.cy * rel.t[2];
  rel.b[2] = rel.t[2];
  return rel;
}

}  // namespace kernels
}  // namespace mpmvs

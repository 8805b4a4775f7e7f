#pragma once
// Compilation attributes shared by the host (CPU backend, tests) and device (CUDA backend)
// builds of the per-pixel math. Everything in kernels/*.h that is marked MPMVS_HD is the
// one and only copy of the math; the CPU backend calls it directly, the CUDA backend from
// __global__ launchers.
#include <cstdint>
#include <string.h>

#if defined(__CUDACC__) || (defined(__HIPCC__) && !defined(__HIP_CPU_RT__))
#define MPMVS_HD __host__ __device__
#define MPMVS_FORCE_INLINE __forceinline__
#else
#define MPMVS_HD
#define MPMVS_FORCE_INLINE inline __attribute__((always_inline))
#endif

namespace mpmvs {
namespace kernels {

// Hard cap on source views per reference image (view masks are 32-bit).
constexpr int kMaxSourceViews = 32;
// Photometric cost of an invalid match (NCC cost range is [0, 2]).
constexpr float kInvalidCost = 2.0f;

MPMVS_HD MPMVS_FORCE_INLINE float Clamp(float x, float lo, float hi) {
  return x < lo ? lo : (x > hi ? hi : x);
}
MPMVS_HD MPMVS_FORCE_INLINE float Min(float a, float b) { return a < b ? a : b; }
MPMVS_HD MPMVS_FORCE_INLINE float Max(float a, float b) { return a > b ? a : b; }
MPMVS_HD MPMVS_FORCE_INLINE int MinI(int a, int b) { return a < b ? a : b; }
MPMVS_HD MPMVS_FORCE_INLINE int MaxI(int a, int b) { return a > b ? a : b; }

// e^-x for x >= 0, inline and branch-free (the reference-patch weights and view selection need
// dozens per pixel update; libm's expf is a call). Relative error below 1e-5.
MPMVS_HD MPMVS_FORCE_INLINE float ExpNeg(float x) {
  // t = x log2(e) clamped to [0, 125] (e^-x = 2^-t; NaN -> 125, int-safe), on the bit
  // pattern: integer selects vectorise where float compares, which may trap, do not.
  constexpr int32_t kBits125 = 0x42fa0000;  // 125.f
  const float scaled = x * 1.44269504f;
  int32_t b;
  memcpy(&b, &scaled, sizeof(b));
  const int32_t nan_mask = (0x7f800000 - (b & 0x7fffffff)) >> 31;  // all ones for NaN
  b = MinI(MaxI(b, 0), kBits125);
  b = (b & ~nan_mask) | (kBits125 & nan_mask);
  float t;
  memcpy(&t, &b, sizeof(t));
  const int n = static_cast<int>(t);
  const float y = -(t - static_cast<float>(n)) * 0.693147181f;  // 2^-frac = e^y, y in (-ln2, 0]
  const float p =
      1.f + y * (1.f + y * (0.5f + y * (0.166666667f + y * (0.0416666667f + y * (0.00833333333f +
                                                                                   y * (0.00138888889f + y * 0.000198412698f))))));
  const int bits = (127 - n) << 23;  // 2^-n
  float scale;
  memcpy(&scale, &bits, sizeof(scale));
  return p * scale;
}

}  // namespace kernels
}  // namespace mpmvs

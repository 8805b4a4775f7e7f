#pragma once
// Compilation attributes shared by the host (CPU backend, tests) and device (CUDA backend)
// builds of the per-pixel math. Everything in kernels/*.h that is marked MPMVS_HD is the
// one and only copy of the math; the CPU backend calls it directly, the CUDA backend from
// __global__ launchers.
#include <cstdint>

#if defined(__CUDACC__)
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

}  // namespace kernels
}  // namespace mpmvs

#pragma once
// Counter-based random numbers: every draw is a hash of (seed, image, pixel, iteration,
// stream position), so the CPU and CUDA backends draw identical streams regardless of
// thread count or scheduling (docs/algorithm.md §0).
#include "kernels/common.h"

namespace mpmvs {
namespace kernels {

MPMVS_HD MPMVS_FORCE_INLINE uint64_t Mix64(uint64_t z) {
  // splitmix64 finaliser: a bijective avalanche mix.
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class RandomStream {
 public:
  MPMVS_HD RandomStream(uint64_t seed, uint32_t image, uint32_t pixel, uint32_t iteration)
      : key_(Mix64(Mix64(Mix64(seed ^ 0x9e3779b97f4a7c15ULL) ^ image) ^
                   ((static_cast<uint64_t>(iteration) << 32) | pixel))),
        counter_(0) {}

  // Uniform in [0, 1).
  MPMVS_HD MPMVS_FORCE_INLINE float Uniform() {
    const uint64_t bits = Mix64(key_ + 0x9e3779b97f4a7c15ULL * (++counter_));
    return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);
  }
  // Uniform in [lo, hi).
  MPMVS_HD MPMVS_FORCE_INLINE float Uniform(float lo, float hi) { return lo + (hi - lo) * Uniform(); }
  // Moves past n draws without computing them: the stream then continues as after n calls.
  MPMVS_HD MPMVS_FORCE_INLINE void Skip(uint32_t n) { counter_ += n; }

 private:
  uint64_t key_;
  uint64_t counter_;
};

}  // namespace kernels
}  // namespace mpmvs

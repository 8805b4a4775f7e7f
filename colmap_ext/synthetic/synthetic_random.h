#pragma once
// Deterministic pseudo-random numbers for synthetic scenes. Per-pixel values come from a
// counter-based hash of (seed, view, pixel, ...), so the output never depends on how the
// work is split among threads.
#include <cmath>
#include <cstdint>

namespace mpmvs {

// A 64-bit finaliser with good avalanche (the splitmix64 mixing step).
inline uint64_t SynthMix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

inline uint64_t SynthHash(uint64_t a, uint64_t b) { return SynthMix64(a ^ SynthMix64(b)); }
inline uint64_t SynthHash(uint64_t a, uint64_t b, uint64_t c) {
  return SynthHash(SynthHash(a, b), c);
}
inline uint64_t SynthHash(uint64_t a, uint64_t b, uint64_t c, uint64_t d) {
  return SynthHash(SynthHash(a, b, c), d);
}

// Uniform in [0, 1) from a hash.
inline double SynthUnit(uint64_t h) {
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

// Standard normal from one hash (Box-Muller on its two 32-bit halves).
inline double SynthNormal(uint64_t h) {
  const double u1 = (static_cast<double>(h >> 32) + 0.5) * (1.0 / 4294967296.0);
  const double u2 = (static_cast<double>(h & 0xffffffffULL) + 0.5) * (1.0 / 4294967296.0);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// Sequential generator for single-threaded scene building (camera jitter, texture seeds).
class SynthRng {
 public:
  explicit SynthRng(uint64_t seed) : seed_(SynthMix64(seed)) {}
  uint64_t Next() { return SynthHash(seed_, ++counter_); }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * SynthUnit(Next()); }
  double Normal() { return SynthNormal(Next()); }

 private:
  uint64_t seed_;
  uint64_t counter_ = 0;
};

}  // namespace mpmvs

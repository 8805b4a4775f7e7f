#pragma once
// Vectorised specialisation of ComputeNccCost for the CPU backend (AVX2/FMA: 8 window
// samples per instruction; AVX-512: 16) with gathered bilinear fetches. Same inputs, same
// result as the scalar version within float rounding: tests/kernels/kernels_test.cc checks it
// through CpuBackendNccCost, compiled with the backend's own flags. Host only.
#include <vector>

#include "kernels/ncc.h"

namespace mpmvs {
namespace kernels {

// Largest image for the packed layout: the AVX-512 form computes row-major indices in
// float, exact only up to 2^24.
constexpr size_t kMaxQuadImagePixels = size_t{1} << 24;

// Packs an 8-bit image into ImageView::quads. Returns false, leaving quads empty, when a
// value is not an integer in 0..255 (bytes must be exact) or the image has more than
// kMaxQuadImagePixels pixels; the float path is used then.
inline bool MakeQuadImage(const ImageView& img, std::vector<uint32_t>* quads) {
  const size_t n = static_cast<size_t>(img.width) * img.height;
  if (n > kMaxQuadImagePixels) {
    quads->clear();
    return false;
  }
  for (size_t i = 0; i < n; ++i) {
    const float value = img.data[i];
    if (!(value >= 0.f && value <= 255.f) || value != static_cast<float>(static_cast<int>(value))) {
      quads->clear();
      return false;
    }
  }
  quads->resize(n);
  auto at = [&](int x, int y) {
    x = x < img.width ? x : img.width - 1;
    y = y < img.height ? y : img.height - 1;
    return static_cast<uint32_t>(img.data[static_cast<size_t>(y) * img.width + x]);
  };
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      (*quads)[static_cast<size_t>(y) * img.width + x] =
          at(x, y) | at(x + 1, y) << 8 | at(x, y + 1) << 16 | at(x + 1, y + 1) << 24;
    }
  }
  return true;
}

}  // namespace kernels
}  // namespace mpmvs

#if defined(__AVX2__) && defined(__FMA__) && !defined(__CUDACC__)
#define MPMVS_HAVE_SIMD_NCC 1
#include <immintrin.h>

namespace mpmvs {
namespace kernels {

// The three horizontal sums of 8-lane s, ss, rs at once ([s, ss, rs, rs] by unpack and
// shuffle): a third of the instructions of three separate reductions.
inline void SumThree(__m256 s8, __m256 ss8, __m256 rs8, float* s, float* ss, float* rs) {
  const __m256 a = _mm256_add_ps(_mm256_unpacklo_ps(s8, ss8), _mm256_unpackhi_ps(s8, ss8));
  const __m256 c = _mm256_add_ps(_mm256_unpacklo_ps(rs8, rs8), _mm256_unpackhi_ps(rs8, rs8));
  const __m256 abc = _mm256_add_ps(_mm256_shuffle_ps(a, c, _MM_SHUFFLE(1, 0, 1, 0)),
                                   _mm256_shuffle_ps(a, c, _MM_SHUFFLE(3, 2, 3, 2)));
  const __m128 sums = _mm_add_ps(_mm256_castps256_ps128(abc), _mm256_extractf128_ps(abc, 1));
  *s = _mm_cvtss_f32(sums);
  *ss = _mm_cvtss_f32(_mm_movehdup_ps(sums));
  *rs = _mm_cvtss_f32(_mm_movehl_ps(sums, sums));
}

// The NCC cost of a window from its weighted sums s, ss, rs (8 lanes each), as
// ComputeNccCost ends.
MPMVS_FORCE_INLINE float NccCostOfSums(const RefPatch& patch, __m256 s8, __m256 ss8, __m256 rs8) {
  float s, ss, rs;
  SumThree(s8, ss8, rs8, &s, &ss, &rs);
  const float var_s = ss - s * s;
  if (SourcePatchIsFlat(var_s, ss)) return kInvalidCost;
  const float cov = rs - patch.mean * s;
  return Clamp(1.f - cov / sqrtf(patch.variance * var_s), 0.f, 2.f);
}

#if defined(__AVX512F__) && defined(__AVX512VL__)
// Bilinear value at (fx, fy) of the packed neighbours q (a quads word per lane), minus
// shift = 2^23 + centre. Bytes become floats without conversions: a byte b OR-ed into the
// mantissa of 2^23 is the float 2^23 + b, so differences of two such floats are the exact
// byte differences; subtracting 2^23 + centre (the centre shift of ComputeRefPatch, rounded
// to an integer if it is not one) keeps them exact, and NCC ignores a constant offset.
MPMVS_FORCE_INLINE __m512 BilinearQuads512(__m512i q, __m512 fx, __m512 fy, __m512 shift) {
  const __m512i byte = _mm512_set1_epi32(0xff);
  const __m512i magic = _mm512_set1_epi32(0x4b000000);  // 2^23
  const __m512 p00 = _mm512_castsi512_ps(_mm512_ternarylogic_epi32(q, byte, magic, 0xea));
  const __m512 p01 = _mm512_castsi512_ps(_mm512_ternarylogic_epi32(_mm512_srli_epi32(q, 8), byte, magic, 0xea));
  const __m512 p10 = _mm512_castsi512_ps(_mm512_ternarylogic_epi32(_mm512_srli_epi32(q, 16), byte, magic, 0xea));
  const __m512 p11 = _mm512_castsi512_ps(_mm512_or_si512(_mm512_srli_epi32(q, 24), magic));
  const __m512 top = _mm512_fmadd_ps(fx, _mm512_sub_ps(p01, p00), _mm512_sub_ps(p00, shift));
  const __m512 bottom = _mm512_fmadd_ps(fx, _mm512_sub_ps(p11, p10), _mm512_sub_ps(p10, shift));
  return _mm512_fmadd_ps(fy, _mm512_sub_ps(bottom, top), top);
}

// BilinearQuads512 on 8 lanes.
MPMVS_FORCE_INLINE __m256 BilinearQuads256(__m256i q, __m256 fx, __m256 fy, __m256 shift) {
  const __m256i byte = _mm256_set1_epi32(0xff);
  const __m256i magic = _mm256_set1_epi32(0x4b000000);  // 2^23
  const __m256 p00 = _mm256_castsi256_ps(_mm256_ternarylogic_epi32(q, byte, magic, 0xea));
  const __m256 p01 = _mm256_castsi256_ps(_mm256_ternarylogic_epi32(_mm256_srli_epi32(q, 8), byte, magic, 0xea));
  const __m256 p10 = _mm256_castsi256_ps(_mm256_ternarylogic_epi32(_mm256_srli_epi32(q, 16), byte, magic, 0xea));
  const __m256 p11 = _mm256_castsi256_ps(_mm256_or_si256(_mm256_srli_epi32(q, 24), magic));
  const __m256 top = _mm256_fmadd_ps(fx, _mm256_sub_ps(p01, p00), _mm256_sub_ps(p00, shift));
  const __m256 bottom = _mm256_fmadd_ps(fx, _mm256_sub_ps(p11, p10), _mm256_sub_ps(p10, shift));
  return _mm256_fmadd_ps(fy, _mm256_sub_ps(bottom, top), top);
}

// AVX-512 form of the 8-bit path: the 36 samples in two 16-lane blocks and a 4-lane tail.
inline float NccCostQuads512(const RefPatch& patch, const ImageView& src, const float H[9], float fu,
                             float fv) {
  const __m512 h0 = _mm512_set1_ps(H[0]), h1 = _mm512_set1_ps(H[1]);
  const __m512 h2 = _mm512_set1_ps(H[0] * fu + H[1] * fv + H[2]);
  const __m512 h3 = _mm512_set1_ps(H[3]), h4 = _mm512_set1_ps(H[4]);
  const __m512 h5 = _mm512_set1_ps(H[3] * fu + H[4] * fv + H[5]);
  const __m512 h6 = _mm512_set1_ps(H[6]), h7 = _mm512_set1_ps(H[7]);
  const __m512 h8 = _mm512_set1_ps(H[6] * fu + H[7] * fv + H[8]);
  const __m512 two = _mm512_set1_ps(2.f), zero = _mm512_setzero_ps();
  const __m512 xmax = _mm512_set1_ps(static_cast<float>(src.width - 1));
  const __m512 ymax = _mm512_set1_ps(static_cast<float>(src.height - 1));
  const __m512 width = _mm512_set1_ps(static_cast<float>(src.width));
  const __m512 shift = _mm512_set1_ps(8388608.f + patch.centre);
  const int* base = reinterpret_cast<const int*>(src.quads);
  static_assert(kWindowSamples == 36 && kWindowSamplesPadded >= 40, "16 + 16 + 4 (of 8) lanes");
  __m512 sum_s = zero, sum_ss = zero, sum_rs = zero;
  for (int b = 0; b < 32; b += 16) {
    const __m512 x = _mm512_loadu_ps(patch.offset_x + b);
    const __m512 y = _mm512_loadu_ps(patch.offset_y + b);
    const __m512 hz = _mm512_fmadd_ps(h6, x, _mm512_fmadd_ps(h7, y, h8));
    const __m512 hx = _mm512_fmadd_ps(h0, x, _mm512_fmadd_ps(h1, y, h2));
    const __m512 hy = _mm512_fmadd_ps(h3, x, _mm512_fmadd_ps(h4, y, h5));
    const __m512 r = _mm512_rcp14_ps(hz);
    const __m512 inv = _mm512_mul_ps(r, _mm512_fnmadd_ps(hz, r, two));
    const __m512 sx = _mm512_min_ps(_mm512_max_ps(_mm512_mul_ps(hx, inv), zero), xmax);
    const __m512 sy = _mm512_min_ps(_mm512_max_ps(_mm512_mul_ps(hy, inv), zero), ymax);
    // Integer parts as floats: the row-major index is exact in float below 2^24 pixels.
    const __m512 x0 = _mm512_roundscale_ps(sx, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m512 y0 = _mm512_roundscale_ps(sy, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m512 fx = _mm512_sub_ps(sx, x0);
    const __m512 fy = _mm512_sub_ps(sy, y0);
    const __m512i q = _mm512_i32gather_epi32(_mm512_cvttps_epi32(_mm512_fmadd_ps(y0, width, x0)), base, 4);
    const __m512 value = BilinearQuads512(q, fx, fy, shift);
    const __m512 wv = _mm512_mul_ps(_mm512_loadu_ps(patch.weight + b), value);
    sum_s = _mm512_add_ps(sum_s, wv);
    sum_ss = _mm512_fmadd_ps(wv, value, sum_ss);
    sum_rs = _mm512_fmadd_ps(_mm512_loadu_ps(patch.weighted_value + b), value, sum_rs);
  }
  // The last 4 samples in 256-bit registers: a 512-bit block costs twice as much on CPUs
  // that split them. Lanes 36..39 are zero-weight padding; the gather skips them.
  auto low = [](__m512 v) { return _mm512_castps512_ps256(v); };
  const __m256 x = _mm256_loadu_ps(patch.offset_x + 32);
  const __m256 y = _mm256_loadu_ps(patch.offset_y + 32);
  const __m256 hz = _mm256_fmadd_ps(low(h6), x, _mm256_fmadd_ps(low(h7), y, low(h8)));
  const __m256 hx = _mm256_fmadd_ps(low(h0), x, _mm256_fmadd_ps(low(h1), y, low(h2)));
  const __m256 hy = _mm256_fmadd_ps(low(h3), x, _mm256_fmadd_ps(low(h4), y, low(h5)));
  const __m256 r = _mm256_rcp14_ps(hz);
  const __m256 inv = _mm256_mul_ps(r, _mm256_fnmadd_ps(hz, r, low(two)));
  const __m256 sx = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(hx, inv), low(zero)), low(xmax));
  const __m256 sy = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(hy, inv), low(zero)), low(ymax));
  const __m256 x0 = _mm256_round_ps(sx, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m256 y0 = _mm256_round_ps(sy, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m256 fx = _mm256_sub_ps(sx, x0);
  const __m256 fy = _mm256_sub_ps(sy, y0);
  const __m256i q = _mm256_mmask_i32gather_epi32(
      _mm256_setzero_si256(), 0x0f, _mm256_cvttps_epi32(_mm256_fmadd_ps(y0, low(width), x0)), base, 4);
  const __m256 value = BilinearQuads256(q, fx, fy, low(shift));
  const __m256 wv = _mm256_mul_ps(_mm256_loadu_ps(patch.weight + 32), value);
  auto high = [](__m512 v) { return _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(v), 1)); };
  const __m256 s8 = _mm256_add_ps(_mm256_add_ps(low(sum_s), high(sum_s)), wv);
  const __m256 ss8 = _mm256_fmadd_ps(wv, value, _mm256_add_ps(low(sum_ss), high(sum_ss)));
  const __m256 rs8 = _mm256_fmadd_ps(_mm256_loadu_ps(patch.weighted_value + 32), value,
                                     _mm256_add_ps(low(sum_rs), high(sum_rs)));
  return NccCostOfSums(patch, s8, ss8, rs8);
}
#endif

// Bilinear values of 8 samples from packed 8-bit neighbours (ImageView::quads) at row-major
// indices `index`, minus `shift`: one gather brings the four neighbours of each sample. The
// last block of a window holds only kWindowSamples % 8 real samples (full = false): its
// padding lanes are not loaded.
MPMVS_FORCE_INLINE __m256 SampleQuads8(const ImageView& src, __m256i index, bool full,
                                       __m256 fx, __m256 fy, __m256 shift) {
  const int* base = reinterpret_cast<const int*>(src.quads);
  const __m256i tail_mask = _mm256_cmpgt_epi32(
      _mm256_set1_epi32(kWindowSamples % 8), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256i q = full ? _mm256_i32gather_epi32(base, index, 4)
                         : _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), base, index,
                                                       tail_mask, 4);
  const __m256i byte = _mm256_set1_epi32(0xff);
  const __m256 p00 = _mm256_cvtepi32_ps(_mm256_and_si256(q, byte));
  const __m256 p01 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(q, 8), byte));
  const __m256 p10 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(q, 16), byte));
  const __m256 p11 = _mm256_cvtepi32_ps(_mm256_srli_epi32(q, 24));
  const __m256 top = _mm256_fmadd_ps(fx, _mm256_sub_ps(p01, p00), p00);
  const __m256 bottom = _mm256_fmadd_ps(fx, _mm256_sub_ps(p11, p10), p10);
  return _mm256_sub_ps(_mm256_fmadd_ps(fy, _mm256_sub_ps(bottom, top), top), shift);
}

// Bilinear values of 8 samples of a float image at pixel (x0, y0) + (fx, fy), clamped to
// the edge like SampleBilinear, minus `shift`: four gathers.
MPMVS_FORCE_INLINE __m256 SampleFloats8(const ImageView& src, __m256i x0, __m256i y0,
                                        __m256 fx, __m256 fy, __m256 shift) {
  const __m256i width = _mm256_set1_epi32(src.width);
  const __m256i one = _mm256_set1_epi32(1);
  const __m256i x1 = _mm256_min_epi32(_mm256_add_epi32(x0, one), _mm256_set1_epi32(src.width - 1));
  const __m256i y1 = _mm256_min_epi32(_mm256_add_epi32(y0, one), _mm256_set1_epi32(src.height - 1));
  const __m256i r0 = _mm256_mullo_epi32(y0, width);
  const __m256i r1 = _mm256_mullo_epi32(y1, width);
  const __m256 p00 = _mm256_i32gather_ps(src.data, _mm256_add_epi32(r0, x0), 4);
  const __m256 p01 = _mm256_i32gather_ps(src.data, _mm256_add_epi32(r0, x1), 4);
  const __m256 p10 = _mm256_i32gather_ps(src.data, _mm256_add_epi32(r1, x0), 4);
  const __m256 p11 = _mm256_i32gather_ps(src.data, _mm256_add_epi32(r1, x1), 4);
  const __m256 top = _mm256_fmadd_ps(fx, _mm256_sub_ps(p01, p00), p00);
  const __m256 bottom = _mm256_fmadd_ps(fx, _mm256_sub_ps(p11, p10), p10);
  return _mm256_sub_ps(_mm256_fmadd_ps(fy, _mm256_sub_ps(bottom, top), top), shift);
}

// ComputeNccCost's sampling part (NccCostOfDefined), vectorised.
inline float NccCostOfDefinedSimd(const RefPatch& patch, const ImageView& src, const float H[9], int u,
                                  int v, const WindowSpec& /*win*/) {
  const float fu = static_cast<float>(u), fv = static_cast<float>(v);
#if defined(__AVX512F__) && defined(__AVX512VL__)
  if (src.quads) return NccCostQuads512(patch, src, H, fu, fv);
#endif

  // Homography applied to window offsets: the pixel position is folded into the last column.
  const __m256 h0 = _mm256_set1_ps(H[0]), h1 = _mm256_set1_ps(H[1]);
  const __m256 h2 = _mm256_set1_ps(H[0] * fu + H[1] * fv + H[2]);
  const __m256 h3 = _mm256_set1_ps(H[3]), h4 = _mm256_set1_ps(H[4]);
  const __m256 h5 = _mm256_set1_ps(H[3] * fu + H[4] * fv + H[5]);
  const __m256 h6 = _mm256_set1_ps(H[6]), h7 = _mm256_set1_ps(H[7]);
  const __m256 h8 = _mm256_set1_ps(H[6] * fu + H[7] * fv + H[8]);
  const __m256 two = _mm256_set1_ps(2.f);
  const __m256 zero = _mm256_setzero_ps();
  const __m256 xmax = _mm256_set1_ps(static_cast<float>(src.width - 1));
  const __m256 ymax = _mm256_set1_ps(static_cast<float>(src.height - 1));
  const __m256i width = _mm256_set1_epi32(src.width);
  const __m256 shift = _mm256_set1_ps(patch.centre);
  __m256 sum_s = zero, sum_ss = zero, sum_rs = zero;
  for (int b = 0; b < kWindowSamplesPadded; b += 8) {
    const __m256 x = _mm256_loadu_ps(patch.offset_x + b);
    const __m256 y = _mm256_loadu_ps(patch.offset_y + b);
    const __m256 hz = _mm256_fmadd_ps(h6, x, _mm256_fmadd_ps(h7, y, h8));
    const __m256 hx = _mm256_fmadd_ps(h0, x, _mm256_fmadd_ps(h1, y, h2));
    const __m256 hy = _mm256_fmadd_ps(h3, x, _mm256_fmadd_ps(h4, y, h5));
    // 1/hz: 12-bit estimate + one Newton step (~1e-7 relative, like a division, cheaper).
    const __m256 r = _mm256_rcp_ps(hz);
    const __m256 inv = _mm256_mul_ps(r, _mm256_fnmadd_ps(hz, r, two));
    // Clamp-to-edge addressing as SampleBilinear (max/min also map NaN to the border).
    const __m256 sx = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(hx, inv), zero), xmax);
    const __m256 sy = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(hy, inv), zero), ymax);
    const __m256i x0 = _mm256_cvttps_epi32(sx);
    const __m256i y0 = _mm256_cvttps_epi32(sy);
    const __m256 fx = _mm256_sub_ps(sx, _mm256_cvtepi32_ps(x0));
    const __m256 fy = _mm256_sub_ps(sy, _mm256_cvtepi32_ps(y0));
    const __m256 value =
        src.quads ? SampleQuads8(src, _mm256_add_epi32(_mm256_mullo_epi32(y0, width), x0),
                                 b + 8 <= kWindowSamples, fx, fy, shift)
                  : SampleFloats8(src, x0, y0, fx, fy, shift);
    const __m256 wv = _mm256_mul_ps(_mm256_loadu_ps(patch.weight + b), value);
    sum_s = _mm256_add_ps(sum_s, wv);
    sum_ss = _mm256_fmadd_ps(wv, value, sum_ss);
    sum_rs = _mm256_fmadd_ps(_mm256_loadu_ps(patch.weighted_value + b), value, sum_rs);
  }
  return NccCostOfSums(patch, sum_s, sum_ss, sum_rs);
}

struct SimdNcc {
  static float CostOfDefined(const RefPatch& patch, const ImageView& src, const float H[9], int u,
                             int v, const WindowSpec& win) {
    return NccCostOfDefinedSimd(patch, src, H, u, v, win);
  }
};

}  // namespace kernels
}  // namespace mpmvs
#endif

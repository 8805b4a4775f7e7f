#pragma once
// AVX2/FMA specialisation of ComputeNccCost for the CPU backend: 8 window samples per
// instruction with gathered bilinear fetches. Same inputs, same result as the scalar
// version within float rounding (tests/kernels_test.cc checks it). Host only.
#include "kernels/ncc.h"

#if defined(__AVX2__) && defined(__FMA__) && !defined(__CUDACC__)
#define MPMVS_HAVE_SIMD_NCC 1
#include <immintrin.h>

namespace mpmvs {
namespace kernels {

inline float ComputeNccCostSimd(const RefPatch& patch, const ImageView& src, const float H[9], int u,
                                int v, const WindowSpec& /*win*/) {
  const float fu = static_cast<float>(u), fv = static_cast<float>(v);
  if (!NccDefined(patch, src, H, fu, fv)) return kInvalidCost;

  const __m256 h0 = _mm256_set1_ps(H[0]), h1 = _mm256_set1_ps(H[1]), h2 = _mm256_set1_ps(H[2]);
  const __m256 h3 = _mm256_set1_ps(H[3]), h4 = _mm256_set1_ps(H[4]), h5 = _mm256_set1_ps(H[5]);
  const __m256 h6 = _mm256_set1_ps(H[6]), h7 = _mm256_set1_ps(H[7]), h8 = _mm256_set1_ps(H[8]);
  const __m256 vu = _mm256_set1_ps(fu), vv = _mm256_set1_ps(fv);
  const __m256 zero = _mm256_setzero_ps();
  const __m256 xmax = _mm256_set1_ps(static_cast<float>(src.width - 1));
  const __m256 ymax = _mm256_set1_ps(static_cast<float>(src.height - 1));
  const __m256i width = _mm256_set1_epi32(src.width);
  const __m256i xlast = _mm256_set1_epi32(src.width - 1);
  const __m256i ylast = _mm256_set1_epi32(src.height - 1);
  const __m256i one = _mm256_set1_epi32(1);
  const __m256 shift = _mm256_set1_ps(patch.centre);
  __m256 sum_s = zero, sum_ss = zero, sum_rs = zero;
  for (int b = 0; b < kWindowSamplesPadded; b += 8) {
    const __m256 x = _mm256_add_ps(vu, _mm256_loadu_ps(patch.offset_x + b));
    const __m256 y = _mm256_add_ps(vv, _mm256_loadu_ps(patch.offset_y + b));
    const __m256 hz = _mm256_fmadd_ps(h6, x, _mm256_fmadd_ps(h7, y, h8));
    const __m256 hx = _mm256_fmadd_ps(h0, x, _mm256_fmadd_ps(h1, y, h2));
    const __m256 hy = _mm256_fmadd_ps(h3, x, _mm256_fmadd_ps(h4, y, h5));
    const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.f), hz);
    // Clamp-to-edge addressing as SampleBilinear (max/min also map NaN to the border).
    const __m256 sx = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(hx, inv), zero), xmax);
    const __m256 sy = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(hy, inv), zero), ymax);
    const __m256i x0 = _mm256_cvttps_epi32(sx);
    const __m256i y0 = _mm256_cvttps_epi32(sy);
    const __m256 fx = _mm256_sub_ps(sx, _mm256_cvtepi32_ps(x0));
    const __m256 fy = _mm256_sub_ps(sy, _mm256_cvtepi32_ps(y0));
    const __m256i x1 = _mm256_min_epi32(_mm256_add_epi32(x0, one), xlast);
    const __m256i y1 = _mm256_min_epi32(_mm256_add_epi32(y0, one), ylast);
    const __m256i r0 = _mm256_mullo_epi32(y0, width);
    const __m256i r1 = _mm256_mullo_epi32(y1, width);
    __m256 value;
    if (src.pairs) {
      // Two 64-bit gathers per row fetch (I(x0), I(x0+1)) for 8 samples; the shuffles
      // leave lanes in the order 0,1,4,5,2,3,6,7, so fx/fy are permuted alike and the
      // result is permuted back.
      const __m256i i0 = _mm256_add_epi32(r0, x0);
      const __m256i i1 = _mm256_add_epi32(r1, x0);
      const double* pairs = reinterpret_cast<const double*>(src.pairs);
      const __m256 t_lo = _mm256_castpd_ps(_mm256_i32gather_pd(pairs, _mm256_castsi256_si128(i0), 8));
      const __m256 t_hi = _mm256_castpd_ps(_mm256_i32gather_pd(pairs, _mm256_extracti128_si256(i0, 1), 8));
      const __m256 b_lo = _mm256_castpd_ps(_mm256_i32gather_pd(pairs, _mm256_castsi256_si128(i1), 8));
      const __m256 b_hi = _mm256_castpd_ps(_mm256_i32gather_pd(pairs, _mm256_extracti128_si256(i1, 1), 8));
      const __m256 p00 = _mm256_shuffle_ps(t_lo, t_hi, _MM_SHUFFLE(2, 0, 2, 0));
      const __m256 p01 = _mm256_shuffle_ps(t_lo, t_hi, _MM_SHUFFLE(3, 1, 3, 1));
      const __m256 p10 = _mm256_shuffle_ps(b_lo, b_hi, _MM_SHUFFLE(2, 0, 2, 0));
      const __m256 p11 = _mm256_shuffle_ps(b_lo, b_hi, _MM_SHUFFLE(3, 1, 3, 1));
      // Lane order after the shuffles: 0,1,4,5,2,3,6,7 (64-bit lanes 0,2,1,3).
      const __m256 fxq = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(fx), _MM_SHUFFLE(3, 1, 2, 0)));
      const __m256 fyq = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(fy), _MM_SHUFFLE(3, 1, 2, 0)));
      const __m256 top = _mm256_fmadd_ps(fxq, _mm256_sub_ps(p01, p00), p00);
      const __m256 bottom = _mm256_fmadd_ps(fxq, _mm256_sub_ps(p11, p10), p10);
      const __m256 vq = _mm256_fmadd_ps(fyq, _mm256_sub_ps(bottom, top), top);
      value = _mm256_sub_ps(
          _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(vq), _MM_SHUFFLE(3, 1, 2, 0))), shift);
    } else {
      const __m256 p00 = _mm256_i32gather_ps(src.data, _mm256_add_epi32(r0, x0), 4);
      const __m256 p01 = _mm256_i32gather_ps(src.data, _mm256_add_epi32(r0, x1), 4);
      const __m256 p10 = _mm256_i32gather_ps(src.data, _mm256_add_epi32(r1, x0), 4);
      const __m256 p11 = _mm256_i32gather_ps(src.data, _mm256_add_epi32(r1, x1), 4);
      const __m256 top = _mm256_fmadd_ps(fx, _mm256_sub_ps(p01, p00), p00);
      const __m256 bottom = _mm256_fmadd_ps(fx, _mm256_sub_ps(p11, p10), p10);
      value = _mm256_sub_ps(_mm256_fmadd_ps(fy, _mm256_sub_ps(bottom, top), top), shift);
    }
    const __m256 wv = _mm256_mul_ps(_mm256_loadu_ps(patch.weight + b), value);
    sum_s = _mm256_add_ps(sum_s, wv);
    sum_ss = _mm256_fmadd_ps(wv, value, sum_ss);
    sum_rs = _mm256_fmadd_ps(_mm256_loadu_ps(patch.weighted_value + b), value, sum_rs);
  }
  auto hsum = [](__m256 a) {
    const __m128 s = _mm_add_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    const __m128 t = _mm_add_ps(s, _mm_movehl_ps(s, s));
    return _mm_cvtss_f32(_mm_add_ss(t, _mm_shuffle_ps(t, t, 1)));
  };
  const float s = hsum(sum_s), ss = hsum(sum_ss), rs = hsum(sum_rs);
  const float var_s = ss - s * s;
  if (var_s < kMinNccVariance) return kInvalidCost;
  const float cov = rs - patch.mean * s;
  return Clamp(1.f - cov / sqrtf(patch.variance * var_s), 0.f, 2.f);
}

struct SimdNcc {
  static float Cost(const RefPatch& patch, const ImageView& src, const float H[9], int u, int v,
                    const WindowSpec& win) {
    return ComputeNccCostSimd(patch, src, H, u, v, win);
  }
};

}  // namespace kernels
}  // namespace mpmvs
#endif

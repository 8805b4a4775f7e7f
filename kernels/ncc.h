#pragma once
// Bilateral-weighted NCC over a sparse 6x6 window warped by a plane homography
// (docs/algorithm.md §3, §4). The reference side (weights, mean, variance) depends only on the
// pixel and the window scale, so it is computed once per pixel update (RefPatch) and reused
// for every hypothesis and source view.
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "kernels/camera.h"

namespace mpmvs {
namespace kernels {

// A grey image in memory (values 0..255), row-major. Same struct on host and device.
struct ImageView {
  const float* data = nullptr;
  int width = 0;
  int height = 0;
  // Optional CPU-only copy for 8-bit images: quads[y * width + x] packs the four bilinear
  // neighbours I(x, y), I(x+1, y), I(x, y+1), I(x+1, y+1) (clamped to the image) as bytes,
  // so one 32-bit gather fetches a whole bilinear sample (ncc_simd.h, MakeQuadImage).
  const uint32_t* quads = nullptr;
  // Optional, reference image only: a chroma guide, 2 floats per pixel (colmap_ext's
  // MakeChromaGuide). Its L1 difference is added to the grey difference in the bilateral
  // weights, so a window is also cut at colour edges between equally bright surfaces.
  const float* chroma = nullptr;
};

// Window of scale S: edge L = 2^S*10+1, 6x6 samples with spacing 2^(S+1) (radius 5*2^S).
constexpr int kWindowSamplesPerAxis = 6;
constexpr int kWindowSamples = kWindowSamplesPerAxis * kWindowSamplesPerAxis;
// Sample arrays are padded with zero-weight samples at the centre to a multiple of 8 so a
// vectorised CPU specialisation (ncc_simd.h) can run whole SIMD lanes.
constexpr int kWindowSamplesPadded = 40;

// Made by WindowForScale.
struct WindowSpec {
  int radius = 5;
  int step = 2;
  // Distance of sample k (row-major) from the centre, for the bilateral spatial term: per
  // window, not per pixel update (36 square roots were 5 % of a whole run).
  float distance[kWindowSamples] = {};
};

// Offset of sample k (0..5) along an axis.
MPMVS_HD MPMVS_FORCE_INLINE int WindowOffset(const WindowSpec& w, int k) { return -w.radius + k * w.step; }
MPMVS_HD inline WindowSpec WindowForScale(int scale) {
  WindowSpec w;
  w.radius = 5 << scale;
  w.step = 2 << scale;
  for (int k = 0; k < kWindowSamples; ++k) {
    const int dx = WindowOffset(w, k % kWindowSamplesPerAxis);
    const int dy = WindowOffset(w, k / kWindowSamplesPerAxis);
    w.distance[k] = sqrtf(static_cast<float>(dx * dx + dy * dy));
  }
  return w;
}
MPMVS_HD MPMVS_FORCE_INLINE int WindowSide(const WindowSpec& w) { return 2 * w.radius + 1; }

// Bilateral weight constants (distances unsquared, as in the reference code). σ_c is 2.5,
// not ACMH's 3: measured on real and synthetic scenes, kernels/DESIGN.md item 11.
constexpr float kSigmaSpatial = 5.0f;
constexpr float kSigmaColor = 2.5f;
constexpr float kMinNccVariance = 1e-5f;

// Whether a source patch is flat. Its variance E[x^2] - E[x]^2 is computed on values shifted
// by the reference centre, so a flat patch at offset c leaves float rounding of order
// c^2 * 1e-7: the floor grows with E[x^2] to stay above that (x^2 <= 255^2 keeps it below
// 0.7 grey levels^2, far under any real texture).
MPMVS_HD MPMVS_FORCE_INLINE bool SourcePatchIsFlat(float var_s, float mean_square) {
  return var_s < kMinNccVariance * (1.f + mean_square);
}

// x clamped to [lo, hi], NaN to lo: safe to convert to int afterwards.
MPMVS_HD MPMVS_FORCE_INLINE float ClampCoordinate(float x, float lo, float hi) {
  return x > lo ? (x < hi ? x : hi) : lo;
}

// Bilinear sample with clamp-to-edge addressing (a NaN coordinate, from a window sample on
// the source's principal plane, reads the border like the vectorised CPU form).
MPMVS_HD MPMVS_FORCE_INLINE float SampleBilinear(const ImageView& img, float x, float y) {
  x = ClampCoordinate(x, 0.f, static_cast<float>(img.width - 1));
  y = ClampCoordinate(y, 0.f, static_cast<float>(img.height - 1));
  const int x0 = static_cast<int>(x);
  const int y0 = static_cast<int>(y);
  const int x1 = MinI(x0 + 1, img.width - 1);
  const int y1 = MinI(y0 + 1, img.height - 1);
  const float fx = x - x0;
  const float fy = y - y0;
  const float* r0 = img.data + static_cast<long>(y0) * img.width;
  const float* r1 = img.data + static_cast<long>(y1) * img.width;
  const float top = r0[x0] + fx * (r0[x1] - r0[x0]);
  const float bottom = r1[x0] + fx * (r1[x1] - r1[x0]);
  return top + fy * (bottom - top);
}

// Reference patch statistics. Intensities are shifted by the centre value (NCC is offset
// invariant) so the float moments do not cancel catastrophically on flat walls.
struct RefPatch {
  float weight[kWindowSamplesPadded];          // normalised to sum 1; padding 0
  float weighted_value[kWindowSamplesPadded];  // weight * (I_ref - centre); padding 0
  float offset_x[kWindowSamplesPadded];        // sample offsets (padding 0)
  float offset_y[kWindowSamplesPadded];
  float mean;                             // sum weight * (I_ref - centre)
  float variance;                         // weighted variance
  float texture;                          // weighted variance a linear ramp leaves (with_texture)
  float centre;                           // I_ref(p)
};

// The sum of term(k) over the padded window (terms of the padding must be 0), as 8
// interleaved partial sums: eight short chains of adds instead of one of 36, which SIMD
// lanes run at once. A fixed order, the same on every backend.
static_assert(kWindowSamplesPadded % 8 == 0, "WindowSum runs whole groups of 8");
template <class Term>
MPMVS_HD MPMVS_FORCE_INLINE float WindowSum(const Term& term) {
  float lane[8] = {0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f};
  for (int k = 0; k < kWindowSamplesPadded; k += 8) {
    for (int l = 0; l < 8; ++l) lane[l] += term(k + l);
  }
  return ((lane[0] + lane[4]) + (lane[2] + lane[6])) + ((lane[1] + lane[5]) + (lane[3] + lane[7]));
}

// with_texture: also fit the shading ramp (RefPatch::texture), which only prior passes use.
MPMVS_HD inline void ComputeRefPatch(const ImageView& ref, int u, int v, const WindowSpec& win,
                                     RefPatch* patch, bool with_texture = false) {
  const long centre_index = static_cast<long>(v) * ref.width + u;
  const float centre = ref.data[centre_index];
  const float inv_spatial = 1.f / (2.f * kSigmaSpatial * kSigmaSpatial);
  const float inv_color = 1.f / (2.f * kSigmaColor * kSigmaColor);
  // Offsets first, then the sample indices, the gather and the weights, each a straight
  // loop over the 36 samples (this runs once per pixel update, 36 exponentials).
  float values[kWindowSamplesPadded], exponent[kWindowSamples], inside[kWindowSamples];
  for (int k = 0; k < kWindowSamples; ++k) {
    patch->offset_x[k] = static_cast<float>(WindowOffset(win, k % kWindowSamplesPerAxis));
    patch->offset_y[k] = static_cast<float>(WindowOffset(win, k / kWindowSamplesPerAxis));
  }
  const int lo = WindowOffset(win, 0), hi = WindowOffset(win, kWindowSamplesPerAxis - 1);
  const bool interior = u + lo >= 0 && v + lo >= 0 && u + hi < ref.width && v + hi < ref.height;
  // Sample k's index relative to the centre pixel (small enough for int: 32-bit gathers).
  int rel[kWindowSamples];
  if (interior) {
    // The common case, without a bounds test per sample: row by row from the window's corner.
    for (int j = 0; j < kWindowSamplesPerAxis; ++j) {
      const int row = (lo + j * win.step) * ref.width + lo;
      for (int i = 0; i < kWindowSamplesPerAxis; ++i) {
        rel[j * kWindowSamplesPerAxis + i] = row + i * win.step;
        inside[j * kWindowSamplesPerAxis + i] = 1.f;
      }
    }
  } else {
    for (int k = 0; k < kWindowSamples; ++k) {
      const int dx = WindowOffset(win, k % kWindowSamplesPerAxis);
      const int dy = WindowOffset(win, k / kWindowSamplesPerAxis);
      // Samples outside the reference image take no part (weight 0) instead of repeating
      // the border, which would compare invented texture with the source's real one.
      const bool in = u + dx >= 0 && v + dy >= 0 && u + dx < ref.width && v + dy < ref.height;
      rel[k] = in ? dy * ref.width + dx : 0;
      inside[k] = in ? 1.f : 0.f;
    }
  }
  const float* at_centre = ref.data + centre_index;
  float* colour = exponent;  // the colour distance, then in place the exponent
  for (int k = 0; k < kWindowSamples; ++k) {
    values[k] = at_centre[rel[k]] - centre;
    colour[k] = fabsf(values[k]);
  }
  if (ref.chroma) {
    const float* chroma_centre = ref.chroma + 2 * centre_index;
    for (int k = 0; k < kWindowSamples; ++k) {
      const float* chroma = chroma_centre + 2 * rel[k];
      colour[k] += fabsf(chroma[0] - chroma_centre[0]) + fabsf(chroma[1] - chroma_centre[1]);
    }
  }
  for (int k = 0; k < kWindowSamples; ++k) exponent[k] = win.distance[k] * inv_spatial + colour[k] * inv_color;
  for (int k = 0; k < kWindowSamples; ++k) patch->weight[k] = inside[k] * ExpNeg(exponent[k]);
  for (int k = kWindowSamples; k < kWindowSamplesPadded; ++k) {
    patch->weight[k] = patch->weighted_value[k] = patch->offset_x[k] = patch->offset_y[k] = 0.f;
    values[k] = 0.f;
  }
  const float inv_wsum = 1.f / WindowSum([&](int k) { return patch->weight[k]; });
  for (int k = 0; k < kWindowSamplesPadded; ++k) {
    patch->weight[k] *= inv_wsum;
    patch->weighted_value[k] = patch->weight[k] * values[k];
  }
  const float mean = WindowSum([&](int k) { return patch->weighted_value[k]; });
  const float sq = WindowSum([&](int k) { return patch->weighted_value[k] * values[k]; });
  patch->mean = mean;
  patch->variance = sq - mean * mean;
  patch->centre = centre;
  patch->texture = patch->variance;
  if (!with_texture) return;
  // Smooth shading is locally a linear ramp, which matches itself under any shift along it
  // and so says nothing about depth: the texture is the variance a weighted ramp fit leaves.
  const float mx = WindowSum([&](int k) { return patch->weight[k] * patch->offset_x[k]; });
  const float my = WindowSum([&](int k) { return patch->weight[k] * patch->offset_y[k]; });
  float x[kWindowSamplesPadded], y[kWindowSamplesPadded], wi[kWindowSamplesPadded];
  for (int k = 0; k < kWindowSamplesPadded; ++k) {
    x[k] = patch->offset_x[k] - mx;
    y[k] = patch->offset_y[k] - my;
    wi[k] = patch->weight[k] * (values[k] - mean);
  }
  const float sxx = WindowSum([&](int k) { return patch->weight[k] * x[k] * x[k]; });
  const float syy = WindowSum([&](int k) { return patch->weight[k] * y[k] * y[k]; });
  const float sxy = WindowSum([&](int k) { return patch->weight[k] * x[k] * y[k]; });
  const float sxi = WindowSum([&](int k) { return wi[k] * x[k]; });
  const float syi = WindowSum([&](int k) { return wi[k] * y[k]; });
  const float det = sxx * syy - sxy * sxy;
  float ramp = 0.f;
  if (det > 1e-6f * sxx * syy) ramp = (syy * sxi * sxi - 2.f * sxy * sxi * syi + sxx * syi * syi) / det;
  patch->texture = Max(patch->variance - ramp, 0.f);
}

// Whether a reference patch is flat (a saturated or clipped area, such as an over-exposed
// window pane): no view can cost any plane there.
MPMVS_HD MPMVS_FORCE_INLINE bool RefPatchIsFlat(const RefPatch& patch) {
  return !(patch.variance >= kMinNccVariance);
}

// Whether an NCC is defined at all: the window centre maps in front of the source camera
// and inside its image, and the reference patch is not flat. Only the centre is tested.
MPMVS_HD MPMVS_FORCE_INLINE bool NccDefined(const RefPatch& patch, const ImageView& src,
                                            const float H[9], float fu, float fv) {
  const float cz = H[6] * fu + H[7] * fv + H[8];
  if (!(cz > 0.f)) return false;
  const float cx = (H[0] * fu + H[1] * fv + H[2]) / cz;
  const float cy = (H[3] * fu + H[4] * fv + H[5]) / cz;
  return cx >= 0.f && cx < src.width && cy >= 0.f && cy < src.height && !RefPatchIsFlat(patch);
}

// The NCC cost of a window for which NccDefined holds (the caller has checked).
MPMVS_HD inline float NccCostOfDefined(const RefPatch& patch, const ImageView& src, const float H[9],
                                       int u, int v, const WindowSpec& win) {
  const float fu = static_cast<float>(u), fv = static_cast<float>(v);
  float sum_s = 0.f, sum_ss = 0.f, sum_rs = 0.f;
  const float shift = patch.centre;
  for (int j = 0; j < kWindowSamplesPerAxis; ++j) {
    const float y = fv + static_cast<float>(WindowOffset(win, j));
    const float row_x = H[1] * y + H[2];
    const float row_y = H[4] * y + H[5];
    const float row_z = H[7] * y + H[8];
    for (int i = 0; i < kWindowSamplesPerAxis; ++i) {
      const float x = fu + static_cast<float>(WindowOffset(win, i));
      const float hz = H[6] * x + row_z;
      const float inv = 1.f / hz;
      const float sx = (H[0] * x + row_x) * inv;
      const float sy = (H[3] * x + row_y) * inv;
      const float value = SampleBilinear(src, sx, sy) - shift;
      const int k = j * kWindowSamplesPerAxis + i;
      const float wv = patch.weight[k] * value;
      sum_s += wv;
      sum_ss += wv * value;
      sum_rs += patch.weighted_value[k] * value;
    }
  }
  const float var_s = sum_ss - sum_s * sum_s;
  if (SourcePatchIsFlat(var_s, sum_ss)) return kInvalidCost;
  const float cov = sum_rs - patch.mean * sum_s;
  return Clamp(1.f - cov / sqrtf(patch.variance * var_s), 0.f, 2.f);
}

// The portable NCC used on the device and as the reference on the host. An NCC policy's
// CostOfDefined samples a window for which NccDefined holds (the caller has checked, and
// counts the NCCs it samples); NccCost below adds the check.
struct ScalarNcc {
  MPMVS_HD MPMVS_FORCE_INLINE static float CostOfDefined(const RefPatch& patch, const ImageView& src,
                                                         const float H[9], int u, int v,
                                                         const WindowSpec& win) {
    return NccCostOfDefined(patch, src, H, u, v, win);
  }
};

// NCC cost in [0, 2] of the reference patch against a source image under homography H
// (reference pixel -> source pixel). 2 when the centre maps outside the source image,
// behind it, or either patch is flat.
template <class Ncc>
MPMVS_HD MPMVS_FORCE_INLINE float NccCost(const RefPatch& patch, const ImageView& src, const float H[9],
                                          int u, int v, const WindowSpec& win) {
  if (!NccDefined(patch, src, H, static_cast<float>(u), static_cast<float>(v))) return kInvalidCost;
  return Ncc::CostOfDefined(patch, src, H, u, v, win);
}

// The scalar NccCost: the reference the vectorised CPU form is tested against.
MPMVS_HD inline float ComputeNccCost(const RefPatch& patch, const ImageView& src, const float H[9],
                                     int u, int v, const WindowSpec& win) {
  return NccCost<ScalarNcc>(patch, src, H, u, v, win);
}

}  // namespace kernels
}  // namespace mpmvs

#pragma once
// The per-pixel PatchMatch update: hypothesis initialisation, checkerboard propagation with
// multi-hypothesis view selection, random refinement, geometric consistency and the planar
// prior score (docs/algorithm.md §2-§8, with the corrections listed in kernels/DESIGN.md).
// Written once for host and device; the backends only decide which pixels run where.
#include <math.h>

#include "kernels/camera.h"
#include "kernels/ncc.h"
#include "kernels/propagation_pattern.h"
#include "kernels/random.h"
#include "kernels/view_selection.h"

namespace mpmvs {
namespace kernels {

constexpr float kPi = 3.14159265358979f;

// One source view of the reference image.
struct SourceView {
  ImageView image;
  Camera camera;
  RelativePose rel;            // reference camera -> this camera
  const float* depth = nullptr;  // this view's depth map (geometric passes), camera size
};

// Per-pixel state, W*H entries each (host or device memory).
struct PixelState {
  float* plane = nullptr;       // 4 floats per pixel: nx, ny, nz, d (reference camera frame)
  float* cost = nullptr;        // cost of the current plane (photometric + lambda * geometric)
  float* photo_cost = nullptr;  // m_p of the current plane
  float* geo_error = nullptr;   // m_g: weighted mean clamped reprojection error (px)
  uint32_t* view_mask = nullptr;
  // Updates each pixel still skips because its plane has settled (SettledPlane); nullptr when
  // PassParams::settled_skips is 0. Zeroed by the initialisation pass, so it never outlives
  // a run: nothing of it is carried between stages (kernels/DESIGN.md 27).
  uint8_t* skips_left = nullptr;
};

// Planar prior per pixel: label != 0 where a triangle covers the pixel.
struct PlanarPrior {
  const float* plane = nullptr;  // 4 floats per pixel, reference camera frame
  const uint8_t* label = nullptr;
  float gamma = 0.5f;
  float beta = 0.18f;
  float sigma_depth = 1.f;                  // (depth_max - depth_min) / 64
  float sigma_normal = 5.f * kPi / 180.f;  // radians
};

struct RefinementParams {
  float rho = 0.02f;  // depth +-2 %, normal +-rho*pi/2 per Euler angle
};

struct PassParams {
  Camera ref_camera;
  ImageView ref_image;
  const SourceView* sources = nullptr;  // host or device array
  int num_sources = 0;
  WindowSpec window;
  PropagationPattern pattern;
  ViewSelectionParams view_selection;
  RefinementParams refinement;
  float depth_min = 0.f, depth_max = 1.f;
  bool geometric = false;
  float geom_lambda = 0.f;     // from PatchMatchSchedule (MakePassParams)
  float geom_max_error = 0.f;
  // Image noise variance of the reference (grey levels^2); 0: off. A window whose variance
  // is not far above it cannot score a plane better than noise does, so the aggregated
  // photometric cost is floored at noise_variance / window variance (kernels/DESIGN.md 14).
  float noise_variance = 0.f;
  bool use_prior = false;
  PlanarPrior prior;
  uint64_t seed = 0;
  uint32_t image_id = 0;
  uint32_t rng_iteration = 0;  // unique per pass and stage, for the random streams
  int color = 0;                // checkerboard colour being updated: (u + v) % 2 == color
  int init_top_k = 4;
  // A pixel whose update left its plane settled skips its next settled_skips updates
  // (SettledPlane; kernels/DESIGN.md 27). 0: every pixel is updated in every pass (the paper).
  int settled_skips = 0;
  // The pass's iteration is the first at its window scale after another scale (mPM): the
  // stored costs are the other window's, so every pixel is updated and no skip carries over.
  bool new_window_scale = false;
  // The propagated candidates are costed in at most this many source views (CostedViews);
  // 0: in every source view (the paper).
  int costed_views = 0;
  uint32_t iteration = 0;  // the pass's iteration in its stage (turns the explored view)
};

// ---------------------------------------------------------------------------------------
// Hypotheses

MPMVS_HD inline Vec3 RandomNormal(RandomStream* rng, Vec3 ray) {
  float q1, q2, s;
  int guard = 0;
  do {
    q1 = rng->Uniform(-1.f, 1.f);
    q2 = rng->Uniform(-1.f, 1.f);
    s = q1 * q1 + q2 * q2;
  } while ((s >= 1.f || s == 0.f) && ++guard < 64);
  if (s >= 1.f || s == 0.f) return Normalize(-ray);
  const float r = 2.f * sqrtf(1.f - s);
  Vec3 n{q1 * r, q2 * r, 1.f - 2.f * s};
  return Normalize(FaceCamera(n, ray));
}

MPMVS_HD inline Vec3 PerturbNormal(RandomStream* rng, Vec3 n, float max_angle, Vec3 ray) {
  const float a1 = rng->Uniform(-max_angle, max_angle);
  const float a2 = rng->Uniform(-max_angle, max_angle);
  const float a3 = rng->Uniform(-max_angle, max_angle);
  const Vec3 p = Normalize(RotateEulerXYZ(n, a1, a2, a3));
  return Dot(p, ray) < 0.f ? p : n;
}

MPMVS_HD MPMVS_FORCE_INLINE Plane LoadPlane(const float* planes, int idx) {
  const float* p = planes + 4 * static_cast<long>(idx);
  return Plane{Vec3{p[0], p[1], p[2]}, p[3]};
}
MPMVS_HD MPMVS_FORCE_INLINE void StorePlane(float* planes, int idx, const Plane& plane) {
  float* p = planes + 4 * static_cast<long>(idx);
  p[0] = plane.n.x;
  p[1] = plane.n.y;
  p[2] = plane.n.z;
  p[3] = plane.d;
}

MPMVS_HD MPMVS_FORCE_INLINE bool SamePlane(const Plane& a, const Plane& b) {
  return a.n.x == b.n.x && a.n.y == b.n.y && a.n.z == b.n.z && a.d == b.d;
}

MPMVS_HD MPMVS_FORCE_INLINE bool DepthInRange(const PassParams& params, float depth) {
  return depth >= params.depth_min && depth <= params.depth_max;
}

// ---------------------------------------------------------------------------------------
// Costs

// The point X_ref (reference camera frame) seen from source view src: the point in the
// source's frame (*X_src), its pixel (*us, *vs) and the depth the source's map holds at the
// nearest pixel; 0 where the point is behind the source or outside its image.
MPMVS_HD inline float SourceDepthAtPoint(const SourceView& src, Vec3 X_ref, Vec3* X_src, float* us, float* vs) {
  *X_src = MatVec(src.rel.R, X_ref) + Vec3{src.rel.t[0], src.rel.t[1], src.rel.t[2]};
  if (!ProjectCameraPoint(src.camera, *X_src, us, vs)) return 0.f;
  // Range check in float before converting: near the source's image plane the projection
  // leaves every int range (or is inf/NaN), and a conversion of it is undefined.
  if (!(*us >= -0.5f && *vs >= -0.5f && *us + 0.5f < static_cast<float>(src.camera.width) &&
        *vs + 0.5f < static_cast<float>(src.camera.height))) {
    return 0.f;
  }
  const int col = static_cast<int>(*us + 0.5f);
  const int row = static_cast<int>(*vs + 0.5f);
  return src.depth[static_cast<long>(row) * src.camera.width + col];
}

// Forward-backward reprojection error (px) of the point at `depth` on the ray of (u, v)
// through source view s and its depth map, clamped to max_error (docs/algorithm.md §7).
MPMVS_HD inline float GeometricError(const PassParams& params, const SourceView& src, int u, int v,
                                     Vec3 ray, float depth) {
  const float max_error = params.geom_max_error;
  if (!(depth > 0.f)) return max_error;
  Vec3 X_src;
  float us, vs;
  const float d = SourceDepthAtPoint(src, depth * ray, &X_src, &us, &vs);
  if (!(d > 0.f)) return max_error;
  const Vec3 back = d * PixelRay(src.camera, us, vs);
  const Vec3 X_ref =
      MatVec(src.rel.Rinv, back) + Vec3{src.rel.tinv[0], src.rel.tinv[1], src.rel.tinv[2]};
  float ur, vr;
  if (!ProjectCameraPoint(params.ref_camera, X_ref, &ur, &vr)) return max_error;
  const float du = ur - static_cast<float>(u), dv = vr - static_cast<float>(v);
  return Min(sqrtf(du * du + dv * dv), max_error);
}

// Per-view photometric cost of a plane in source view s. Ncc is ScalarNcc (device,
// reference) or a vectorised CPU specialisation with the same contract (ncc_simd.h).
template <class Ncc>
MPMVS_HD MPMVS_FORCE_INLINE float ViewPhotoCost(const PassParams& params, const RefPatch& patch,
                                                int s, Vec3 m, int u, int v, uint32_t* num_ncc) {
  float H[9];
  PlaneHomography(params.sources[s].rel, m, H);
  const ImageView& image = params.sources[s].image;
  if (!NccDefined(patch, image, H, static_cast<float>(u), static_cast<float>(v))) return kInvalidCost;
  ++*num_ncc;  // only NCCs that sample their window count (the benchmark's samples/s)
  return Ncc::CostOfDefined(patch, image, H, u, v, params.window);
}

struct WeightedCost {
  float total;  // photo + lambda * geo
  float photo;
  float geo;
};

// View-weighted cost of a plane (docs/algorithm.md §3 step 6, §7).
//
// reject_at (refinement): once the views costed so far alone bring the total to reject_at
// or more, the plane cannot win and the remaining views are skipped; *rejected is then set
// and the returned cost is meaningless. Every per-view term is >= 0 and float rounding is
// monotone, so the full sum could only have been larger: skipping changes no result
// (kernels/DESIGN.md 18).
template <class Ncc>
MPMVS_HD inline WeightedCost EvaluatePlane(const PassParams& params, bool geometric,
                                           const RefPatch& patch, const float* weights, int u,
                                           int v, Vec3 ray, const Plane& plane,
                                           uint32_t* num_ncc, float reject_at = INFINITY,
                                           bool* rejected = nullptr) {
  const Vec3 m = HomographyPlaneVector(params.ref_camera, plane);
  const float depth = geometric ? PlaneDepth(plane, ray) : 0.f;
  // The weights are the view selection's draw counts: their sum is exact in any order.
  float wsum = 0.f;
  for (int s = 0; s < params.num_sources; ++s) wsum += Max(weights[s], 0.f);
  if (!(wsum > 0.f)) return WeightedCost{kInvalidCost, kInvalidCost, params.geom_max_error};
  float photo = 0.f, geo = 0.f;
  for (int s = 0; s < params.num_sources; ++s) {
    const float w = weights[s];
    if (w <= 0.f) continue;
    photo += w * ViewPhotoCost<Ncc>(params, patch, s, m, u, v, num_ncc);
    if (geometric) geo += w * GeometricError(params, params.sources[s], u, v, ray, depth);
    if (photo / wsum + params.geom_lambda * (geo / wsum) >= reject_at) {
      if (rejected) *rejected = true;
      return WeightedCost{kInvalidCost, kInvalidCost, params.geom_max_error};
    }
  }
  photo /= wsum;
  if (params.noise_variance > 0.f) photo = Max(photo, Min(1.f, params.noise_variance / patch.variance));
  geo = geometric ? geo / wsum : 0.f;
  return WeightedCost{photo + params.geom_lambda * geo, photo, geo};
}

// ACMP's beta of the prior score: the paper's value, and the texture-adaptive beta's floor.
constexpr float kAcmpBeta = 0.18f;

// Whether the texture-adaptive prior is on: the noise floor on (image noise variance > 0)
// and the prior's beta above ACMP's.
MPMVS_HD MPMVS_FORCE_INLINE bool TextureAdaptivePrior(float noise_variance, float prior_beta) {
  return noise_variance > 0.f && prior_beta > kAcmpBeta;
}
MPMVS_HD inline bool TextureAdaptivePrior(const PassParams& params) {
  return TextureAdaptivePrior(params.noise_variance, params.prior.beta);
}

// Whether a pass reads RefPatch::texture (ComputeRefPatch's with_texture).
MPMVS_HD MPMVS_FORCE_INLINE bool PriorNeedsTexture(const PassParams& params) {
  return params.use_prior && TextureAdaptivePrior(params);
}

// The prior score's beta at a pixel: with the texture-adaptive prior, it follows the
// window's texture (RefPatch::texture: what a linear ramp of shading does not explain), from
// ACMP's 0.18 on texture (the views decide) to prior.beta where the texture is no more than
// the image noise (the views cannot tell planes apart; the prior decides). Otherwise
// prior.beta everywhere (kernels/DESIGN.md 15, 16).
MPMVS_HD inline float PixelPriorBeta(const PassParams& params, const RefPatch& patch) {
  if (!TextureAdaptivePrior(params)) return params.prior.beta;
  const float flat = Min(1.f, params.noise_variance / Max(patch.texture, 1e-12f));
  return kAcmpBeta + (params.prior.beta - kAcmpBeta) * flat;
}

// Whether a window is plain: its texture (RefPatch::texture, with_texture) is at most twice
// the image noise variance, so its views cannot tell nearby planes apart.
MPMVS_HD MPMVS_FORCE_INLINE bool PlainWindow(const RefPatch& patch, float noise_variance) {
  constexpr float kMaxTextureToNoise = 2.f;
  return patch.texture <= kMaxTextureToNoise * noise_variance;
}

// Whether the prior acts at a labelled pixel of a prior pass: with the texture-adaptive
// prior only on plain windows; textured windows keep what their views say (kernels/DESIGN.md
// 16).
MPMVS_HD inline bool PixelPriorActive(const PassParams& params, const RefPatch& patch, int idx) {
  if (!params.use_prior || !params.prior.label[idx]) return false;
  return !TextureAdaptivePrior(params) || PlainWindow(patch, params.noise_variance);
}

// Costs of a flat pixel that takes its prior plane: NCC 0, no evidence either way. Where the
// views say nothing at all, the planar prior built from the verified vertices around the area
// is the estimate; later passes keep it, since no view can cost another plane there
// (kernels/DESIGN.md 21). Never a prior vertex (m_p < 0.2).
constexpr float kFlatPriorCost = 1.f;

// Fills a flat pixel from its prior plane (prior passes) or keeps its earlier estimate (a
// fill, or a coarser window's estimate: init_cost below kInvalidCost). False where neither
// applies.
MPMVS_HD inline bool FillFlatPixel(const PassParams& params, const PixelState& state, int idx,
                                   Vec3 ray, bool have, const Plane& earlier,
                                   const float* init_cost) {
  Plane plane;
  if (params.use_prior && params.prior.label[idx]) {
    plane = LoadPlane(params.prior.plane, idx);
  } else if (have && init_cost && init_cost[idx] < kInvalidCost) {
    plane = earlier;
  } else {
    return false;
  }
  if (!DepthInRange(params, PlaneDepth(plane, ray))) return false;
  StorePlane(state.plane, idx, plane);
  state.cost[idx] = kFlatPriorCost;
  state.photo_cost[idx] = kFlatPriorCost;
  state.geo_error[idx] = 0.f;
  state.view_mask[idx] = 0;
  return true;
}

// Whether a pixel's costs include the geometric term: in geometric passes, except where the
// prior acts. There it takes the term's place: the source maps it would pull towards are
// the previous pass's, which are wrong on exactly the plain surfaces the prior is for
// (kernels/DESIGN.md 16).
MPMVS_HD MPMVS_FORCE_INLINE bool PixelGeometric(const PassParams& params, bool prior_active) {
  return params.geometric && !prior_active;
}

// A plane's agreement with the prior plane (ACMP): gamma + depth and normal agreement.
MPMVS_HD inline float PriorCompatibility(const PlanarPrior& prior, const Plane& plane,
                                         const Plane& prior_plane, Vec3 ray) {
  const float depth = PlaneDepth(plane, ray);
  const float prior_depth = PlaneDepth(prior_plane, ray);
  const float dz = depth - prior_depth;
  const float cos_angle = Clamp(Dot(plane.n, prior_plane.n), -1.f, 1.f);
  const float angle = acosf(cos_angle);
  return prior.gamma + expf(-dz * dz / (2.f * prior.sigma_depth * prior.sigma_depth)) *
                           expf(-angle * angle / (2.f * prior.sigma_normal * prior.sigma_normal));
}

// Planar compatibility score to maximise (ACMP): exp(-C^2/beta) * PriorCompatibility.
MPMVS_HD inline float PriorScore(const PlanarPrior& prior, float beta, float cost, const Plane& plane,
                                 const Plane& prior_plane, Vec3 ray) {
  return expf(-cost * cost / beta) * PriorCompatibility(prior, plane, prior_plane, ray);
}

// The cost at or above which a plane of compatibility `compat` cannot beat prior score
// `score` (exp(-C^2/beta) * compat > score needs C^2 < beta * ln(compat / score)); with a
// margin of 1e-3 for the rounding of expf, logf and sqrtf, so that it only errs on the
// side of costing a plane in full.
MPMVS_HD MPMVS_FORCE_INLINE float PriorRejectCost(float beta, float compat, float score) {
  if (!(score > 0.f)) return INFINITY;
  if (compat <= score) return 0.f;
  return 1.001f * sqrtf(beta * logf(compat / score)) + 1e-6f;
}

// ---------------------------------------------------------------------------------------
// Initialisation

// Costs of `plane` in every view; cost = mean of the top_k smallest valid ones, mask = views
// at or below the k-th smallest (docs/algorithm.md §2).
template <class Ncc>
MPMVS_HD inline void InitialCost(const PassParams& params, bool geometric, const RefPatch& patch,
                                 int u, int v, Vec3 ray, const Plane& plane, float* cost,
                                 float* photo_cost,
                                 float* geo_error, uint32_t* mask, uint32_t* num_ncc) {
  const Vec3 m = HomographyPlaneVector(params.ref_camera, plane);
  const float depth = PlaneDepth(plane, ray);
  float photo[kMaxSourceViews], geo[kMaxSourceViews], total[kMaxSourceViews];
  int num_valid = 0;
  for (int s = 0; s < params.num_sources; ++s) {
    photo[s] = ViewPhotoCost<Ncc>(params, patch, s, m, u, v, num_ncc);
    geo[s] = geometric ? GeometricError(params, params.sources[s], u, v, ray, depth) : 0.f;
    total[s] = photo[s] + params.geom_lambda * geo[s];
    if (photo[s] < kInvalidCost) ++num_valid;
  }
  const int k = MinI(num_valid, params.init_top_k);
  if (k == 0) {
    *cost = kInvalidCost + (geometric ? params.geom_lambda * params.geom_max_error : 0.f);
    *photo_cost = kInvalidCost;
    *geo_error = geometric ? params.geom_max_error : 0.f;
    *mask = 0;
    return;
  }
  // k-th smallest total cost among valid views by repeated selection (k <= 4, N <= 32).
  uint32_t chosen = 0;
  float sum_total = 0.f, sum_photo = 0.f, sum_geo = 0.f, kth = 0.f;
  for (int i = 0; i < k; ++i) {
    int best = -1;
    for (int s = 0; s < params.num_sources; ++s) {
      if ((chosen >> s & 1u) || !(photo[s] < kInvalidCost)) continue;
      if (best < 0 || total[s] < total[best]) best = s;
    }
    chosen |= 1u << best;
    sum_total += total[best];
    sum_photo += photo[best];
    sum_geo += geo[best];
    kth = total[best];
  }
  uint32_t selected = 0;
  for (int s = 0; s < params.num_sources; ++s) {
    if (photo[s] < kInvalidCost && total[s] <= kth) selected |= 1u << s;
  }
  *cost = sum_total / k;
  *photo_cost = sum_photo / k;
  *geo_error = sum_geo / k;
  *mask = selected;
}

// Initial hypothesis of pixel (u, v). init_plane (optional) holds planes from an earlier
// stage (d = 0 means none); prior pixels whose earlier cost is >= 0.1 restart near the prior
// plane (ACMP's initialisation of the prior run).
template <class Ncc>
MPMVS_HD inline void InitializePixel(const PassParams& params, const PixelState& state,
                                     const float* init_plane, const float* init_cost, int u,
                                     int v, uint32_t* num_ncc) {
  const int W = params.ref_camera.width;
  const int idx = v * W + u;
  if (state.skips_left) state.skips_left[idx] = 0;
  const Vec3 ray = PixelRay(params.ref_camera, static_cast<float>(u), static_cast<float>(v));
  RandomStream rng(params.seed, params.image_id, static_cast<uint32_t>(idx), params.rng_iteration);
  Plane plane{Vec3{0.f, 0.f, -1.f}, 0.f};
  bool have = false;
  if (init_plane) {
    plane = LoadPlane(init_plane, idx);
    const float depth = PlaneDepth(plane, ray);
    have = plane.d != 0.f && DepthInRange(params, depth);
  }
  RefPatch patch;
  ComputeRefPatch(params.ref_image, u, v, params.window, &patch, PriorNeedsTexture(params));
  if (RefPatchIsFlat(patch) && FillFlatPixel(params, state, idx, ray, have, plane, init_cost)) return;
  const bool prior_pixel = PixelPriorActive(params, patch, idx);
  const bool geometric = PixelGeometric(params, prior_pixel);
  // The costs of the plane kept, where choosing it already computed them.
  bool costed = false;
  float cost = 0.f, photo_cost = 0.f, geo_error = 0.f;
  uint32_t view_mask = 0;
  if (prior_pixel && (!have || !init_cost || init_cost[idx] >= 0.1f)) {
    // ACMP restarts poorly matched pixels near the prior plane. Rather than overwriting the
    // earlier estimate, keep whichever of the two scores better under the prior score, so a
    // wrong prior never erases a good match (a deviation from ACMP, see kernels/DESIGN.md).
    const Plane prior_plane = LoadPlane(params.prior.plane, idx);
    const float depth = PlaneDepth(prior_plane, ray) * rng.Uniform(0.94f, 1.06f);
    const Vec3 n = PerturbNormal(&rng, prior_plane.n, 0.03f * kPi, ray);
    if (DepthInRange(params, depth)) {
      const Plane candidate = PlaneFromDepthNormal(ray, depth, n);
      if (!have) {
        plane = candidate;
        have = true;
      } else {
        float c_old, p_old, g_old, c_new, p_new, g_new;
        uint32_t m_old, m_new;
        InitialCost<Ncc>(params, geometric, patch, u, v, ray, plane, &c_old, &p_old, &g_old,
                         &m_old, num_ncc);
        InitialCost<Ncc>(params, geometric, patch, u, v, ray, candidate, &c_new, &p_new, &g_new,
                         &m_new, num_ncc);
        const float beta = PixelPriorBeta(params, patch);
        const bool take = PriorScore(params.prior, beta, c_new, candidate, prior_plane, ray) >
                          PriorScore(params.prior, beta, c_old, plane, prior_plane, ray);
        if (take) plane = candidate;
        costed = true;
        cost = take ? c_new : c_old;
        photo_cost = take ? p_new : p_old;
        geo_error = take ? g_new : g_old;
        view_mask = take ? m_new : m_old;
      }
    }
  }
  if (!have) {
    const float depth = rng.Uniform(params.depth_min, params.depth_max);
    plane = PlaneFromDepthNormal(ray, depth, RandomNormal(&rng, ray));
  }
  StorePlane(state.plane, idx, plane);
  if (!costed) {
    InitialCost<Ncc>(params, geometric, patch, u, v, ray, plane, &cost, &photo_cost, &geo_error, &view_mask,
                     num_ncc);
  }
  state.cost[idx] = cost;
  state.photo_cost[idx] = photo_cost;
  state.geo_error[idx] = geo_error;
  state.view_mask[idx] = view_mask;
}

// Whether an update that took a pixel's plane from `before` to `after` left it settled: its
// depth moved by at most 0.5 % and its normal by at most 3 degrees. Such moves are what
// random refinement keeps finding on a converged surface (a slightly better fit of the same
// window), well inside the 1 % that the evaluation and stereo_fusion tolerate. Skipping them
// holds the Middlebury scores, but plain surfaces lose the updates that slowly spread a
// right plane over them, hence off by default (kernels/DESIGN.md 27).
MPMVS_HD MPMVS_FORCE_INLINE bool SettledPlane(const Plane& before, const Plane& after, Vec3 ray) {
  constexpr float kMaxDepthChange = 0.005f;
  constexpr float kMinNormalCos = 0.99862953f;  // cos(3 degrees)
  const float d0 = PlaneDepth(before, ray), d1 = PlaneDepth(after, ray);
  return fabsf(d1 - d0) <= kMaxDepthChange * d0 && Dot(before.n, after.n) >= kMinNormalCos;
}

// ---------------------------------------------------------------------------------------
// Propagation + view selection + refinement of one pixel (one checkerboard pass), in the
// steps UpdatePixel runs them.

// The propagation candidates of a pixel: the best stored hypothesis of each region.
struct Candidates {
  Plane plane[kNumRegions];
  bool valid[kNumRegions];  // found, with a depth in range
  int pixel[kNumRegions];   // the pixel it comes from (-1: none)
};

// A pixel's planar prior: active on labelled pixels of prior passes.
struct PixelPrior {
  bool active;
  Plane plane;
  float beta;  // PixelPriorBeta
};

// The hypothesis a pixel holds during its update.
struct Hypothesis {
  Plane plane;
  WeightedCost cost;
  float score;    // PriorScore, kept up to date on prior pixels only
  uint32_t mask;  // its selected views
};

// Whether a hypothesis of cost `cost` and prior score `score` replaces `than`: a higher
// prior score on prior pixels, a lower cost elsewhere.
MPMVS_HD MPMVS_FORCE_INLINE bool Replaces(const PixelPrior& prior, const WeightedCost& cost,
                                          float score, const Hypothesis& than) {
  return prior.active ? score > than.score : cost.total < than.cost.total;
}

// The first valid candidate before r with r's plane, or -1: propagation often brings the
// same plane from several regions, whose costs are then computed once.
MPMVS_HD MPMVS_FORCE_INLINE int EarlierSameCandidate(const Candidates& cand, int r) {
  for (int q = 0; q < r; ++q) {
    if (cand.valid[q] && SamePlane(cand.plane[q], cand.plane[r])) return q;
  }
  return -1;
}

// 1. Best stored hypothesis per region (neighbours have the other colour: no races).
// All regions' choices first, then their planes: the plane loads (often cache misses
// with distant regions) are then independent and overlap instead of queueing.
MPMVS_HD MPMVS_FORCE_INLINE void GatherCandidates(const PassParams& params,
                                                  const PixelState& state, int u, int v,
                                                  Vec3 ray, Candidates* cand) {
  const int W = params.ref_camera.width, H = params.ref_camera.height;
  const int reach = params.pattern.reach;
  const bool interior = u >= reach && v >= reach && u + reach < W && v + reach < H;
  int best_of[kNumRegions];
  for (int r = 0; r < kNumRegions; ++r) {
    int best = -1;
    float best_cost = 0.f;
    for (int i = 0; i < params.pattern.num_samples[r]; ++i) {
      const int x = u + params.pattern.du[r][i];
      const int y = v + params.pattern.dv[r][i];
      if (!interior && (x < 0 || y < 0 || x >= W || y >= H)) continue;
      const int q = y * W + x;
      const float c = state.cost[q];
      if (best < 0 || c < best_cost) {
        best = q;
        best_cost = c;
      }
    }
    best_of[r] = best;
  }
  for (int r = 0; r < kNumRegions; ++r) {
    cand->valid[r] = false;
    cand->pixel[r] = best_of[r];
    if (best_of[r] >= 0) {
      cand->plane[r] = LoadPlane(state.plane, best_of[r]);
      cand->valid[r] = DepthInRange(params, PlaneDepth(cand->plane[r], ray));
    }
  }
}

// 2a. The source views the candidates are costed in: all, or with params.costed_views = M
// below the number of sources, the views most often selected last time by the pixel itself
// (counted twice), its four neighbours and the candidates' pixels, up to M - 1 of them, the
// rest explored in turn
// (a different view at each pixel and iteration), so that a view not selected nearby can
// still show that it sees the pixel. The view selection then chooses among these only.
MPMVS_HD MPMVS_FORCE_INLINE bool CostsFewerViews(const PassParams& params) {
  return params.costed_views > 0 && params.num_sources > params.costed_views;
}
MPMVS_HD MPMVS_FORCE_INLINE uint32_t CostedViews(const PassParams& params, const uint32_t* masks,
                                                 int num_masks, uint32_t own_mask, int idx) {
  // masks: the views last selected by the neighbours and by the candidates' pixels.
  const int N = params.num_sources;
  if (!CostsFewerViews(params)) return N >= 32 ? 0xffffffffu : (1u << N) - 1u;
  const int M = params.costed_views;
  int votes[kMaxSourceViews];
  for (int s = 0; s < N; ++s) {
    int n = (own_mask >> s & 1u) ? 2 : 0;
    for (int i = 0; i < num_masks; ++i) n += masks[i] >> s & 1u;
    votes[s] = n;
  }
  uint32_t costed = 0;
  int num_costed = 0;
  for (int level = 2 + num_masks; level > 0 && num_costed < M - 1; --level) {
    for (int s = 0; s < N && num_costed < M - 1; ++s) {
      if (votes[s] == level) {
        costed |= 1u << s;
        ++num_costed;
      }
    }
  }
  // Exploration: the next views not yet costed, from a start that turns with the pixel and
  // the iteration.
  const int start = static_cast<int>((static_cast<uint32_t>(idx) * 2654435761u + params.iteration * 40503u) % N);
  for (int k = 0; k < N && num_costed < M; ++k) {
    const int s = (start + k) % N;
    if (!(costed >> s & 1u)) {
      costed |= 1u << s;
      ++num_costed;
    }
  }
  return costed;
}

// 2b. Per-view photometric costs of the candidates, photo[r * N + s] (invalid regions and
// views not costed: cost 2, left out by the view selection).
template <class Ncc>
MPMVS_HD MPMVS_FORCE_INLINE void CandidatePhotoCosts(const PassParams& params,
                                                     const RefPatch& patch,
                                                     const Candidates& cand, uint32_t costed,
                                                     int u, int v, float* photo, uint32_t* num_ncc) {
  const int N = params.num_sources;
  for (int r = 0; r < kNumRegions; ++r) {
    if (!cand.valid[r]) {
      for (int s = 0; s < N; ++s) photo[r * N + s] = kInvalidCost;
      continue;
    }
    const int same = EarlierSameCandidate(cand, r);
    if (same >= 0) {
      for (int s = 0; s < N; ++s) photo[r * N + s] = photo[same * N + s];
      continue;
    }
    const Vec3 m = HomographyPlaneVector(params.ref_camera, cand.plane[r]);
    for (int s = 0; s < N; ++s) {
      photo[r * N + s] = (costed >> s & 1u) ? ViewPhotoCost<Ncc>(params, patch, s, m, u, v, num_ncc) : kInvalidCost;
    }
  }
}

// The selected-view masks of the (up to 4) direct neighbours; returns how many.
MPMVS_HD MPMVS_FORCE_INLINE int NeighbourMasks(const PassParams& params, const PixelState& state, int u, int v,
                                               uint32_t* masks) {
  const int W = params.ref_camera.width, H = params.ref_camera.height;
  const int idx = v * W + u;
  int n = 0;
  if (v > 0) masks[n++] = state.view_mask[idx - W];
  if (v + 1 < H) masks[n++] = state.view_mask[idx + W];
  if (u > 0) masks[n++] = state.view_mask[idx - 1];
  if (u + 1 < W) masks[n++] = state.view_mask[idx + 1];
  return n;
}

// The views a pixel's candidates are costed in (CostedViews), from the masks stored around it.
MPMVS_HD MPMVS_FORCE_INLINE uint32_t ViewsToCost(const PassParams& params, const PixelState& state,
                                                 const Candidates& cand, const uint32_t* neighbour_masks,
                                                 int num_neighbours, int idx) {
  if (!CostsFewerViews(params)) return ~0u;
  uint32_t masks[4 + kNumRegions];
  int num_masks = 0;
  for (int i = 0; i < num_neighbours; ++i) masks[num_masks++] = neighbour_masks[i];
  for (int r = 0; r < kNumRegions; ++r) {
    if (cand.valid[r]) masks[num_masks++] = state.view_mask[cand.pixel[r]];
  }
  return CostedViews(params, masks, num_masks, state.view_mask[idx], idx);
}

// 3. View selection among the costed views, with the prior of the four neighbours' views;
// returns the selected views, their weights in `weights`.
MPMVS_HD MPMVS_FORCE_INLINE uint32_t SelectPixelViews(const PassParams& params, const uint32_t* neighbour_masks,
                                                      int num_neighbours, uint32_t costed,
                                                      const float* photo, const bool* valid,
                                                      RandomStream* rng, float* weights) {
  float prior[kMaxSourceViews];
  NeighbourViewPrior(neighbour_masks, num_neighbours, params.num_sources, params.view_selection,
                     prior);
  if (CostsFewerViews(params)) {
    for (int s = 0; s < params.num_sources; ++s) {
      if (!(costed >> s & 1u)) prior[s] = 0.f;
    }
  }
  return SelectViews(photo, valid, params.num_sources, prior, params.view_selection, rng, weights);
}

// 4a. View-weighted costs of the valid candidates from their per-view photometric costs,
// plus the geometric term when `geometric` (PixelGeometric).
MPMVS_HD MPMVS_FORCE_INLINE void CandidateCosts(const PassParams& params, bool geometric,
                                                const float* weights, const Candidates& cand,
                                                const float* photo,
                                                int u, int v, Vec3 ray, WeightedCost* costs) {
  const int N = params.num_sources;
  float wsum = 0.f;
  for (int s = 0; s < N; ++s) wsum += weights[s];
  for (int r = 0; r < kNumRegions; ++r) {
    if (!cand.valid[r]) continue;
    const int same = EarlierSameCandidate(cand, r);
    if (same >= 0) {
      costs[r] = costs[same];
      continue;
    }
    WeightedCost c;
    c.photo = 0.f;
    for (int s = 0; s < N; ++s) c.photo += weights[s] * photo[r * N + s];
    c.photo /= wsum;
    c.geo = 0.f;
    if (geometric) {
      const float depth = PlaneDepth(cand.plane[r], ray);
      for (int s = 0; s < N; ++s) {
        if (weights[s] > 0.f)
          c.geo += weights[s] * GeometricError(params, params.sources[s], u, v, ray, depth);
      }
      c.geo /= wsum;
    }
    c.total = c.photo + params.geom_lambda * c.geo;
    costs[r] = c;
  }
}

// 4b. The pixel's stored hypothesis, costed with the new view weights (a candidate's cost
// when one is the stored plane itself, which is common once a region has converged).
template <class Ncc>
MPMVS_HD MPMVS_FORCE_INLINE Hypothesis StoredHypothesis(
    const PassParams& params, const PixelState& state, const RefPatch& patch,
    const float* weights, const Candidates& cand, const WeightedCost* costs,
    const PixelPrior& prior, int u, int v, Vec3 ray, uint32_t* num_ncc) {
  const int idx = v * params.ref_camera.width + u;
  Hypothesis h;
  h.plane = LoadPlane(state.plane, idx);
  h.mask = state.view_mask[idx];
  int current_row = -1;
  for (int r = 0; r < kNumRegions && current_row < 0; ++r) {
    if (cand.valid[r] && SamePlane(cand.plane[r], h.plane)) current_row = r;
  }
  h.cost = current_row >= 0 ? costs[current_row]
                            : EvaluatePlane<Ncc>(params, PixelGeometric(params, prior.active), patch,
                                                 weights, u, v, ray, h.plane, num_ncc);
  h.score = prior.active ? PriorScore(params.prior, prior.beta, h.cost.total, h.plane, prior.plane, ray) : 0.f;
  return h;
}

// 4c. The best candidate replaces the stored hypothesis if it is better, with the views
// selected in step 3.
MPMVS_HD MPMVS_FORCE_INLINE void AdoptBestCandidate(const PassParams& params,
                                                    const Candidates& cand,
                                                    const WeightedCost* costs,
                                                    const PixelPrior& prior, Vec3 ray,
                                                    uint32_t selected, Hypothesis* current) {
  int best_r = -1;
  Hypothesis best{Plane{}, WeightedCost{0.f, 0.f, 0.f}, 0.f, selected};
  for (int r = 0; r < kNumRegions; ++r) {
    if (!cand.valid[r]) continue;
    const float score =
        prior.active ? PriorScore(params.prior, prior.beta, costs[r].total, cand.plane[r], prior.plane, ray) : 0.f;
    if (best_r < 0 || Replaces(prior, costs[r], score, best)) {
      best_r = r;
      best.plane = cand.plane[r];
      best.cost = costs[r];
      best.score = score;
    }
  }
  if (best_r >= 0 && Replaces(prior, best.cost, best.score, *current)) *current = best;
}

// 5a. The 5 refinement planes around / away from the current one (ACMP's sampling around
// the prior plane on prior pixels; the reference MP-MVS code lost that branch).
struct RefinementPlanes {
  float depth[5];
  Vec3 normal[5];
};
MPMVS_HD MPMVS_FORCE_INLINE RefinementPlanes RefinementCandidates(const PassParams& params,
                                                                  const PixelPrior& prior,
                                                                  Vec3 ray, const Plane& current,
                                                                  RandomStream* rng) {
  const float depth_now = PlaneDepth(current, ray);
  float depth_rand;
  Vec3 normal_rand;
  if (prior.active) {
    const float prior_depth = PlaneDepth(prior.plane, ray);
    const float span = 3.f * params.prior.sigma_depth;
    depth_rand = Clamp(rng->Uniform(prior_depth - span, prior_depth + span), params.depth_min,
                       params.depth_max);
    normal_rand = PerturbNormal(rng, prior.plane.n, 0.5f * params.prior.sigma_normal, ray);
  } else {
    depth_rand = rng->Uniform(params.depth_min, params.depth_max);
    normal_rand = RandomNormal(rng, ray);
  }
  const float rho = params.refinement.rho;
  const float depth_perturbed = rng->Uniform((1.f - rho) * depth_now, (1.f + rho) * depth_now);
  const Vec3 normal_perturbed = PerturbNormal(rng, current.n, 0.5f * rho * kPi, ray);
  const Vec3 normal_now = current.n;
  return RefinementPlanes{{depth_rand, depth_now, depth_rand, depth_now, depth_perturbed},
                          {normal_now, normal_rand, normal_rand, normal_perturbed, normal_now}};
}

// 5b. Random refinement: each refinement plane in range replaces the current one if better.
template <class Ncc>
MPMVS_HD MPMVS_FORCE_INLINE void Refine(const PassParams& params, const RefPatch& patch,
                                        const float* weights, const PixelPrior& prior, int u,
                                        int v, Vec3 ray, RandomStream* rng, Hypothesis* current,
                                        uint32_t* num_ncc) {
  const RefinementPlanes planes = RefinementCandidates(params, prior, ray, current->plane, rng);
  for (int i = 0; i < 5; ++i) {
    if (!DepthInRange(params, planes.depth[i])) continue;
    const Plane plane = PlaneFromDepthNormal(ray, planes.depth[i], planes.normal[i]);
    const float compat = prior.active ? PriorCompatibility(params.prior, plane, prior.plane, ray) : 0.f;
    const float reject_at = prior.active ? PriorRejectCost(prior.beta, compat, current->score) : current->cost.total;
    bool rejected = false;
    const WeightedCost c = EvaluatePlane<Ncc>(params, PixelGeometric(params, prior.active), patch, weights,
                                              u, v, ray, plane, num_ncc, reject_at, &rejected);
    if (rejected) continue;
    const float score = prior.active ? expf(-c.total * c.total / prior.beta) * compat : 0.f;
    if (Replaces(prior, c, score, *current)) {
      current->plane = plane;
      current->cost = c;
      current->score = score;
    }
  }
}

// One checkerboard update of pixel (u, v): propagation candidates, view selection, their
// costs, the better of them and the stored hypothesis, then random refinement.
template <class Ncc>
MPMVS_HD inline void UpdatePixel(const PassParams& params, const PixelState& state, int u, int v,
                                 uint32_t* num_ncc) {
  const int idx = v * params.ref_camera.width + u;
  // Only this pixel's own update reads or writes its skip count: no races, and the result
  // does not depend on the order or the number of threads.
  if (state.skips_left && state.skips_left[idx] > 0) {
    if (params.new_window_scale) {
      state.skips_left[idx] = 0;
    } else {
      --state.skips_left[idx];
      return;
    }
  }
  const Vec3 ray = PixelRay(params.ref_camera, static_cast<float>(u), static_cast<float>(v));
  RandomStream rng(params.seed, params.image_id, static_cast<uint32_t>(idx), params.rng_iteration);
  RefPatch patch;
  ComputeRefPatch(params.ref_image, u, v, params.window, &patch, PriorNeedsTexture(params));
  // A flat pixel with an estimate (a fill, or a coarser window's) keeps it: no view can cost
  // another plane here (FillFlatPixel).
  if (RefPatchIsFlat(patch) && state.photo_cost[idx] < kInvalidCost) return;

  Candidates cand;
  GatherCandidates(params, state, u, v, ray, &cand);
  uint32_t neighbour_masks[4];
  const int num_neighbours = NeighbourMasks(params, state, u, v, neighbour_masks);
  const uint32_t costed = ViewsToCost(params, state, cand, neighbour_masks, num_neighbours, idx);
  float photo[kNumRegions * kMaxSourceViews];
  CandidatePhotoCosts<Ncc>(params, patch, cand, costed, u, v, photo, num_ncc);
  float weights[kMaxSourceViews];
  const uint32_t selected =
      SelectPixelViews(params, neighbour_masks, num_neighbours, costed, photo, cand.valid, &rng, weights);

  PixelPrior prior{PixelPriorActive(params, patch, idx), Plane{}, 0.f};
  if (prior.active) {
    prior.plane = LoadPlane(params.prior.plane, idx);
    prior.beta = PixelPriorBeta(params, patch);
  }
  WeightedCost costs[kNumRegions];
  CandidateCosts(params, PixelGeometric(params, prior.active), weights, cand, photo, u, v, ray,
                 costs);
  Hypothesis current = StoredHypothesis<Ncc>(params, state, patch, weights, cand, costs, prior, u,
                                             v, ray, num_ncc);
  const Plane before = current.plane;
  AdoptBestCandidate(params, cand, costs, prior, ray, selected, &current);
  Refine<Ncc>(params, patch, weights, prior, u, v, ray, &rng, &current, num_ncc);
  if (state.skips_left && SettledPlane(before, current.plane, ray)) {
    state.skips_left[idx] = static_cast<uint8_t>(params.settled_skips);
  }

  StorePlane(state.plane, idx, current.plane);
  state.cost[idx] = current.cost.total;
  state.photo_cost[idx] = current.cost.photo;
  state.geo_error[idx] = current.cost.geo;
  state.view_mask[idx] = current.mask;
}

// Depth and camera-frame normal of the final plane; 0 where the pixel has no valid estimate.
MPMVS_HD inline void ExtractDepthNormal(const PassParams& params, const PixelState& state, int u,
                                        int v, float* depth, Vec3* normal) {
  const int idx = v * params.ref_camera.width + u;
  const Plane plane = LoadPlane(state.plane, idx);
  const Vec3 ray = PixelRay(params.ref_camera, static_cast<float>(u), static_cast<float>(v));
  const float z = PlaneDepth(plane, ray);
  if (!(state.photo_cost[idx] < kInvalidCost) || !DepthInRange(params, z)) {
    *depth = 0.f;
    *normal = Vec3{0.f, 0.f, 0.f};
    return;
  }
  *depth = z;
  *normal = plane.n;
}

}  // namespace kernels
}  // namespace mpmvs

#pragma once
// COLMAP-style output filter (--PatchMatchStereo.filter): a pixel is kept when at least
// min_num_consistent source views see its plane photo-consistently (NCC >= min_ncc, in
// params.window: the caller sets the finest window, WindowForScale(0)), under
// a triangulation angle >= min_triangulation_angle and, in geometric stages, with a
// forward-backward reprojection error <= geom_max_error.
#include <math.h>

#include "kernels/patch_match_pixel.h"

namespace mpmvs {
namespace kernels {

struct FilterParams {
  float min_ncc = 0.1f;
  float min_triangulation_angle_deg = 3.f;
  int min_num_consistent = 2;
  float max_reprojection_error = 1.f;
};

template <class Ncc>
MPMVS_HD inline bool PixelPassesFilter(const PassParams& params, const FilterParams& filter,
                                       const PixelState& state, int u, int v) {
  const int idx = v * params.ref_camera.width + u;
  const Plane plane = LoadPlane(state.plane, idx);
  const Vec3 ray = PixelRay(params.ref_camera, static_cast<float>(u), static_cast<float>(v));
  const float depth = PlaneDepth(plane, ray);
  if (!(state.photo_cost[idx] < kInvalidCost) || !DepthInRange(params, depth)) return false;
  RefPatch patch;
  ComputeRefPatch(params.ref_image, u, v, params.window, &patch);
  const Vec3 m = HomographyPlaneVector(params.ref_camera, plane);
  const Vec3 X = depth * ray;
  const float cos_min = cosf(filter.min_triangulation_angle_deg * kPi / 180.f);
  int consistent = 0;
  for (int s = 0; s < params.num_sources; ++s) {
    const SourceView& src = params.sources[s];
    float H[9];
    PlaneHomography(src.rel, m, H);
    const float cost = NccCost<Ncc>(patch, src.image, H, u, v, params.window);
    if (1.f - cost < filter.min_ncc) continue;
    // Source centre in the reference frame is tinv; the angle at X between both rays.
    const Vec3 to_ref = Normalize(-X);
    const Vec3 to_src = Normalize(Vec3{src.rel.tinv[0], src.rel.tinv[1], src.rel.tinv[2]} - X);
    if (Dot(to_ref, to_src) > cos_min) continue;
    if (params.geometric && GeometricError(params, src, u, v, ray, depth) > filter.max_reprojection_error) continue;
    ++consistent;
  }
  return consistent >= MinI(filter.min_num_consistent, params.num_sources);
}

// How far a source's depth map is from the point X_ref (reference frame), relative to the
// point's depth seen from the source: |source depth at the nearest pixel - point depth| /
// point depth (the depth test of COLMAP's stereo_fusion). kNoDepthDifference where the source
// is occluded there, has no depth there or does not see the point.
constexpr float kNoDepthDifference = 3.0e38f;
MPMVS_HD inline float SourceDepthDifference(const SourceView& src, Vec3 X_ref) {
  if (!src.depth) return kNoDepthDifference;
  Vec3 X;
  float us, vs;
  const float d = SourceDepthAtPoint(src, X_ref, &X, &us, &vs);
  return d > 0.f ? fabsf(d - X.z) / X.z : kNoDepthDifference;
}

// Whether a source's depth map confirms the point: within max_relative_error of it.
MPMVS_HD inline bool SourceConfirmsDepth(const SourceView& src, Vec3 X_ref, float max_relative_error) {
  return SourceDepthDifference(src, X_ref) < max_relative_error;
}

// The pixel's point (depth * ray) when it has a valid depth in range, else false.
MPMVS_HD inline bool PixelPoint(const PassParams& params, const PixelState& state, int u, int v, Vec3* X) {
  const int idx = v * params.ref_camera.width + u;
  const Vec3 ray = PixelRay(params.ref_camera, static_cast<float>(u), static_cast<float>(v));
  const float depth = PlaneDepth(LoadPlane(state.plane, idx), ray);
  if (!(state.photo_cost[idx] < kInvalidCost) || !DepthInRange(params, depth)) return false;
  *X = depth * ray;
  return true;
}

// The difference within which min_views (1 to kMaxSourceViews) sources confirm the pixel's depth:
// the min_views-th smallest SourceDepthDifference over its sources; kNoDepthDifference
// without a valid depth or with fewer sources that hold a depth there.
MPMVS_HD inline float PixelConfirmingDifference(const PassParams& params, const PixelState& state, int u, int v,
                                                int min_views) {
  Vec3 X;
  if (!PixelPoint(params, state, u, v, &X) || min_views > params.num_sources) return kNoDepthDifference;
  if (min_views < 1) return 0.f;
  float smallest[kMaxSourceViews];  // ascending, the min_views smallest so far
  int held = 0;
  for (int s = 0; s < params.num_sources; ++s) {
    const float d = SourceDepthDifference(params.sources[s], X);
    if (held == min_views && !(d < smallest[held - 1])) continue;
    int i = held < min_views ? held++ : held - 1;
    for (; i > 0 && smallest[i - 1] > d; --i) smallest[i] = smallest[i - 1];
    smallest[i] = d;
  }
  return smallest[min_views - 1];
}

// Bit s set for each source s whose depth map confirms the pixel's depth (as above); 0
// for a pixel without a valid depth.
MPMVS_HD inline uint32_t PixelConfirmingViews(const PassParams& params, const PixelState& state, int u, int v,
                                              float max_relative_error) {
  Vec3 X;
  if (!PixelPoint(params, state, u, v, &X)) return 0u;
  uint32_t views = 0u;
  for (int s = 0; s < params.num_sources; ++s) {
    if (SourceConfirmsDepth(params.sources[s], X, max_relative_error)) views |= 1u << s;
  }
  return views;
}

}  // namespace kernels
}  // namespace mpmvs

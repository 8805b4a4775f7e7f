#pragma once
// Per-run median filter of depths (docs/algorithm.md §9.1, plane-aware: kernels/DESIGN.md item 12).
// One pixel of one checkerboard colour; its 20 neighbours have the other colour, so all
// pixels of a colour can be filtered in parallel.
#include "kernels/patch_match_pixel.h"

namespace mpmvs {
namespace kernels {

struct MedianFilterInput {
  Camera camera;
  float depth_min = 0.f, depth_max = 1.f;
  float* plane = nullptr;             // 4 floats per pixel, updated in place
  const float* cost = nullptr;        // pixels with cost < 0.001 are left alone
  const float* photo_cost = nullptr;  // >= kInvalidCost: neither read nor changed
};

// The pixel's depth becomes the median of its own and of the depths that its valid
// neighbours' planes give on its ray; the plane moves along the ray, the normal is kept.
MPMVS_HD inline void MedianFilterPixel(const MedianFilterInput& in, int u, int v) {
  const int W = in.camera.width, H = in.camera.height;
  const int idx = v * W + u;
  if (!(in.photo_cost[idx] < kInvalidCost) || in.cost[idx] < 0.001f) return;
  const Vec3 ray = PixelRay(in.camera, static_cast<float>(u), static_cast<float>(v));
  const Plane own = LoadPlane(in.plane, idx);
  const float z = PlaneDepth(own, ray);
  if (!(z >= in.depth_min && z <= in.depth_max)) return;
  // (0,+-1), (0,+-3), (0,+-5), (+-1,0), (+-3,0), (+-5,0), (+-2,+-1), (+-1,+-2).
  const int du[20] = {0, 0, 0, 0, 0, 0, 1, -1, 3, -3, 5, -5, 2, 2, -2, -2, 1, 1, -1, -1};
  const int dv[20] = {1, -1, 3, -3, 5, -5, 0, 0, 0, 0, 0, 0, 1, -1, 1, -1, 2, -2, 2, -2};
  // On a slanted surface the neighbours' planes agree on this ray, where their raw depths
  // would pull a one-sided (border) median off the surface.
  float values[21];
  int count = 0;
  values[count++] = z;
  for (int k = 0; k < 20; ++k) {
    const int x = u + du[k], y = v + dv[k];
    if (x < 0 || y < 0 || x >= W || y >= H) continue;
    const int q = y * W + x;
    if (!(in.photo_cost[q] < kInvalidCost)) continue;
    const float zq = PlaneDepth(LoadPlane(in.plane, q), ray);
    if (zq >= in.depth_min && zq <= in.depth_max) values[count++] = zq;
  }
  // Median by rank counting over a fixed-size padded array: no data-dependent branches
  // (a sort of random depths mispredicts most of its comparisons). Value i occupies the
  // sorted positions [#less, #less-or-equal), so ties need no index order; the result
  // equals the sorted-array median.
  constexpr int kMaxValues = 21;
  for (int i = count; i < kMaxValues; ++i) values[i] = INFINITY;  // ranks after every depth
  int less[kMaxValues], less_equal[kMaxValues];
  for (int i = 0; i < kMaxValues; ++i) less[i] = less_equal[i] = 0;
  for (int j = 0; j < kMaxValues; ++j) {  // inner loop over i: vectorises without reductions
    for (int i = 0; i < kMaxValues; ++i) {
      less[i] += values[j] < values[i] ? 1 : 0;
      less_equal[i] += values[j] <= values[i] ? 1 : 0;
    }
  }
  const int lo = (count - 1) / 2, hi = count / 2;
  float value_lo = z, value_hi = z;
  for (int i = 0; i < kMaxValues; ++i) {
    value_lo = less[i] <= lo && lo < less_equal[i] ? values[i] : value_lo;
    value_hi = less[i] <= hi && hi < less_equal[i] ? values[i] : value_hi;
  }
  const float median = 0.5f * (value_lo + value_hi);
  if (median != z) StorePlane(in.plane, idx, PlaneFromDepthNormal(ray, median, own.n));
}

}  // namespace kernels
}  // namespace mpmvs

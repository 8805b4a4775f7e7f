#include "kernels/depth_segments.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace mpmvs {
namespace kernels {

size_t InvalidateSmallDepthSegments(const PatchMatchProblem& problem, int min_pixels, float max_relative_step,
                                    PatchMatchResult* result) {
  const int W = result->width, H = result->height;
  std::vector<float> depth, normal;
  ExtractDepthNormalMaps(problem, *result, &depth, &normal);  // 0 where there is no depth
  auto joined = [&](size_t a, size_t b) {
    const float da = depth[a], db = depth[b];
    return da > 0.f && db > 0.f && std::abs(da - db) < max_relative_step * std::min(da, db);
  };
  std::vector<uint8_t> visited(depth.size(), 0);
  std::vector<size_t> members;  // the current segment's pixels, also the flood fill's queue
  size_t removed = 0;
  for (size_t seed = 0; seed < depth.size(); ++seed) {
    if (!(depth[seed] > 0.f) || visited[seed]) continue;
    members.assign(1, seed);
    visited[seed] = 1;
    for (size_t k = 0; k < members.size(); ++k) {
      const size_t i = members[k];
      const int u = static_cast<int>(i % W), v = static_cast<int>(i / W);
      const size_t next[4] = {i - 1, i + 1, i - W, i + W};
      const bool inside[4] = {u > 0, u + 1 < W, v > 0, v + 1 < H};
      for (int n = 0; n < 4; ++n) {
        if (inside[n] && !visited[next[n]] && joined(i, next[n])) {
          visited[next[n]] = 1;
          members.push_back(next[n]);
        }
      }
    }
    if (members.size() >= static_cast<size_t>(min_pixels)) continue;
    for (size_t i : members) result->photo_cost[i] = kInvalidCost;
    removed += members.size();
  }
  return removed;
}

}  // namespace kernels
}  // namespace mpmvs

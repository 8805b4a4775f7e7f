#include "colmap_ext/prior/image_noise.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace mpmvs {

float EstimateNoiseVariance(const GrayImage& image) {
  const int W = image.width, H = image.height;
  if (W < 3 || H < 3) return 0.f;
  std::vector<float> response;
  response.reserve(static_cast<size_t>(W - 2) * (H - 2));
  const float* I = image.data.data();
  for (int v = 1; v + 1 < H; ++v) {
    for (int u = 1; u + 1 < W; ++u) {
      const float* r0 = I + static_cast<size_t>(v - 1) * W + u;
      const float* r1 = r0 + W;
      const float* r2 = r1 + W;
      const float n = (r0[-1] - 2.f * r0[0] + r0[1]) - 2.f * (r1[-1] - 2.f * r1[0] + r1[1]) +
                      (r2[-1] - 2.f * r2[0] + r2[1]);
      response.push_back(std::fabs(n));
    }
  }
  auto mid = response.begin() + response.size() / 2;
  std::nth_element(response.begin(), mid, response.end());
  // median |N(0, s^2)| = 0.6745 s, and the mask's response to noise of sigma has s = 6 sigma.
  const float sigma = *mid / (0.6745f * 6.f);
  return sigma * sigma;
}

}  // namespace mpmvs

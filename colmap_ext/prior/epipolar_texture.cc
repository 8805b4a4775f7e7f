#include "colmap_ext/prior/epipolar_texture.h"

#include <cmath>

#include "colmap_ext/util/thread_range.h"

namespace mpmvs {

std::vector<uint8_t> EpipolarBlindMask(const kernels::ImageView& ref, const kernels::Camera& ref_camera,
                                       const std::vector<kernels::Camera>& sources,
                                       const kernels::WindowSpec& window, float noise_variance,
                                       float max_ratio, const std::vector<uint8_t>& candidate,
                                       int num_threads) {
  const int W = ref.width, H = ref.height;
  std::vector<uint8_t> blind(static_cast<size_t>(W) * H, 0);
  std::vector<kernels::Vec3> centres;  // the sources' centres in the reference camera's frame
  for (const kernels::Camera& src : sources) {
    const kernels::RelativePose rel = kernels::ComputeRelativePose(ref_camera, src);
    centres.push_back(kernels::Vec3{rel.tinv[0], rel.tinv[1], rel.tinv[2]});
  }
  const float limit = max_ratio * 2.f * noise_variance;
  const kernels::Camera& c = ref_camera;
  RunRangeInThreads(H, num_threads, [&](int begin, int end) {
    for (int v = begin; v < end; ++v) {
      for (int u = 0; u < W; ++u) {
        const size_t i = static_cast<size_t>(v) * W + u;
        if (!candidate[i]) continue;
        bool seen = false;
        for (const kernels::Vec3& C : centres) {
          // Pixel minus epipole, times the centre's depth (finite for an epipole at infinity).
          float dx = C.z * (u - c.cx) - c.fx * C.x, dy = C.z * (v - c.cy) - c.fy * C.y;
          const float norm = std::sqrt(dx * dx + dy * dy);
          if (!(norm > 1e-6f * (std::abs(c.fx * C.x) + std::abs(c.fy * C.y) + std::abs(C.z)))) continue;
          dx /= norm;
          dy /= norm;
          float sum = 0.f, sum2 = 0.f;
          for (int k = 0; k < kernels::kWindowSamples; ++k) {
            const float x = static_cast<float>(u + kernels::WindowOffset(window, k % kernels::kWindowSamplesPerAxis));
            const float y = static_cast<float>(v + kernels::WindowOffset(window, k / kernels::kWindowSamplesPerAxis));
            const float d = kernels::SampleBilinear(ref, x + dx, y + dy) - kernels::SampleBilinear(ref, x - dx, y - dy);
            sum += d;
            sum2 += d * d;
          }
          const float mean = sum / kernels::kWindowSamples;
          if (sum2 / kernels::kWindowSamples - mean * mean > limit) {
            seen = true;
            break;
          }
        }
        blind[i] = !seen;
      }
    }
  });
  return blind;
}

}  // namespace mpmvs

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
          // Noise variance of the difference of two bilinear samples at +-(a, b) around a
          // pixel: the centre pixel's share cancels, six pixels remain. 2 sigma^2 along an
          // axis, 0.67 sigma^2 on a diagonal.
          const float a = std::abs(dx), b = std::abs(dy);
          const float noise = 2.f * noise_variance *
                              ((a * (1.f - b)) * (a * (1.f - b)) + ((1.f - a) * b) * ((1.f - a) * b) + (a * b) * (a * b));
          float sum = 0.f, sum2 = 0.f;
          int n = 0;
          for (int k = 0; k < kernels::kWindowSamples; ++k) {
            const float x = static_cast<float>(u + kernels::WindowOffset(window, k % kernels::kWindowSamplesPerAxis));
            const float y = static_cast<float>(v + kernels::WindowOffset(window, k / kernels::kWindowSamplesPerAxis));
            // Samples whose points leave the image would read the repeated border.
            if (!(x - a >= 0.f && x + a <= W - 1.f && y - b >= 0.f && y + b <= H - 1.f)) continue;
            const float d = kernels::SampleBilinear(ref, x + dx, y + dy) - kernels::SampleBilinear(ref, x - dx, y - dy);
            sum += d;
            sum2 += d * d;
            ++n;
          }
          if (n < kernels::kWindowSamples / 2) {  // too little of the window to tell
            seen = true;
            break;
          }
          const float mean = sum / n;
          if (sum2 / n - mean * mean > max_ratio * noise) {
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

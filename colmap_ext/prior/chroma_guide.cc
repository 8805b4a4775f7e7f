#include "colmap_ext/prior/chroma_guide.h"

#include <algorithm>
#include <string>

#include "colmap_ext/util/error.h"

namespace mpmvs {
namespace {

// One [1 2 1]/4 pass along x or y of a 2-channel interleaved image (clamp-to-edge).
void BinomialPass(int width, int height, bool along_x, const std::vector<float>& in,
                  std::vector<float>* out) {
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int x0 = along_x ? std::max(x - 1, 0) : x, x1 = along_x ? std::min(x + 1, width - 1) : x;
      const int y0 = along_x ? y : std::max(y - 1, 0), y1 = along_x ? y : std::min(y + 1, height - 1);
      const size_t c = 2 * (static_cast<size_t>(y) * width + x);
      const size_t a = 2 * (static_cast<size_t>(y0) * width + x0);
      const size_t b = 2 * (static_cast<size_t>(y1) * width + x1);
      for (int ch = 0; ch < 2; ++ch) {
        (*out)[c + ch] = 0.25f * (in[a + ch] + 2.f * in[c + ch] + in[b + ch]);
      }
    }
  }
}

}  // namespace

std::vector<float> MakeChromaGuide(const RgbImage& image, float weight) {
  const size_t n = static_cast<size_t>(image.width) * image.height;
  if (image.width <= 0 || image.height <= 0 || image.data.size() != 3 * n) {
    throw Error("MakeChromaGuide: RGB data of " + std::to_string(image.data.size()) +
                " bytes does not match " + std::to_string(image.width) + "x" +
                std::to_string(image.height));
  }
  std::vector<float> guide(2 * n), scratch(2 * n);
  for (size_t i = 0; i < n; ++i) {
    const float g = image.data[3 * i + 1];
    guide[2 * i] = weight * (image.data[3 * i] - g);
    guide[2 * i + 1] = weight * (image.data[3 * i + 2] - g);
  }
  for (int pass = 0; pass < kChromaSmoothingPasses; ++pass) {
    BinomialPass(image.width, image.height, true, guide, &scratch);
    BinomialPass(image.width, image.height, false, scratch, &guide);
  }
  return guide;
}

}  // namespace mpmvs

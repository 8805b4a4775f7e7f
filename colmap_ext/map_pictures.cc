#include "colmap_ext/map_pictures.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/image_io.h"

namespace mpmvs {
namespace {

// A compact perceptual rainbow ("turbo"-like) via piecewise-linear control points.
void ColorMap(float t, uint8_t* rgb) {
  static const float kStops[6][3] = {{48, 18, 59},   {40, 126, 230}, {33, 210, 160},
                                     {190, 240, 50}, {250, 140, 30}, {122, 4, 3}};
  t = std::min(1.f, std::max(0.f, t)) * 5.f;
  const int i = std::min(4, static_cast<int>(t));
  const float f = t - i;
  for (int c = 0; c < 3; ++c) {
    rgb[c] = static_cast<uint8_t>(kStops[i][c] + f * (kStops[i + 1][c] - kStops[i][c]) + 0.5f);
  }
}

}  // namespace

void WriteDepthPicture(const std::string& path, const FloatMap& depth, float depth_min, float depth_max) {
  RgbImage img;
  img.width = depth.width;
  img.height = depth.height;
  img.data.assign(3 * static_cast<size_t>(img.width) * img.height, 0);
  const float range = std::max(depth_max - depth_min, 1e-6f);
  for (int r = 0; r < depth.height; ++r) {
    for (int c = 0; c < depth.width; ++c) {
      const float z = depth.At(r, c);
      if (!(z > 0.f)) continue;
      ColorMap(1.f - (z - depth_min) / range, &img.data[3 * (static_cast<size_t>(r) * img.width + c)]);
    }
  }
  WriteRgbPng(path, img);
}

void WriteNormalPicture(const std::string& path, const FloatMap& normal) {
  RgbImage img;
  img.width = normal.width;
  img.height = normal.height;
  img.data.assign(3 * static_cast<size_t>(img.width) * img.height, 0);
  for (int r = 0; r < normal.height; ++r) {
    for (int c = 0; c < normal.width; ++c) {
      const float n[3] = {normal.At(r, c, 0), -normal.At(r, c, 1), -normal.At(r, c, 2)};
      if (n[0] == 0.f && n[1] == 0.f && n[2] == 0.f) continue;
      uint8_t* px = &img.data[3 * (static_cast<size_t>(r) * img.width + c)];
      for (int k = 0; k < 3; ++k) px[k] = static_cast<uint8_t>(std::lround(127.5f * (n[k] + 1.f)));
    }
  }
  WriteRgbPng(path, img);
}

}  // namespace mpmvs

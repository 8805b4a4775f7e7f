// Windows that no source's epipolar line crosses any texture of: a straight edge parallel to
// the baseline is blind, the same edge across it, or any edge seen by a second source whose
// baseline crosses it, is not.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "colmap_ext/prior/epipolar_texture.h"

namespace mpmvs {
namespace {

constexpr int kW = 64, kH = 48;

kernels::Camera CameraAt(float x, float y, float z = 0.f) {
  kernels::Camera c;
  c.width = kW;
  c.height = kH;
  c.fx = c.fy = 60.f;
  c.cx = 31.f;
  c.cy = 23.f;
  c.t[0] = -x;  // X_cam = X_world + t: the centre at (x, y, z)
  c.t[1] = -y;
  c.t[2] = -z;
  return c;
}

// A step of 40 grey levels across a horizontal (or vertical) line through the image centre,
// plus deterministic uniform noise of variance 1.44.
std::vector<float> EdgeImage(bool horizontal) {
  std::vector<float> image(kW * kH);
  uint32_t state = 12345;
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      state = state * 1664525u + 1013904223u;
      const float noise = ((state >> 8) / float(1 << 24) - 0.5f) * 4.16f;
      const bool bright = horizontal ? v >= kH / 2 : u >= kW / 2;
      image[v * kW + u] = (bright ? 120.f : 80.f) + noise;
    }
  }
  return image;
}

std::vector<uint8_t> Blind(const std::vector<float>& image, const std::vector<kernels::Camera>& sources) {
  kernels::ImageView view{image.data(), kW, kH};
  const std::vector<uint8_t> all(kW * kH, 1);
  return EpipolarBlindMask(view, CameraAt(0, 0), sources, kernels::WindowForScale(0), 1.44f, 2.f, all, 1);
}

TEST(EpipolarTexture, AnEdgeAlongTheBaselineIsBlindAndAcrossItIsNot) {
  const std::vector<kernels::Camera> sideways = {CameraAt(0.3f, 0.f), CameraAt(-0.3f, 0.f)};
  const int centre = (kH / 2) * kW + kW / 2;
  EXPECT_EQ(Blind(EdgeImage(/*horizontal=*/true), sideways)[centre], 1);
  EXPECT_EQ(Blind(EdgeImage(/*horizontal=*/false), sideways)[centre], 0);
  // The horizontal edge seen by a source above the reference: its epipolar lines cross it.
  EXPECT_EQ(Blind(EdgeImage(true), {CameraAt(0.3f, 0.f), CameraAt(0.f, 0.3f)})[centre], 0);
  // Far from the edge only noise is left: blind for every baseline.
  EXPECT_EQ(Blind(EdgeImage(false), {CameraAt(0.3f, 0.f), CameraAt(0.f, 0.3f)})[10 * kW + 10], 1);
}

TEST(EpipolarTexture, SlantedBaselinesUseTheNoiseOfInterpolatedSamples) {
  // A source up and to the right: lines at 45 degrees, whose bilinear samples average
  // pixels, so the noise alone varies their differences less than along an axis.
  const std::vector<kernels::Camera> diagonal = {CameraAt(0.3f, 0.3f)};
  EXPECT_EQ(Blind(EdgeImage(false), diagonal)[10 * kW + 10], 1);     // noise only
  EXPECT_EQ(Blind(EdgeImage(false), diagonal)[(kH / 2) * kW + kW / 2], 0);  // crossing an edge
  // The same grain taken for texture over a noise of variance 0.3 (a fifth of its own): its
  // differences on the diagonal vary by about 0.67 * 1.44, above twice the 0.2 that noise of
  // 0.3 leaves there (under the 1.2 it would leave along an axis).
  const std::vector<float> image = EdgeImage(false);
  kernels::ImageView view{image.data(), kW, kH};
  const std::vector<uint8_t> all(kW * kH, 1);
  EXPECT_EQ(EpipolarBlindMask(view, CameraAt(0, 0), diagonal, kernels::WindowForScale(0), 0.3f, 2.f, all, 1)[10 * kW + 10],
            0);
}

TEST(EpipolarTexture, SamplesOutsideTheImageDoNotCount) {
  // In the image's corner, three of the window's six rows and, along a horizontal line,
  // three of its six columns leave the image: the nine samples left are too few to call
  // the window blind.
  const std::vector<kernels::Camera> sideways = {CameraAt(0.3f, 0.f)};
  const std::vector<uint8_t> blind = Blind(EdgeImage(true), sideways);
  EXPECT_EQ(blind[10 * kW + 8], 1);  // the window inside the image: noise only, blind
  EXPECT_EQ(blind[0], 0);
}

TEST(EpipolarTexture, ForwardMotionLinesRadiateFromTheEpipole) {
  // A source straight ahead: its epipole is the principal point (31, 23) and its epipolar
  // lines radiate from it. A horizontal edge through the epipole's row runs along them.
  const std::vector<kernels::Camera> ahead = {CameraAt(0.f, 0.f, 0.5f)};
  std::vector<float> image = EdgeImage(true);  // bright from row 24: the edge between 23 and 24
  EXPECT_EQ(Blind(image, ahead)[23 * kW + 8], 1);
  // On the epipole's row the line is horizontal: it crosses a vertical edge there, and runs
  // along it below the epipole.
  EXPECT_EQ(Blind(EdgeImage(false), ahead)[23 * kW + kW / 2], 0);
  EXPECT_EQ(Blind(EdgeImage(false), ahead)[(23 + 12) * kW + kW / 2], 1);
}

TEST(EpipolarTexture, OnlyCandidatesAreTested) {
  const std::vector<float> image = EdgeImage(true);
  kernels::ImageView view{image.data(), kW, kH};
  std::vector<uint8_t> candidate(kW * kH, 0);
  candidate[10 * kW + 10] = 1;
  const std::vector<uint8_t> blind =
      EpipolarBlindMask(view, CameraAt(0, 0), {CameraAt(0.3f, 0.f)}, kernels::WindowForScale(0), 1.44f, 2.f,
                        candidate, 2);
  for (int i = 0; i < kW * kH; ++i) EXPECT_EQ(blind[i], i == 10 * kW + 10 ? 1 : 0) << i;
}

}  // namespace
}  // namespace mpmvs

#include "colmap_ext/prior/chroma_guide.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/error.h"

namespace mpmvs {
namespace {

RgbImage Uniform(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  RgbImage image;
  image.width = w;
  image.height = h;
  for (int i = 0; i < w * h; ++i) image.data.insert(image.data.end(), {r, g, b});
  return image;
}

TEST(ChromaGuide, GreyGivesZerosAndUniformColourItsWeightedChroma) {
  for (float value : MakeChromaGuide(Uniform(9, 7, 80, 80, 80), 8.f)) EXPECT_EQ(value, 0.f);
  const std::vector<float> guide = MakeChromaGuide(Uniform(9, 7, 100, 60, 30), 8.f);
  ASSERT_EQ(guide.size(), 2u * 9 * 7);
  for (size_t i = 0; i < guide.size(); i += 2) {
    EXPECT_FLOAT_EQ(guide[i], 8.f * 40);
    EXPECT_FLOAT_EQ(guide[i + 1], 8.f * -30);
  }
}

TEST(ChromaGuide, SmoothsNoiseAndKeepsEdgesApart) {
  // Left half red, right half green, equal grey; one noisy pixel in the red half.
  RgbImage image = Uniform(40, 20, 150, 50, 50);
  for (int y = 0; y < 20; ++y) {
    for (int x = 20; x < 40; ++x) {
      uint8_t* p = &image.data[3 * (y * 40 + x)];
      p[0] = 50, p[1] = 150, p[2] = 50;
    }
  }
  image.data[3 * (10 * 40 + 5)] = 190;  // R + 40 at (5, 10)
  const std::vector<float> guide = MakeChromaGuide(image, 1.f);
  auto rg = [&](int x, int y) { return guide[2 * (y * 40 + x)]; };
  // Far from the edge each side keeps its chroma; across the edge they stay far apart.
  EXPECT_NEAR(rg(12, 3), 100.f, 1e-3f);
  EXPECT_NEAR(rg(30, 3), -100.f, 1e-3f);
  EXPECT_GT(rg(17, 3) - rg(22, 3), 150.f);
  // The noisy pixel's +40 is spread out: a small bump, mass conserved.
  EXPECT_GT(rg(5, 10), 100.f);
  EXPECT_LT(rg(5, 10), 100.f + 40.f * 0.1f);
  float mass = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 15; ++x) mass += rg(x, y) - 100.f;
  }
  EXPECT_NEAR(mass, 40.f, 0.05f);
}

TEST(ChromaGuide, RejectsDataOfTheWrongSize) {
  RgbImage image = Uniform(4, 4, 1, 2, 3);
  image.data.pop_back();
  EXPECT_THROW(MakeChromaGuide(image, 1.f), Error);
}

}  // namespace
}  // namespace mpmvs

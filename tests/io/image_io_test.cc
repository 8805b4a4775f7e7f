#include "colmap_ext/io/image_io.h"

#include <FreeImage.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "colmap_ext/util/file_util.h"
#include "tests/io_test_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

using test::TempDir;

RgbImage MakeRgb(int width, int height, uint32_t seed) {
  RgbImage image;
  image.width = width;
  image.height = height;
  image.data.resize(3 * static_cast<size_t>(width) * height);
  std::mt19937 rng(seed);
  for (uint8_t& v : image.data) v = static_cast<uint8_t>(rng() & 0xff);
  return image;
}

// Rec. 709 luma, which FreeImage's greyscale conversion uses.
float Luma(const RgbImage& image, int row, int col) {
  const uint8_t* p = &image.data[3 * (static_cast<size_t>(row) * image.width + col)];
  return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
}

// Saves a FreeImage bitmap built by fill(x, y_from_top, scanline_pixel) as PNG, for image
// types our writers do not produce (RGBA, 16 bit).
template <typename Fill>
void SaveSpecialPng(const std::string& path, FREE_IMAGE_TYPE type, int bpp, int width,
                    int height, Fill fill) {
  FIBITMAP* bitmap = FreeImage_AllocateT(type, width, height, bpp);
  ASSERT_NE(bitmap, nullptr);
  for (int row = 0; row < height; ++row) {
    BYTE* line = FreeImage_GetScanLine(bitmap, height - 1 - row);
    for (int col = 0; col < width; ++col) fill(row, col, line);
  }
  ASSERT_TRUE(FreeImage_Save(FIF_PNG, bitmap, path.c_str()));
  FreeImage_Unload(bitmap);
}

TEST(ImageIo, RgbPngRoundTripAndRowOrder) {
  TempDir dir;
  RgbImage image = MakeRgb(7, 5, 1);
  // Distinct top-left pixel to catch a vertical flip.
  image.data[0] = 255;
  image.data[1] = 0;
  image.data[2] = 0;
  WriteRgbPng(dir / "rgb.png", image);
  const RgbImage read = ReadRgbImage(dir / "rgb.png");
  EXPECT_EQ(read.width, 7);
  EXPECT_EQ(read.height, 5);
  EXPECT_EQ(read.data, image.data);
  EXPECT_EQ(std::filesystem::directory_iterator(dir.path())->path().filename(), "rgb.png");
}

TEST(ImageIo, GreyConversionMatchesFreeImageLuma) {
  TempDir dir;
  const RgbImage image = MakeRgb(16, 9, 2);
  WriteRgbPng(dir / "rgb.png", image);
  const GrayImage gray = ReadGrayImage(dir / "rgb.png");
  ASSERT_EQ(gray.width, 16);
  ASSERT_EQ(gray.height, 9);
  for (int r = 0; r < 9; ++r) {
    for (int c = 0; c < 16; ++c) {
      EXPECT_NEAR(gray.At(r, c), Luma(image, r, c), 1.0f) << r << "," << c;
      EXPECT_EQ(gray.At(r, c), std::round(gray.At(r, c)));  // 8-bit values
    }
  }
}

TEST(ImageIo, GreyPngRoundTrip) {
  TempDir dir;
  std::vector<uint8_t> values(11 * 6);
  for (size_t i = 0; i < values.size(); ++i) values[i] = static_cast<uint8_t>(i * 3);
  WriteGrayPng(dir / "g.png", 11, 6, values);
  const GrayImage gray = ReadGrayImage(dir / "g.png");
  ASSERT_EQ(gray.width, 11);
  ASSERT_EQ(gray.height, 6);
  for (size_t i = 0; i < values.size(); ++i) EXPECT_EQ(gray.data[i], values[i]);
  const RgbImage rgb = ReadRgbImage(dir / "g.png");
  for (size_t i = 0; i < values.size(); ++i) {
    EXPECT_EQ(rgb.data[3 * i], values[i]);
    EXPECT_EQ(rgb.data[3 * i + 2], values[i]);
  }
}

TEST(ImageIo, AlphaAndSixteenBitImagesGoThroughTwentyFourBits) {
  TempDir dir;
  const RgbImage image = MakeRgb(8, 6, 3);
  WriteRgbPng(dir / "rgb.png", image);
  const GrayImage expected = ReadGrayImage(dir / "rgb.png");
  ReadGrayImage(dir / "rgb.png");  // FreeImage is initialised by now

  SaveSpecialPng(dir / "rgba.png", FIT_BITMAP, 32, 8, 6, [&](int row, int col, BYTE* line) {
    const uint8_t* p = &image.data[3 * (row * 8 + col)];
    line[4 * col + FI_RGBA_RED] = p[0];
    line[4 * col + FI_RGBA_GREEN] = p[1];
    line[4 * col + FI_RGBA_BLUE] = p[2];
    line[4 * col + FI_RGBA_ALPHA] = static_cast<BYTE>(col * 30);  // alpha is ignored
  });
  EXPECT_EQ(ReadGrayImage(dir / "rgba.png").data, expected.data);
  EXPECT_EQ(ReadRgbImage(dir / "rgba.png").data, image.data);

  SaveSpecialPng(dir / "rgb16.png", FIT_RGB16, 48, 8, 6, [&](int row, int col, BYTE* line) {
    const uint8_t* p = &image.data[3 * (row * 8 + col)];
    FIRGB16* pixel = reinterpret_cast<FIRGB16*>(line) + col;
    pixel->red = static_cast<WORD>(p[0] * 257);
    pixel->green = static_cast<WORD>(p[1] * 257);
    pixel->blue = static_cast<WORD>(p[2] * 257);
  });
  EXPECT_EQ(ReadGrayImage(dir / "rgb16.png").data, expected.data);
  EXPECT_EQ(ReadRgbImage(dir / "rgb16.png").data, image.data);  // the chroma guide's reader

  SaveSpecialPng(dir / "grey16.png", FIT_UINT16, 16, 8, 6, [&](int row, int col, BYTE* line) {
    reinterpret_cast<WORD*>(line)[col] = static_cast<WORD>((row * 8 + col) * 257);
  });
  const GrayImage grey16 = ReadGrayImage(dir / "grey16.png");
  for (int i = 0; i < 48; ++i) EXPECT_EQ(grey16.data[i], i);
  const RgbImage grey16_rgb = ReadRgbImage(dir / "grey16.png");
  ASSERT_EQ(grey16_rgb.data.size(), 3u * 48);
  for (int i = 0; i < 48; ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(grey16_rgb.data[3 * i + c], i);
  }
}

TEST(ImageIo, BadFilesNameTheFile) {
  TempDir dir;
  EXPECT_MPMVS_ERROR(ReadGrayImage(dir / "missing.png"), "missing.png: image file does not exist");
  test::WriteText(dir / "garbage.png", std::string(300, 'g'));
  EXPECT_MPMVS_ERROR(ReadGrayImage(dir / "garbage.png"), "garbage.png: ");
  test::WriteText(dir / "garbage.xyz", std::string(300, 'g'));
  EXPECT_MPMVS_ERROR(ReadRgbImage(dir / "garbage.xyz"), "garbage.xyz: not an image file");
  test::WriteText(dir / "empty.jpg", "");
  EXPECT_MPMVS_ERROR(ReadGrayImage(dir / "empty.jpg"), "empty.jpg: ");
  // A PNG cut in half.
  WriteRgbPng(dir / "full.png", MakeRgb(64, 64, 4));
  const std::vector<uint8_t> bytes = ReadFileBytes(dir / "full.png");
  test::WriteBytes(dir / "cut.png", std::vector<uint8_t>(bytes.begin(), bytes.begin() + 100));
  EXPECT_MPMVS_ERROR(ReadGrayImage(dir / "cut.png"), "cut.png: ");
}

TEST(ImageIo, WritersValidateAndAreAtomic) {
  TempDir dir;
  WriteGrayPng(dir / "g.png", 2, 2, {1, 2, 3, 4});
  EXPECT_MPMVS_ERROR(WriteGrayPng(dir / "g.png", 3, 2, {1, 2, 3, 4}), "g.png");
  RgbImage bad = MakeRgb(2, 2, 5);
  bad.data.pop_back();
  EXPECT_MPMVS_ERROR(WriteRgbPng(dir / "g.png", bad), "g.png");
  EXPECT_EQ(ReadGrayImage(dir / "g.png").data, (std::vector<float>{1, 2, 3, 4}));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(ImageIo, ResizeKeepsConstantsAndRamps) {
  GrayImage constant;
  constant.width = 40;
  constant.height = 30;
  constant.data.assign(40 * 30, 77.f);
  const GrayImage small = ResizeGrayImage(constant, 20, 15);
  ASSERT_EQ(small.width, 20);
  ASSERT_EQ(small.height, 15);
  ASSERT_EQ(small.data.size(), 300u);
  for (float v : small.data) EXPECT_EQ(v, 77.f);

  // Horizontal ramp: stays monotone in x and constant in y, ends near the original ends.
  GrayImage ramp;
  ramp.width = 200;
  ramp.height = 10;
  for (int r = 0; r < 10; ++r) {
    for (int c = 0; c < 200; ++c) ramp.data.push_back(static_cast<float>(c));
  }
  const GrayImage half = ResizeGrayImage(ramp, 100, 5);
  for (int r = 0; r < 5; ++r) {
    for (int c = 1; c < 100; ++c) {
      EXPECT_GE(half.At(r, c), half.At(r, c - 1));
      EXPECT_EQ(half.At(r, c), half.At(0, c));
    }
  }
  EXPECT_NEAR(half.At(2, 50), 100.5f, 1.5f);  // centre of target pixel 50 is source x 100.5
  EXPECT_EQ(ResizeGrayImage(ramp, 200, 10).data, ramp.data);
  EXPECT_THROW(ResizeGrayImage(ramp, 0, 5), Error);
}

TEST(ImageIo, ResizeRgbKeepsChannelsApart) {
  // Red ramp in x, constant green and blue: each channel resized on its own.
  RgbImage image;
  image.width = 200;
  image.height = 10;
  for (int r = 0; r < 10; ++r) {
    for (int c = 0; c < 200; ++c) image.data.insert(image.data.end(), {static_cast<uint8_t>(c), 40, 200});
  }
  const RgbImage half = ResizeRgbImage(image, 100, 5);
  ASSERT_EQ(half.width, 100);
  ASSERT_EQ(half.height, 5);
  ASSERT_EQ(half.data.size(), 3u * 100 * 5);
  for (int i = 0; i < 100 * 5; ++i) {
    EXPECT_EQ(half.data[3 * i + 1], 40);
    EXPECT_EQ(half.data[3 * i + 2], 200);
  }
  EXPECT_NEAR(half.data[3 * (2 * 100 + 50)], 100.5f, 1.5f);
  EXPECT_EQ(ResizeRgbImage(image, 200, 10).data, image.data);
  EXPECT_THROW(ResizeRgbImage(image, 0, 5), Error);
  image.data.pop_back();
  EXPECT_THROW(ResizeRgbImage(image, 100, 5), Error);
}

TEST(ImageIo, PfmRoundTripAndBottomUpRows) {
  TempDir dir;
  PfmImage image;
  image.width = 3;
  image.height = 2;
  image.data = {1, 2, 3, 4, 5, 6};  // top row 1 2 3
  WritePfm(dir / "d.pfm", image);
  const std::vector<uint8_t> bytes = ReadFileBytes(dir / "d.pfm");
  const std::string header = "Pf\n3 2\n-1\n";
  ASSERT_EQ(bytes.size(), header.size() + 24);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + header.size()), header);
  float first;
  std::memcpy(&first, bytes.data() + header.size(), 4);
  EXPECT_EQ(first, 4.f);  // the bottom row comes first in the file
  const PfmImage read = ReadPfm(dir / "d.pfm");
  EXPECT_EQ(read.width, 3);
  EXPECT_EQ(read.height, 2);
  EXPECT_EQ(read.data, image.data);
}

TEST(ImageIo, BigEndianPfm) {
  TempDir dir;
  std::string text = "Pf\n2 1\n1.0\n";
  std::vector<uint8_t> bytes(text.begin(), text.end());
  for (float value : {1.5f, -2.0f}) {
    uint8_t le[4];
    std::memcpy(le, &value, 4);
    bytes.insert(bytes.end(), {le[3], le[2], le[1], le[0]});
  }
  test::WriteBytes(dir / "be.pfm", bytes);
  EXPECT_EQ(ReadPfm(dir / "be.pfm").data, (std::vector<float>{1.5f, -2.0f}));
}

TEST(ImageIo, CorruptPfm) {
  TempDir dir;
  const std::string path = dir / "x.pfm";
  struct Case {
    std::string header;
    size_t num_floats;
    std::string expected;
  };
  const Case cases[] = {
      {"P5\n2 2\n-1\n", 4, "not a PFM file"},
      {"PF\n2 2\n-1\n", 12, "colour PFM"},
      {"Pf\n2 x\n-1\n", 4, "bad height"},
      {"Pf\n2 -2\n-1\n", 4, "bad height"},
      {"Pf\n2 2\n0\n", 4, "bad scale"},
      {"Pf\n2 2\n-1", 0, "no data follows"},
      {"Pf\n2 2\n-1\n", 3, "header says 2x2"},
      {"Pf\n2 2\n-1\n", 5, "header says 2x2"},
      {"Pf\n2000000000 2000000000\n-1\n", 4, "header says 2000000000x2000000000"},
      {"", 0, "missing magic"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.header);
    std::vector<uint8_t> bytes(c.header.begin(), c.header.end());
    bytes.resize(bytes.size() + 4 * c.num_floats);
    test::WriteBytes(path, bytes);
    EXPECT_MPMVS_ERROR(ReadPfm(path), path + ": ");
    EXPECT_MPMVS_ERROR(ReadPfm(path), c.expected);
  }
  EXPECT_MPMVS_ERROR(ReadPfm(dir / "none.pfm"), "none.pfm");
}

TEST(ImageIoDataset, ReadsDollsImagesAndGroundTruth) {
  MPMVS_REQUIRE_DATASET(dataset, "middlebury2005_dolls");
  const GrayImage gray = ReadGrayImage(dataset + "/images/view1.png");
  EXPECT_EQ(gray.width, 463);
  EXPECT_EQ(gray.height, 370);
  const RgbImage rgb = ReadRgbImage(dataset + "/images/view1.png");
  EXPECT_NEAR(gray.At(100, 200), Luma(rgb, 100, 200), 1.0f);
  const PfmImage depth = ReadPfm(dataset + "/gt/depth_view1.pfm");
  ASSERT_EQ(depth.width, 463);
  ASSERT_EQ(depth.height, 370);
  size_t valid = 0;
  for (float z : depth.data) {
    if (z > 0) {
      ++valid;
      EXPECT_GT(z, 1.0f);
      EXPECT_LT(z, 3.5f);
    }
  }
  EXPECT_GT(valid, depth.data.size() * 9 / 10);
}

}  // namespace
}  // namespace mpmvs

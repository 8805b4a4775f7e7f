#pragma once
// Image files through FreeImage (the image library COLMAP 3.8 uses): grey conversion as
// COLMAP's Bitmap does it, resizing for max_image_size, PNG pictures, PFM ground truth.
#include <cstdint>
#include <string>
#include <vector>

namespace mpmvs {

// Grey image, values 0..255 as float, row-major.
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<float> data;
  float At(int row, int col) const { return data[static_cast<size_t>(row) * width + col]; }
};

// 8-bit RGB image, row-major, interleaved r,g,b.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> data;  // 3*width*height
};

// Reads any 8-bit grey or colour image FreeImage knows (PNG, JPEG, ...) and converts it to
// grey the way COLMAP does (FreeImage's greyscale conversion, 8-bit). Throws Error naming
// the path when missing, unreadable or not an image.
GrayImage ReadGrayImage(const std::string& path);
RgbImage ReadRgbImage(const std::string& path);

// Bilinear down-scaling as COLMAP's Bitmap::Rescale (FreeImage FILTER_BILINEAR) on the
// 8-bit image; returns the rescaled grey image.
GrayImage ResizeGrayImage(const GrayImage& image, int new_width, int new_height);
// The same for a colour image (each channel as the grey one).
RgbImage ResizeRgbImage(const RgbImage& image, int new_width, int new_height);

// Atomic PNG writers (temporary + rename).
void WriteRgbPng(const std::string& path, const RgbImage& image);
void WriteGrayPng(const std::string& path, int width, int height, const std::vector<uint8_t>& gray);

// PFM (1 channel "Pf"): rows stored bottom-to-top in the file, returned top-to-bottom.
// Scale sign gives endianness (negative = little endian).
struct PfmImage {
  int width = 0;
  int height = 0;
  std::vector<float> data;  // row-major, top row first
};
PfmImage ReadPfm(const std::string& path);
void WritePfm(const std::string& path, const PfmImage& image);

}  // namespace mpmvs

#include "colmap_ext/io/image_io.h"

#include <FreeImage.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "mp-mvs assumes a little-endian host");

namespace mpmvs {
namespace {

// FreeImage reports details (e.g. "Not a PNG file") through a callback; keep the last one of
// this thread so errors can quote it.
thread_local std::string last_freeimage_message;

void StoreFreeImageMessage(FREE_IMAGE_FORMAT /*format*/, const char* message) {
  last_freeimage_message = message ? message : "";
}

void InitializeFreeImage() {
  static const bool initialized = [] {
    FreeImage_Initialise();
    FreeImage_SetOutputMessage(&StoreFreeImageMessage);
    return true;
  }();
  (void)initialized;
}

struct BitmapDeleter {
  void operator()(FIBITMAP* bitmap) const {
    if (bitmap != nullptr) FreeImage_Unload(bitmap);
  }
};
using BitmapPtr = std::unique_ptr<FIBITMAP, BitmapDeleter>;

std::string FreeImageDetail() {
  if (last_freeimage_message.empty()) return "";
  return " (" + last_freeimage_message + ")";
}

bool IsGrey8(FIBITMAP* bitmap) {
  return FreeImage_GetImageType(bitmap) == FIT_BITMAP && FreeImage_GetBPP(bitmap) == 8 &&
         FreeImage_GetColorType(bitmap) == FIC_MINISBLACK;
}

bool IsRgb24(FIBITMAP* bitmap) {
  return FreeImage_GetImageType(bitmap) == FIT_BITMAP && FreeImage_GetBPP(bitmap) == 24 &&
         FreeImage_GetColorType(bitmap) == FIC_RGB;
}

BitmapPtr Convert(const std::string& path, FIBITMAP* converted, const char* what) {
  if (converted == nullptr) {
    ThrowFileError(path, std::string("cannot convert the image to ") + what + FreeImageDetail());
  }
  return BitmapPtr(converted);
}

BitmapPtr NewGreyBitmap(const std::string& path, int width, int height);
BitmapPtr Grey16ToGrey8(const std::string& path, FIBITMAP* bitmap16);

BitmapPtr LoadBitmap(const std::string& path) {
  InitializeFreeImage();
  if (!FileExists(path)) ThrowFileError(path, "image file does not exist");
  last_freeimage_message.clear();
  FREE_IMAGE_FORMAT format = FreeImage_GetFileType(path.c_str(), 0);
  if (format == FIF_UNKNOWN) format = FreeImage_GetFIFFromFilename(path.c_str());
  if (format == FIF_UNKNOWN || !FreeImage_FIFSupportsReading(format)) {
    ThrowFileError(path, "not an image file that can be read (unknown or unsupported format)");
  }
  BitmapPtr bitmap(FreeImage_Load(format, path.c_str()));
  if (!bitmap) ThrowFileError(path, "cannot read the image, file corrupt?" + FreeImageDetail());
  if (FreeImage_GetWidth(bitmap.get()) == 0 || FreeImage_GetHeight(bitmap.get()) == 0) {
    ThrowFileError(path, "image is empty");
  }
  // COLMAP 3.8 cannot read these types at all; take the high byte of 16-bit grey (as
  // FreeImage does for 16-bit colour) and let FreeImage stretch other types to 8 bits.
  // RGB16 and RGBA16 are handled by the 24-bit conversion later, as in COLMAP.
  const FREE_IMAGE_TYPE type = FreeImage_GetImageType(bitmap.get());
  if (type == FIT_UINT16) {
    bitmap = Grey16ToGrey8(path, bitmap.get());
  } else if (type != FIT_BITMAP && type != FIT_RGB16 && type != FIT_RGBA16) {
    bitmap = Convert(path, FreeImage_ConvertToStandardType(bitmap.get(), TRUE), "8 bits");
  }
  return bitmap;
}

// Rows of FreeImage bitmaps are stored bottom-up; row 0 of ours is the top row.
const BYTE* TopDownRow(FIBITMAP* bitmap, int row) {
  return FreeImage_GetScanLine(bitmap, static_cast<int>(FreeImage_GetHeight(bitmap)) - 1 - row);
}
BYTE* TopDownRowMutable(FIBITMAP* bitmap, int row) {
  return FreeImage_GetScanLine(bitmap, static_cast<int>(FreeImage_GetHeight(bitmap)) - 1 - row);
}

GrayImage GrayFromBitmap(FIBITMAP* bitmap) {
  GrayImage image;
  image.width = static_cast<int>(FreeImage_GetWidth(bitmap));
  image.height = static_cast<int>(FreeImage_GetHeight(bitmap));
  image.data.resize(static_cast<size_t>(image.width) * image.height);
  for (int row = 0; row < image.height; ++row) {
    const BYTE* line = TopDownRow(bitmap, row);
    float* out = image.data.data() + static_cast<size_t>(row) * image.width;
    for (int col = 0; col < image.width; ++col) out[col] = line[col];
  }
  return image;
}

// An 8-bit bitmap with an explicit linear grey palette, so FreeImage sees FIC_MINISBLACK.
BitmapPtr NewGreyBitmap(const std::string& path, int width, int height) {
  InitializeFreeImage();
  BitmapPtr bitmap(FreeImage_Allocate(width, height, 8));
  if (!bitmap) ThrowFileError(path, "cannot allocate a " + std::to_string(width) + "x" +
                                        std::to_string(height) + " image");
  RGBQUAD* palette = FreeImage_GetPalette(bitmap.get());
  for (int i = 0; i < 256; ++i) {
    palette[i].rgbRed = palette[i].rgbGreen = palette[i].rgbBlue = static_cast<BYTE>(i);
    palette[i].rgbReserved = 0;
  }
  return bitmap;
}

BitmapPtr Grey16ToGrey8(const std::string& path, FIBITMAP* bitmap16) {
  const int width = static_cast<int>(FreeImage_GetWidth(bitmap16));
  const int height = static_cast<int>(FreeImage_GetHeight(bitmap16));
  BitmapPtr bitmap8 = NewGreyBitmap(path, width, height);
  for (int y = 0; y < height; ++y) {  // same row order in both, no flip needed
    const uint16_t* in = reinterpret_cast<const uint16_t*>(FreeImage_GetScanLine(bitmap16, y));
    BYTE* out = FreeImage_GetScanLine(bitmap8.get(), y);
    for (int x = 0; x < width; ++x) out[x] = static_cast<BYTE>(in[x] >> 8);
  }
  return bitmap8;
}

void SavePngAtomically(const std::string& path, FIBITMAP* bitmap) {
  struct MemoryDeleter {
    void operator()(FIMEMORY* memory) const { FreeImage_CloseMemory(memory); }
  };
  std::unique_ptr<FIMEMORY, MemoryDeleter> memory(FreeImage_OpenMemory());
  // zlib's fastest level: a run writes several pictures per image and stage, and level 6
  // (PNG_DEFAULT) spent more time on them than on some stages while shrinking them little.
  if (!memory || !FreeImage_SaveToMemory(FIF_PNG, bitmap, memory.get(), PNG_Z_BEST_SPEED)) {
    ThrowFileError(path, "PNG encoding failed" + FreeImageDetail());
  }
  BYTE* bytes = nullptr;
  DWORD num_bytes = 0;
  if (!FreeImage_AcquireMemory(memory.get(), &bytes, &num_bytes)) {
    ThrowFileError(path, "PNG encoding failed" + FreeImageDetail());
  }
  WriteFileAtomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes), static_cast<std::streamsize>(num_bytes));
  });
}

void CheckImageSize(const std::string& path, int width, int height, size_t num_values) {
  if (width <= 0 || height <= 0 || num_values != static_cast<size_t>(width) * height) {
    ThrowFileError(path, "image size " + std::to_string(width) + "x" + std::to_string(height) +
                             " does not match its " + std::to_string(num_values) + " values");
  }
}

}  // namespace

GrayImage ReadGrayImage(const std::string& path) {
  BitmapPtr bitmap = LoadBitmap(path);
  // COLMAP 3.8 (Bitmap::Read as grey): images that are not 8-bit grey are brought to 24-bit
  // colour first unless already 24-bit, then FreeImage's greyscale conversion.
  if (!IsGrey8(bitmap.get())) {
    if (FreeImage_GetBPP(bitmap.get()) != 24) {
      bitmap = Convert(path, FreeImage_ConvertTo24Bits(bitmap.get()), "24-bit colour");
    }
    bitmap = Convert(path, FreeImage_ConvertToGreyscale(bitmap.get()), "grey");
  }
  if (FreeImage_GetBPP(bitmap.get()) != 8) ThrowFileError(path, "grey conversion failed");
  return GrayFromBitmap(bitmap.get());
}

namespace {

RgbImage RgbFromBitmap(FIBITMAP* bitmap) {
  RgbImage image;
  image.width = static_cast<int>(FreeImage_GetWidth(bitmap));
  image.height = static_cast<int>(FreeImage_GetHeight(bitmap));
  image.data.resize(3 * static_cast<size_t>(image.width) * image.height);
  for (int row = 0; row < image.height; ++row) {
    const BYTE* line = TopDownRow(bitmap, row);
    uint8_t* out = image.data.data() + 3 * static_cast<size_t>(row) * image.width;
    for (int col = 0; col < image.width; ++col) {
      out[3 * col + 0] = line[3 * col + FI_RGBA_RED];
      out[3 * col + 1] = line[3 * col + FI_RGBA_GREEN];
      out[3 * col + 2] = line[3 * col + FI_RGBA_BLUE];
    }
  }
  return image;
}

// A 24-bit bitmap of an RgbImage whose size the caller has checked.
BitmapPtr BitmapFromRgb(const std::string& path, const RgbImage& image) {
  InitializeFreeImage();
  BitmapPtr bitmap(FreeImage_Allocate(image.width, image.height, 24));
  if (!bitmap) ThrowFileError(path, "cannot allocate the image");
  for (int row = 0; row < image.height; ++row) {
    BYTE* line = TopDownRowMutable(bitmap.get(), row);
    const uint8_t* in = image.data.data() + 3 * static_cast<size_t>(row) * image.width;
    for (int col = 0; col < image.width; ++col) {
      line[3 * col + FI_RGBA_RED] = in[3 * col + 0];
      line[3 * col + FI_RGBA_GREEN] = in[3 * col + 1];
      line[3 * col + FI_RGBA_BLUE] = in[3 * col + 2];
    }
  }
  return bitmap;
}

}  // namespace

RgbImage ReadRgbImage(const std::string& path) {
  BitmapPtr bitmap = LoadBitmap(path);
  if (!IsRgb24(bitmap.get())) {
    bitmap = Convert(path, FreeImage_ConvertTo24Bits(bitmap.get()), "24-bit colour");
  }
  return RgbFromBitmap(bitmap.get());
}

RgbImage ResizeRgbImage(const RgbImage& image, int new_width, int new_height) {
  const std::string what = "ResizeRgbImage";
  if (image.data.size() % 3 != 0) ThrowFileError(what, "RGB data size is not a multiple of 3");
  CheckImageSize(what, image.width, image.height, image.data.size() / 3);
  if (new_width <= 0 || new_height <= 0) {
    ThrowFileError(what, "bad target size " + std::to_string(new_width) + "x" +
                             std::to_string(new_height));
  }
  if (new_width == image.width && new_height == image.height) return image;
  BitmapPtr bitmap = BitmapFromRgb(what, image);
  BitmapPtr scaled(FreeImage_Rescale(bitmap.get(), new_width, new_height, FILTER_BILINEAR));
  if (!scaled) ThrowFileError(what, "FreeImage_Rescale failed" + FreeImageDetail());
  if (!IsRgb24(scaled.get())) {
    scaled = Convert(what, FreeImage_ConvertTo24Bits(scaled.get()), "24-bit colour");
  }
  return RgbFromBitmap(scaled.get());
}

GrayImage ResizeGrayImage(const GrayImage& image, int new_width, int new_height) {
  const std::string what = "ResizeGrayImage";
  CheckImageSize(what, image.width, image.height, image.data.size());
  if (new_width <= 0 || new_height <= 0) {
    ThrowFileError(what, "bad target size " + std::to_string(new_width) + "x" +
                             std::to_string(new_height));
  }
  if (new_width == image.width && new_height == image.height) return image;
  BitmapPtr bitmap = NewGreyBitmap(what, image.width, image.height);
  for (int row = 0; row < image.height; ++row) {
    BYTE* line = TopDownRowMutable(bitmap.get(), row);
    for (int col = 0; col < image.width; ++col) {
      const float value = std::round(image.At(row, col));
      line[col] = static_cast<BYTE>(std::min(255.f, std::max(0.f, value)));
    }
  }
  BitmapPtr scaled(FreeImage_Rescale(bitmap.get(), new_width, new_height, FILTER_BILINEAR));
  if (!scaled) ThrowFileError(what, "FreeImage_Rescale failed" + FreeImageDetail());
  if (!IsGrey8(scaled.get())) {
    scaled = Convert(what, FreeImage_ConvertToGreyscale(scaled.get()), "grey");
  }
  return GrayFromBitmap(scaled.get());
}

void WriteRgbPng(const std::string& path, const RgbImage& image) {
  if (image.data.size() % 3 != 0) ThrowFileError(path, "RGB data size is not a multiple of 3");
  CheckImageSize(path, image.width, image.height, image.data.size() / 3);
  BitmapPtr bitmap = BitmapFromRgb(path, image);
  SavePngAtomically(path, bitmap.get());
}

void WriteGrayPng(const std::string& path, int width, int height,
                  const std::vector<uint8_t>& gray) {
  CheckImageSize(path, width, height, gray.size());
  BitmapPtr bitmap = NewGreyBitmap(path, width, height);
  for (int row = 0; row < height; ++row) {
    std::memcpy(TopDownRowMutable(bitmap.get(), row),
                gray.data() + static_cast<size_t>(row) * width, static_cast<size_t>(width));
  }
  SavePngAtomically(path, bitmap.get());
}

// ---------------------------------------------------------------------------------------
// PFM: "Pf" <ws> width <ws> height <ws> scale <one whitespace byte> then float rows,
// bottom row first; negative scale = little endian.

namespace {

class PfmHeaderParser {
 public:
  PfmHeaderParser(const std::string& path, const std::vector<uint8_t>& bytes)
      : path_(path), bytes_(bytes) {}

  std::string NextToken(const char* what) {
    while (pos_ < bytes_.size() && IsSpace(bytes_[pos_])) ++pos_;
    std::string token;
    while (pos_ < bytes_.size() && !IsSpace(bytes_[pos_])) {
      token.push_back(static_cast<char>(bytes_[pos_++]));
      if (token.size() > 32) Fail(std::string("malformed header (") + what + ")");
    }
    if (token.empty()) Fail(std::string("malformed header: missing ") + what);
    return token;
  }

  int NextDimension(const char* what) {
    const std::string token = NextToken(what);
    char* end = nullptr;
    const long long value = std::strtoll(token.c_str(), &end, 10);
    if (end != token.c_str() + token.size() || value <= 0 || value > INT_MAX) {
      Fail(std::string("malformed header: bad ") + what + " '" + token + "'");
    }
    return static_cast<int>(value);
  }

  // The single whitespace byte that ends the header.
  size_t EndOfHeader() {
    if (pos_ >= bytes_.size() || !IsSpace(bytes_[pos_])) Fail("malformed header: no data follows");
    return pos_ + 1;
  }

  [[noreturn]] void Fail(const std::string& what) const { ThrowFileError(path_, what); }

 private:
  static bool IsSpace(uint8_t c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

  const std::string& path_;
  const std::vector<uint8_t>& bytes_;
  size_t pos_ = 0;
};

}  // namespace

PfmImage ReadPfm(const std::string& path) {
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  PfmHeaderParser parser(path, bytes);
  const std::string magic = parser.NextToken("magic");
  if (magic == "PF") parser.Fail("colour PFM (\"PF\") is not supported, expected 1-channel \"Pf\"");
  if (magic != "Pf") parser.Fail("not a PFM file (magic '" + magic + "', expected 'Pf')");
  PfmImage image;
  image.width = parser.NextDimension("width");
  image.height = parser.NextDimension("height");
  const std::string scale_token = parser.NextToken("scale");
  char* end = nullptr;
  const double scale = std::strtod(scale_token.c_str(), &end);
  if (end != scale_token.c_str() + scale_token.size() || scale == 0 || !std::isfinite(scale)) {
    parser.Fail("malformed header: bad scale '" + scale_token + "'");
  }
  const size_t data_offset = parser.EndOfHeader();
  const size_t num_values = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  if ((bytes.size() - data_offset) % sizeof(float) != 0 ||
      (bytes.size() - data_offset) / sizeof(float) != num_values) {
    parser.Fail("header says " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                " but " + std::to_string(bytes.size() - data_offset) +
                " data bytes follow (truncated or corrupt)");
  }
  const bool big_endian = scale > 0;
  image.data.resize(num_values);
  for (int file_row = 0; file_row < image.height; ++file_row) {
    const int row = image.height - 1 - file_row;
    for (int col = 0; col < image.width; ++col) {
      const size_t offset =
          data_offset + sizeof(float) * (static_cast<size_t>(file_row) * image.width + col);
      uint8_t value_bytes[4];
      std::memcpy(value_bytes, bytes.data() + offset, 4);
      if (big_endian) {
        std::swap(value_bytes[0], value_bytes[3]);
        std::swap(value_bytes[1], value_bytes[2]);
      }
      std::memcpy(&image.data[static_cast<size_t>(row) * image.width + col], value_bytes, 4);
    }
  }
  return image;
}

void WritePfm(const std::string& path, const PfmImage& image) {
  CheckImageSize(path, image.width, image.height, image.data.size());
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "Pf\n" << image.width << " " << image.height << "\n-1\n";
    for (int row = image.height - 1; row >= 0; --row) {
      out.write(reinterpret_cast<const char*>(image.data.data() +
                                              static_cast<size_t>(row) * image.width),
                static_cast<std::streamsize>(sizeof(float) * image.width));
    }
  });
}

}  // namespace mpmvs

#pragma once
// Pictures a person can look at: scalar maps (depth, error) in false colour with a
// vertical colour bar and printed min/mid/max, normal maps as RGB, 5x7 bitmap text for
// titles and labels, and tiling of several pictures into one panel.
#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"

namespace mpmvs {

struct RgbColor {
  uint8_t r = 0, g = 0, b = 0;
};

// Colour of t in [0, 1] (clamped) on a dark-blue, blue, cyan, green, yellow, red, dark-red
// scale.
RgbColor ScalarColor(double t);

RgbImage MakeRgbImage(int width, int height, RgbColor fill);
void FillRect(RgbImage* image, int x, int y, int width, int height, RgbColor color);
// Copies src into dst with its top-left corner at (x, y), clipped.
void Blit(RgbImage* dst, const RgbImage& src, int x, int y);
// 5x7 bitmap text (upper-case letters, digits, . , - + % : / ( ) = _ < >, and 'm' for
// metres); other lower case is drawn as upper case, unknown characters as '?'. scale >= 1 enlarges each dot.
void DrawText(RgbImage* image, int x, int y, const std::string& text, RgbColor color, int scale = 1);
int TextWidth(const std::string& text, int scale = 1);
int TextHeight(int scale = 1);

// Special values of ScalarPicture: NaN = no data (black), -infinity = "missing" (grey).
struct ScalarPictureOptions {
  double value_min = 0;
  double value_max = 1;
  bool reverse = false;        // true: value_min is red, value_max is blue (near = warm)
  std::string title;
  std::string unit;            // appended to the labels, e.g. "m" or "%"
  double label_factor = 1.0;   // labels show value * label_factor (100 for percent)
};

// The map in false colour with a title above and a colour bar at the right.
RgbImage ScalarPicture(const std::vector<float>& values, int width, int height,
                       const ScalarPictureOptions& options);
// Depth map (0 or non-finite = no data), near = warm.
RgbImage DepthPicture(const FloatMap& depth, double depth_min, double depth_max,
                      const std::string& title);
// Camera-frame normal map as RGB = ((x, -y, -z) + 1) / 2 (camera-facing surfaces look
// blue), invalid (0,0,0) black, with a title.
RgbImage NormalPicture(const FloatMap& normal, const std::string& title);
// DepthPicture / NormalPicture written as a PNG file at path.
void WriteDepthPicture(const std::string& path, const FloatMap& depth, double depth_min, double depth_max,
                       const std::string& title);
void WriteNormalPicture(const std::string& path, const FloatMap& normal, const std::string& title);

// Greyscale image with a title (e.g. the input photo).
RgbImage TitledPicture(const RgbImage& image, const std::string& title);

// Tiles pictures row by row, `columns` per row, on a white background.
RgbImage TilePictures(const std::vector<RgbImage>& pictures, int columns, int gap = 6);

// Robust value range: the lo and hi quantiles (0..1) of the finite, positive values;
// false when there are none.
bool RobustRange(const std::vector<float>& values, double lo_quantile, double hi_quantile,
                 double* value_min, double* value_max);

}  // namespace mpmvs

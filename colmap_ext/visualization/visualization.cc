#include "colmap_ext/visualization/visualization.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

namespace mpmvs {
namespace {

struct Glyph {
  char c;
  const char* rows[7];
};

// Hand-drawn 5x7 glyphs ('#' = dot).
const Glyph kGlyphs[] = {
    {' ', {"     ", "     ", "     ", "     ", "     ", "     ", "     "}},
    {'0', {" ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### "}},
    {'1', {"  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
    {'2', {" ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####"}},
    {'3', {"#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### "}},
    {'4', {"   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # "}},
    {'5', {"#####", "#    ", "#### ", "    #", "    #", "#   #", " ### "}},
    {'6', {"  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### "}},
    {'7', {"#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   "}},
    {'8', {" ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### "}},
    {'9', {" ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  "}},
    {'A', {" ### ", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
    {'B', {"#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### "}},
    {'C', {" ### ", "#   #", "#    ", "#    ", "#    ", "#   #", " ### "}},
    {'D', {"#### ", "#   #", "#   #", "#   #", "#   #", "#   #", "#### "}},
    {'E', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####"}},
    {'F', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#    "}},
    {'G', {" ### ", "#   #", "#    ", "# ###", "#   #", "#   #", " ####"}},
    {'H', {"#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
    {'I', {" ### ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
    {'J', {"  ###", "   # ", "   # ", "   # ", "   # ", "#  # ", " ##  "}},
    {'K', {"#   #", "#  # ", "# #  ", "##   ", "# #  ", "#  # ", "#   #"}},
    {'L', {"#    ", "#    ", "#    ", "#    ", "#    ", "#    ", "#####"}},
    {'M', {"#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #"}},
    {'N', {"#   #", "#   #", "##  #", "# # #", "#  ##", "#   #", "#   #"}},
    {'O', {" ### ", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
    {'P', {"#### ", "#   #", "#   #", "#### ", "#    ", "#    ", "#    "}},
    {'Q', {" ### ", "#   #", "#   #", "#   #", "# # #", "#  # ", " ## #"}},
    {'R', {"#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #"}},
    {'S', {" ####", "#    ", "#    ", " ### ", "    #", "    #", "#### "}},
    {'T', {"#####", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {'U', {"#   #", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
    {'V', {"#   #", "#   #", "#   #", "#   #", "#   #", " # # ", "  #  "}},
    {'W', {"#   #", "#   #", "#   #", "# # #", "# # #", "# # #", " # # "}},
    {'X', {"#   #", "#   #", " # # ", "  #  ", " # # ", "#   #", "#   #"}},
    {'Y', {"#   #", "#   #", " # # ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {'Z', {"#####", "    #", "   # ", "  #  ", " #   ", "#    ", "#####"}},
    {'.', {"     ", "     ", "     ", "     ", "     ", " ##  ", " ##  "}},
    {',', {"     ", "     ", "     ", "     ", " ##  ", "  #  ", " #   "}},
    {'-', {"     ", "     ", "     ", "#####", "     ", "     ", "     "}},
    {'+', {"     ", "  #  ", "  #  ", "#####", "  #  ", "  #  ", "     "}},
    {'%', {"##   ", "##  #", "   # ", "  #  ", " #   ", "#  ##", "   ##"}},
    {':', {"     ", " ##  ", " ##  ", "     ", " ##  ", " ##  ", "     "}},
    {'/', {"     ", "    #", "   # ", "  #  ", " #   ", "#    ", "     "}},
    {'(', {"   # ", "  #  ", " #   ", " #   ", " #   ", "  #  ", "   # "}},
    {')', {" #   ", "  #  ", "   # ", "   # ", "   # ", "  #  ", " #   "}},
    {'=', {"     ", "     ", "#####", "     ", "#####", "     ", "     "}},
    {'_', {"     ", "     ", "     ", "     ", "     ", "     ", "#####"}},
    {'<', {"   # ", "  #  ", " #   ", "#    ", " #   ", "  #  ", "   # "}},
    {'>', {" #   ", "  #  ", "   # ", "    #", "   # ", "  #  ", " #   "}},
    {'m', {"     ", "     ", "## # ", "# # #", "# # #", "#   #", "#   #"}},
    {'?', {" ### ", "#   #", "    #", "   # ", "  #  ", "     ", "  #  "}},
};

const Glyph& FindGlyph(char c) {
  for (const Glyph& g : kGlyphs) {
    if (g.c == c) return g;  // the few lower-case glyphs (m for metres)
  }
  const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const Glyph& g : kGlyphs) {
    if (g.c == upper) return g;
  }
  for (const Glyph& g : kGlyphs) {
    if (g.c == '?') return g;
  }
  return kGlyphs[0];
}

const RgbColor kBlack{0, 0, 0};
const RgbColor kWhite{255, 255, 255};
const RgbColor kMissing{110, 110, 110};

std::string FormatLabel(double v, const std::string& unit) {
  char buf[32];
  const double a = std::abs(v);
  if (a != 0 && (a < 0.01 || a >= 1e5)) {
    std::snprintf(buf, sizeof(buf), "%.2e", v);
  } else if (a < 10) {
    std::snprintf(buf, sizeof(buf), "%.3g", v);
  } else {
    std::snprintf(buf, sizeof(buf), "%.1f", v);
  }
  return std::string(buf) + unit;
}

int FontScaleFor(int width) { return std::max(1, width / 500); }

// Draws a title bar above `body`.
RgbImage WithTitle(const RgbImage& body, const std::string& title, int scale) {
  const int title_h = title.empty() ? 0 : TextHeight(scale) + 6 * scale;
  RgbImage out = MakeRgbImage(body.width, body.height + title_h, kWhite);
  std::string upper = title;  // titles in capitals; only unit labels use the 'm' glyph
  for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  if (!title.empty()) DrawText(&out, 2 * scale, 3 * scale, upper, kBlack, scale);
  Blit(&out, body, 0, title_h);
  return out;
}

}  // namespace

RgbColor ScalarColor(double t) {
  static const double kStops[7][3] = {{20, 10, 90},   {30, 90, 230},  {20, 200, 220},
                                      {60, 200, 60},  {245, 225, 40}, {235, 70, 20},
                                      {120, 0, 10}};
  if (!std::isfinite(t)) t = 0;
  t = std::min(1.0, std::max(0.0, t)) * 6.0;
  const int i = std::min(5, static_cast<int>(t));
  const double f = t - i;
  RgbColor c;
  c.r = static_cast<uint8_t>(std::lround(kStops[i][0] + f * (kStops[i + 1][0] - kStops[i][0])));
  c.g = static_cast<uint8_t>(std::lround(kStops[i][1] + f * (kStops[i + 1][1] - kStops[i][1])));
  c.b = static_cast<uint8_t>(std::lround(kStops[i][2] + f * (kStops[i + 1][2] - kStops[i][2])));
  return c;
}

RgbImage MakeRgbImage(int width, int height, RgbColor fill) {
  RgbImage image;
  image.width = width;
  image.height = height;
  image.data.resize(3 * static_cast<size_t>(width) * height);
  for (size_t i = 0; i < image.data.size(); i += 3) {
    image.data[i] = fill.r;
    image.data[i + 1] = fill.g;
    image.data[i + 2] = fill.b;
  }
  return image;
}

void FillRect(RgbImage* image, int x, int y, int width, int height, RgbColor color) {
  for (int r = std::max(0, y); r < std::min(image->height, y + height); ++r) {
    for (int c = std::max(0, x); c < std::min(image->width, x + width); ++c) {
      uint8_t* p = &image->data[3 * (static_cast<size_t>(r) * image->width + c)];
      p[0] = color.r;
      p[1] = color.g;
      p[2] = color.b;
    }
  }
}

void Blit(RgbImage* dst, const RgbImage& src, int x, int y) {
  for (int r = 0; r < src.height; ++r) {
    const int dr = y + r;
    if (dr < 0 || dr >= dst->height) continue;
    for (int c = 0; c < src.width; ++c) {
      const int dc = x + c;
      if (dc < 0 || dc >= dst->width) continue;
      for (int k = 0; k < 3; ++k) {
        dst->data[3 * (static_cast<size_t>(dr) * dst->width + dc) + k] =
            src.data[3 * (static_cast<size_t>(r) * src.width + c) + k];
      }
    }
  }
}

void DrawText(RgbImage* image, int x, int y, const std::string& text, RgbColor color, int scale) {
  scale = std::max(1, scale);
  int pen = x;
  for (char ch : text) {
    const Glyph& g = FindGlyph(ch);
    for (int r = 0; r < 7; ++r) {
      for (int c = 0; c < 5; ++c) {
        if (g.rows[r][c] == '#') FillRect(image, pen + c * scale, y + r * scale, scale, scale, color);
      }
    }
    pen += 6 * scale;
  }
}

int TextWidth(const std::string& text, int scale) {
  return text.empty() ? 0 : static_cast<int>(text.size()) * 6 * scale - scale;
}

int TextHeight(int scale) { return 7 * scale; }

RgbImage ScalarPicture(const std::vector<float>& values, int width, int height,
                       const ScalarPictureOptions& options) {
  const int scale = FontScaleFor(width);
  const double lo = options.value_min;
  const double span = std::max(1e-12, options.value_max - options.value_min);
  auto to_t = [&](double v) {
    const double t = (v - lo) / span;
    return options.reverse ? 1.0 - t : t;
  };
  const std::string label_max = FormatLabel(options.value_max * options.label_factor, options.unit);
  const std::string label_mid =
      FormatLabel(0.5 * (options.value_min + options.value_max) * options.label_factor, options.unit);
  const std::string label_min = FormatLabel(options.value_min * options.label_factor, options.unit);
  const int label_w = std::max({TextWidth(label_max, scale), TextWidth(label_mid, scale),
                                TextWidth(label_min, scale)});
  const int bar_x = width + 6 * scale, bar_w = 12 * scale;
  const int text_h = TextHeight(scale);
  RgbImage body = MakeRgbImage(bar_x + bar_w + 4 * scale + label_w + 4 * scale, height, kWhite);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const float v = values[static_cast<size_t>(r) * width + c];
      RgbColor color = kBlack;
      if (std::isfinite(v)) {
        color = ScalarColor(to_t(v));
      } else if (std::isinf(v) && v < 0) {
        color = kMissing;
      }
      FillRect(&body, c, r, 1, 1, color);
    }
  }
  // Colour bar: value_max at the top.
  for (int r = 0; r < height; ++r) {
    const double v = options.value_max - span * r / std::max(1, height - 1);
    FillRect(&body, bar_x, r, bar_w, 1, ScalarColor(to_t(v)));
  }
  const int label_x = bar_x + bar_w + 4 * scale;
  DrawText(&body, label_x, 0, label_max, kBlack, scale);
  DrawText(&body, label_x, (height - text_h) / 2, label_mid, kBlack, scale);
  DrawText(&body, label_x, height - text_h, label_min, kBlack, scale);
  return WithTitle(body, options.title, scale);
}

RgbImage DepthPicture(const FloatMap& depth, double depth_min, double depth_max,
                      const std::string& title) {
  std::vector<float> values(static_cast<size_t>(depth.width) * depth.height);
  for (size_t i = 0; i < values.size(); ++i) {
    const float z = depth.data[i];
    values[i] = (std::isfinite(z) && z > 0) ? z : std::nanf("");
  }
  ScalarPictureOptions options;
  options.value_min = depth_min;
  options.value_max = depth_max;
  options.reverse = true;
  options.title = title;
  options.unit = "m";
  return ScalarPicture(values, depth.width, depth.height, options);
}

RgbImage NormalPicture(const FloatMap& normal, const std::string& title) {
  RgbImage body = MakeRgbImage(normal.width, normal.height, kBlack);
  for (int r = 0; r < normal.height; ++r) {
    for (int c = 0; c < normal.width; ++c) {
      const float n[3] = {normal.At(r, c, 0), -normal.At(r, c, 1), -normal.At(r, c, 2)};
      if ((n[0] == 0 && n[1] == 0 && n[2] == 0) || !std::isfinite(n[0] + n[1] + n[2])) continue;
      RgbColor color;
      color.r = static_cast<uint8_t>(std::lround(127.5 * (std::max(-1.f, std::min(1.f, n[0])) + 1)));
      color.g = static_cast<uint8_t>(std::lround(127.5 * (std::max(-1.f, std::min(1.f, n[1])) + 1)));
      color.b = static_cast<uint8_t>(std::lround(127.5 * (std::max(-1.f, std::min(1.f, n[2])) + 1)));
      FillRect(&body, c, r, 1, 1, color);
    }
  }
  return WithTitle(body, title, FontScaleFor(normal.width));
}

void WriteDepthPicture(const std::string& path, const FloatMap& depth, double depth_min, double depth_max,
                       const std::string& title) {
  WriteRgbPng(path, DepthPicture(depth, depth_min, depth_max, title));
}

void WriteNormalPicture(const std::string& path, const FloatMap& normal, const std::string& title) {
  WriteRgbPng(path, NormalPicture(normal, title));
}

RgbImage TitledPicture(const RgbImage& image, const std::string& title) {
  return WithTitle(image, title, FontScaleFor(image.width));
}

RgbImage TilePictures(const std::vector<RgbImage>& pictures, int columns, int gap) {
  if (pictures.empty()) return MakeRgbImage(1, 1, kWhite);
  columns = std::max(1, std::min(columns, static_cast<int>(pictures.size())));
  const int rows = (static_cast<int>(pictures.size()) + columns - 1) / columns;
  std::vector<int> col_w(columns, 0), row_h(rows, 0);
  for (size_t i = 0; i < pictures.size(); ++i) {
    col_w[i % columns] = std::max(col_w[i % columns], pictures[i].width);
    row_h[i / columns] = std::max(row_h[i / columns], pictures[i].height);
  }
  int total_w = gap, total_h = gap;
  for (int w : col_w) total_w += w + gap;
  for (int h : row_h) total_h += h + gap;
  RgbImage out = MakeRgbImage(total_w, total_h, kWhite);
  int y = gap;
  for (int r = 0; r < rows; ++r) {
    int x = gap;
    for (int c = 0; c < columns; ++c) {
      const size_t i = static_cast<size_t>(r) * columns + c;
      if (i < pictures.size()) Blit(&out, pictures[i], x, y);
      x += col_w[c] + gap;
    }
    y += row_h[r] + gap;
  }
  return out;
}

bool RobustRange(const std::vector<float>& values, double lo_quantile, double hi_quantile,
                 double* value_min, double* value_max) {
  std::vector<float> v;
  v.reserve(values.size());
  for (float x : values) {
    if (std::isfinite(x) && x > 0) v.push_back(x);
  }
  if (v.empty()) return false;
  // Two selections, not a sort: the same order statistics in linear time (a sort of every
  // depth was 0.5 % of a whole run). With hi < lo, v[hi] <= v[lo] whatever it holds after the
  // first selection, and the range is widened below: no second selection is needed.
  const size_t n = v.size();
  const size_t lo = std::min(n - 1, static_cast<size_t>(lo_quantile * (n - 1)));
  const size_t hi = std::min(n - 1, static_cast<size_t>(hi_quantile * (n - 1)));
  std::nth_element(v.begin(), v.begin() + lo, v.end());
  *value_min = v[lo];
  if (hi > lo) std::nth_element(v.begin() + lo + 1, v.begin() + hi, v.end());
  *value_max = v[hi];
  if (*value_max <= *value_min) *value_max = *value_min + 1e-6;
  return true;
}

}  // namespace mpmvs

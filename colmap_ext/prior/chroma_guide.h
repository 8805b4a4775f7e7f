#pragma once
// The reference image's chroma guide for the bilateral NCC weights (kernels/ncc.h,
// ImageView::chroma; kernels/DESIGN.md item 13). Grey alone cannot separate two surfaces of
// equal brightness and different colour, and in two-view scenes most wrong depths sit at
// such edges. The guide adds colour without adding colour noise: chroma is smoothed first.
#include <vector>

#include "colmap_ext/io/image_io.h"

namespace mpmvs {

// Binomial 3x3 passes applied to the chroma planes (about a Gaussian of sigma 1.4 px).
constexpr int kChromaSmoothingPasses = 4;

// Per pixel, interleaved: weight * (R - G) and weight * (B - G), each smoothed by
// kChromaSmoothingPasses binomial 3x3 passes with clamp-to-edge borders. A grey image gives
// zeros. Throws Error on an image whose data does not match its size.
std::vector<float> MakeChromaGuide(const RgbImage& image, float weight);

}  // namespace mpmvs

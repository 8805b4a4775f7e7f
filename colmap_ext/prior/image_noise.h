#pragma once
// Sensor noise of a grey image, for the photometric cost's noise floor.
#include "colmap_ext/io/image_io.h"

namespace mpmvs {

// Variance (grey levels^2) of the image's pixel noise, estimated robustly from the median
// absolute response of a second-difference filter (Immerkaer's mask, whose response to
// white noise has 6 sigma): texture and edges affect only the upper half of the responses.
float EstimateNoiseVariance(const GrayImage& image);

}  // namespace mpmvs

#pragma once
// PNG pictures of depth and normal maps, for people who would rather look than read.
#include <string>

#include "colmap_ext/mat_io.h"

namespace mpmvs {

// Depth coloured over [depth_min, depth_max] (near = warm), invalid pixels black.
void WriteDepthPicture(const std::string& path, const FloatMap& depth, float depth_min, float depth_max);
// Camera-frame normal as RGB = (n + 1) / 2 with y and z flipped so surfaces facing the
// camera look blue-ish as in most viewers; invalid pixels black.
void WriteNormalPicture(const std::string& path, const FloatMap& normal);

}  // namespace mpmvs

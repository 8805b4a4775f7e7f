#pragma once
// What a synthetic scene layout is built from and what it builds: shared by the named
// layouts (synthetic_layouts.h) and the room family (room_layouts.h).
#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/synthetic/scene_renderer.h"

namespace mpmvs {

struct LayoutParams {
  std::string scene = "indoor";
  int width = 320;
  int height = 240;
  int num_views = 5;
  uint64_t seed = 1;
  // plane scene: the plane normal is turned this far (degrees) away from the cameras;
  // every camera's optical axis then meets the plane at least this obliquely.
  double plane_tilt_deg = 0;
};

struct SyntheticLayout {
  SyntheticWorld world;  // geometry already built
  std::vector<SyntheticCamera> cameras;
  // plane scene only: angle (deg) between the plane normal and each camera's optical axis.
  std::vector<double> plane_view_angles_deg;
};

}  // namespace mpmvs

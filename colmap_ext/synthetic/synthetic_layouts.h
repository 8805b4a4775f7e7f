#pragma once
// The named synthetic scenes (geometry, materials, lights and cameras):
//   indoor  a room: plain walls/floor/ceiling, a few textured objects and posters, cameras
//           inside looking around with overlapping views;
//   facade  an outdoor courtyard: large plain façade walls with recessed windows, a door,
//           textured paving, poles, a tree, sky without depth;
//   plane   one textured plane, optionally tilted away from all cameras (sanity case);
//   plain_wall  a plain, lamp-lit wall framed by textured posters, two boxes in front
//           (the planar prior's case: only the frame and the boxes can be matched);
//   room_window, room_l, room_corridor   multi-view rooms (room_layouts.h).
// World frame: z up, metres.
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

std::vector<std::string> SyntheticLayoutNames();
// The names joined by ", " (for messages).
std::string SyntheticLayoutNameList();
// Throws Error for an unknown scene name.
SyntheticLayout BuildSyntheticLayout(const LayoutParams& params);

}  // namespace mpmvs

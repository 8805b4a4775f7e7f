#pragma once
// The named synthetic scenes (geometry, materials, lights and cameras):
//   indoor  a room: plain walls/floor/ceiling, a few textured objects and posters, cameras
//           inside looking around with overlapping views;
//   facade  an outdoor courtyard: large plain façade walls with recessed windows, a door,
//           textured paving, poles, a tree, sky without depth;
//   plane   one textured plane, optionally tilted away from all cameras (sanity case);
//   plain_wall  a plain, lamp-lit wall framed by textured posters, two boxes in front
//           (the planar prior's case: only the frame and the boxes can be matched);
//   room_window, room_l, room_corridor, room_sweep   multi-view rooms (room_layouts.h).
// World frame: z up, metres.
#include <string>
#include <vector>

#include "colmap_ext/synthetic/layout_types.h"

namespace mpmvs {

std::vector<std::string> SyntheticLayoutNames();
// The names joined by ", " (for messages).
std::string SyntheticLayoutNameList();
// Throws Error for an unknown scene name.
SyntheticLayout BuildSyntheticLayout(const LayoutParams& params);

}  // namespace mpmvs

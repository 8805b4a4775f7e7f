#pragma once
// The multi-view room family: closed rooms whose walls and ceiling are plain paint lit by
// lamps (smooth shading gradients only), with textured furniture, posters and a thin
// striped pole. Made to measure untextured-surface reconstruction on, not to tune to one:
//   room_window    box room, a bright window-like area on one wall, furniture in the
//                  corners, cameras on an arc facing the window wall;
//   room_l         L-shaped room with a large, weakly textured concrete floor, cameras on
//                  a path along the outer walls turning round the corner;
//   room_corridor  long narrow corridor with a side branch, ceiling lamp panels, cameras
//                  walking forward and turning into the branch;
//   room_sweep     long hall, cameras translating across it while facing its far wall, so
//                  the plain side walls, floor and ceiling are seen at grazing angles
//                  (60-85 degrees); a ceiling light whose hot spot saturates.
// The shell's materials name their surfaces ("walls", "side walls", "far wall", "floor",
// "ceiling") for the per-surface scores of `evaluate`.
// Intrinsics: PINHOLE, fx = 0.8 width (512 px at 640), slightly off-centre principal point.
#include <string>
#include <vector>

#include "colmap_ext/synthetic/layout_types.h"

namespace mpmvs {

std::vector<std::string> RoomLayoutNames();
bool IsRoomLayout(const std::string& name);
// Throws Error for a name not in RoomLayoutNames().
SyntheticLayout BuildRoomLayout(const LayoutParams& params);

}  // namespace mpmvs

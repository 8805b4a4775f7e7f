#pragma once
// `colmap mp_patch_match_stereo`: the command function that the patch in patches/ adds to
// COLMAP's command table (src/colmap/exe/colmap.cc), with COLMAP's calling convention
// (argv[0] = program, options from argv[1]). Same options and maps as
// `colmap-mp mp_patch_match_stereo`; the workspace is read and the maps are written with
// COLMAP's own classes (colmap_workspace_io.h).

namespace mpmvs {

// Returns EXIT_SUCCESS / EXIT_FAILURE; errors are logged, never thrown.
int RunColmapMpPatchMatchStereo(int argc, char** argv);

}  // namespace mpmvs

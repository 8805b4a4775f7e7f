#pragma once
// The command-line flags of mp_patch_match_stereo (both front ends).
#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/pipeline/patch_match_options.h"

namespace mpmvs {

// Registers every option on the parser (COLMAP-only algorithm options are accepted and
// ignored with a warning naming the --MPMVS. option to use).
void AddPatchMatchOptions(OptionParser* parser, PatchMatchStereoOptions* colmap_options,
                          MpMvsOptions* mpmvs_options);

}  // namespace mpmvs

#pragma once
// The command-line flags of mp_patch_match_stereo (both front ends).
#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"
#include "colmap_ext/options/patch_match_options.h"

namespace mpmvs {

// Registers every option on the parser (COLMAP-only algorithm options are accepted and
// ignored with a warning naming the --MPMVS. option to use).
void AddPatchMatchOptions(OptionParser* parser, PatchMatchStereoOptions* colmap_options,
                          MpMvsOptions* mpmvs_options);

// COLMAP's general options (--project_path, --log_to_stderr, --log_level, --random_seed):
// applied once parsed (logging, and --random_seed to mpmvs_options->seed).
void AddGeneralOptions(OptionParser* parser, MpMvsOptions* mpmvs_options);

// Everything mp_patch_match_stereo accepts: --workspace_path (required), the workspace
// options, AddPatchMatchOptions and AddGeneralOptions. pmvs_option_name: accepted and unused (COLMAP's PMVS).
void AddMpPatchMatchRunOptions(OptionParser* parser, MpPatchMatchRun* run, std::string* pmvs_option_name);

}  // namespace mpmvs

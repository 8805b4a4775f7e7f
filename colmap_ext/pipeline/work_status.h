#pragma once
// How far a workspace is: per stage, which shards still have images to do. slurm_submit
// uses it so that a second submit runs only the unfinished stages and shards (and nothing
// for a finished workspace).
#include <string>
#include <vector>

#include "colmap_ext/pipeline/mp_patch_match_stereo.h"

namespace mpmvs {

struct StageStatus {
  std::string name;
  std::vector<int> unfinished_shards;  // ascending
  int unfinished_images = 0;
};

// Loads the workspace and patch-match.cfg of run as mp_patch_match_stereo does and splits
// the images into `shards` (shard.h). An image is finished in a stage when its result of
// that stage exists (and the maps the stage writes), or when no stage needs that result any
// more (NeededStageResults: its final maps exist, or the later stages' results do).
std::vector<StageStatus> ComputeWorkStatus(const MpPatchMatchRun& run, int shards);

}  // namespace mpmvs

#pragma once
// Everything one run of mp_patch_match_stereo needs, translated once from the command-line
// options: the stages, the planar prior and output filter parameters, the backend and
// cache settings.
#include <cstddef>
#include <string>
#include <vector>

#include "colmap_ext/options/patch_match_options.h"
#include "colmap_ext/plan/backend_options.h"
#include "colmap_ext/plan/shard.h"
#include "colmap_ext/plan/stage_plan.h"
#include "colmap_ext/prior/planar_prior.h"
#include "kernels/patch_match.h"

namespace mpmvs {

struct RunPlan {
  PipelinePlan pipeline;
  std::string final_type;  // "geometric" or "photometric": the last maps written
  PlanarPriorOptions prior;  // selection per stage: StagePlan::prior_geometric_selection
  bool filter = false;       // COLMAP-style output filter on the written maps
  kernels::FilterParams filter_params;
  BackendOptions backend;
  size_t cache_bytes = 0;  // --PatchMatchStereo.cache_size
  int num_threads = -1;
  float chroma_guide_weight = 0;  // the colour guide of the NCC weights (0: none)
  int sources_per_reference = 0;
  bool overwrite = false;
  bool final_pictures = false;  // --MPMVS.write_pictures final or all: of the maps fusion reads
  bool stage_pictures = false;  // --MPMVS.write_pictures all: of every stage and written map
  bool write_consistency_graph = false;
  bool keep_states = false;  // keep every stage's state (else removed once not needed)
  bool allow_missing_files = false;  // also: a source's missing stage result is left out
  // Which part of the work this process does (plan/shard.h, schedule/work_claims.h).
  ShardSpec shard;
  std::vector<std::string> image_names;  // --MPMVS.image_list_path ("": all)
  int only_stage = -1;                   // --MPMVS.stage: index in pipeline.stages (-1: all)
  int claim_lease_seconds = 600;
  // Whether other processes may run images of this run: their inputs are waited for.
  bool Partial() const { return !shard.All() || !image_names.empty(); }
};

// Checks the options (throws Error naming the bad one) and translates them.
RunPlan MakeRunPlan(const PatchMatchStereoOptions& colmap_options, const MpMvsOptions& options,
                    bool cpu_side_work);

}  // namespace mpmvs

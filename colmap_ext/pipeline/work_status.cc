#include "colmap_ext/pipeline/work_status.h"

#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/plan/run_plan.h"
#include "colmap_ext/plan/shard.h"
#include "colmap_ext/schedule/stage_inputs.h"
#include "colmap_ext/schedule/stage_results.h"
#include "colmap_ext/store/result_fingerprint.h"
#include "colmap_ext/store/stage_store.h"
#include "colmap_ext/store/state_record.h"

namespace mpmvs {

std::vector<StageStatus> ComputeWorkStatus(const MpPatchMatchRun& run, int shards) {
  MpMvsWorkspaceIo io;
  const RunPlan plan = MakeRunPlan(run.colmap_options, run.options, false);
  const DenseWorkspace workspace = io.Load(run.workspace_path, run.colmap_options.max_image_size);
  const std::vector<ReferenceProblem> problems =
      LoadReferenceProblems(workspace, run.config_path, run.colmap_options, plan.sources_per_reference).runnable;
  StageStore store(workspace, &io, plan, problems,
                   MakeResultFingerprint(run.colmap_options, run.options, workspace, problems));
  const StageInputs inputs(plan, problems);
  std::vector<char> done;
  for (const ReferenceProblem& p : problems) done.push_back(!plan.overwrite && store.AllFinalOutputsExist(p.ref));
  const std::vector<std::vector<char>> needed = NeededStageResults(plan, problems, inputs, &store);
  const std::vector<std::vector<size_t>> split = SplitIntoShards(workspace, problems, plan.image_names, shards);

  std::vector<StageStatus> status;
  for (size_t s = 0; s < plan.pipeline.stages.size(); ++s) {
    StageStatus st;
    st.name = plan.pipeline.stages[s].name;
    for (int k = 0; k < shards; ++k) {
      int unfinished = 0;
      for (size_t i : split[k]) {
        const int view = problems[i].ref;
        if (!needed[i][s]) continue;
        if (!inputs.Produces(static_cast<int>(s), view)) continue;
        const bool writes_photometric = static_cast<int>(s) == plan.pipeline.photometric_output;
        // A needed state of a done image is recomputed without writing its maps.
        const bool writes_final = !done[i] && static_cast<int>(s) == plan.pipeline.geometric_output;
        if (plan.overwrite || writes_final || !store.HasState(view, st.name) ||
            (writes_photometric && !done[i] && !store.FinalOutputsExist(view, "photometric"))) {
          ++unfinished;
        }
      }
      if (unfinished > 0) st.unfinished_shards.push_back(k);
      st.unfinished_images += unfinished;
    }
    status.push_back(st);
  }
  return status;
}

}  // namespace mpmvs

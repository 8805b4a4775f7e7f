#pragma once
// What a stage of one reference image reads from stereo/mpmvs: its own result of the input
// stage and, in a stage with the geometric term, its sources' results of the input stage.
// A process that runs only some images (--MPMVS.shard, --MPMVS.image_list_path) or one
// stage (--MPMVS.stage) checks these exist before it starts a stage, so that it never runs
// a stage on fewer inputs than one process running everything would have had.
#include <string>
#include <vector>

#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/plan/run_plan.h"

namespace mpmvs {

class StageInputs {
 public:
  // problems: every runnable reference image of the run (not only this process's).
  StageInputs(const RunPlan& plan, const std::vector<ReferenceProblem>& problems);

  // Whether a complete run writes the result of `view` in stage `stage` (an image whose
  // sources all lack their geometric-stage inputs is skipped, as in one process).
  bool Produces(int stage, int view) const;

  struct Input {
    int stage = -1;
    int view = -1;
  };
  // The results stage `stage` of problem p reads (empty for the first stage).
  std::vector<Input> Inputs(int stage, const ReferenceProblem& p) const;

 private:
  const RunPlan& plan_;
  std::vector<std::vector<bool>> produces_;  // [stage][view]
};

}  // namespace mpmvs

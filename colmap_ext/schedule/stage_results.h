#pragma once
// Which stage results a run still needs, judged from what is on disk (the states in
// stereo/mpmvs and the final maps), so that a run computes only those and removes the others.
// A result of (stage s, image v) is needed until every stage that reads it (s's successor:
// v's own next stage and, when that stage is geometric, the next stage of each image that has
// v as a source) has its result, or no longer needs it itself, and the maps stage s writes for
// v exist. A needed result is read (from its state) or computed (from its inputs, which are
// then needed too); a result that is not needed is never read again, so its state can go and
// resuming, shards and any split over processes still give the maps of one run.
#include <string>
#include <vector>

#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/plan/run_plan.h"
#include "colmap_ext/schedule/stage_inputs.h"
#include "colmap_ext/store/stage_store.h"

namespace mpmvs {

// [problem][stage]: whether the run still needs that result (problems: every runnable image).
std::vector<std::vector<char>> NeededStageResults(const RunPlan& plan, const std::vector<ReferenceProblem>& problems,
                                                  const StageInputs& inputs, StageStore* store);

// Whether the result of stage `stage` of problems[problem] is needed: one entry of
// NeededStageResults, judging only the results it depends on.
bool StageResultNeeded(const RunPlan& plan, const std::vector<ReferenceProblem>& problems, const StageInputs& inputs,
                       StageStore* store, int stage, size_t problem);

// "geometric" or "photometric" when stage `stage` writes those maps, else "".
std::string StageMapType(const PipelinePlan& pipeline, int stage);

// Whether the maps that stage `stage` writes (if any) are written from its
// inputs even when its result is resumed: the output filter and the consistency graph read
// the sources' results of the input stage.
bool WritesMapsFromInputs(const RunPlan& plan, int stage);

}  // namespace mpmvs

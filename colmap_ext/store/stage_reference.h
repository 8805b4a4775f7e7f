#pragma once
// One reference image of a stage, assembled for the backend: its image and colour guide,
// its sources' images and depth maps, the input stage's planes and the planar prior, and
// whether it is computed, resumed from its state file or skipped.
#include <memory>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/plan/run_plan.h"
#include "colmap_ext/prior/planar_prior.h"
#include "colmap_ext/store/stage_store.h"
#include "kernels/patch_match.h"

namespace mpmvs {

// Owns the data pm's pointers refer to.
struct StageReference {
  // kNotNeeded: no stage reads this result any more (its later stages' results exist).
  enum class Action { kFinalMapsExist, kNotNeeded, kResume, kNoSources, kCompute };
  Action action = Action::kCompute;
  const ReferenceProblem* problem = nullptr;
  bool filter_here = false;  // the output filter runs on this stage's written maps
  // False for a reference whose final maps were whole when it was claimed (at the start,
  // or written meanwhile by another process of the run): it is computed only for the state
  // another reference needs, and its maps are kept.
  bool write_final = true;
  kernels::PatchMatchProblem pm;
  std::vector<std::shared_ptr<const GrayImage>> images;
  std::shared_ptr<const std::vector<float>> chroma;  // pm.ref_image.chroma
  std::vector<std::shared_ptr<const std::vector<float>>> depths;
  kernels::PatchMatchResult input;  // the input stage's planes and costs (pm.init_*)
  PlanarPriorModel prior;           // pm.prior_*
};

// Loads and assembles reference image p for stage stage_index; decides whether it is
// computed, resumed or skipped. done: p's final maps are whole (judged when p was claimed;
// they are kept); state_needed: the run still needs this stage's result of p
// (schedule/stage_results.h), so a done reference without a usable state computes it. Throws Error naming the file on
// damaged input.
std::unique_ptr<StageReference> PrepareStageReference(const RunPlan& plan, const DenseWorkspace& workspace,
                                                      StageStore* store, int stage_index,
                                                      const ReferenceProblem& p, bool done, bool state_needed);

}  // namespace mpmvs

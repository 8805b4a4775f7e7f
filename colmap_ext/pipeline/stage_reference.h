#pragma once
// One reference image of a stage, assembled for the backend: its image and colour guide,
// its sources' images and depth maps, the input stage's planes and the planar prior, and
// whether it is computed, resumed from its state file or skipped.
#include <memory>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/pipeline/planar_prior.h"
#include "colmap_ext/pipeline/reference_problems.h"
#include "colmap_ext/pipeline/run_plan.h"
#include "colmap_ext/pipeline/stage_store.h"
#include "kernels/patch_match.h"

namespace mpmvs {

// Owns the data pm's pointers refer to.
struct StageReference {
  enum class Action { kFinalMapsExist, kResume, kNoSources, kCompute };
  Action action = Action::kCompute;
  const ReferenceProblem* problem = nullptr;
  bool filter_here = false;  // the output filter runs on this stage's written maps
  kernels::PatchMatchProblem pm;
  std::vector<std::shared_ptr<const GrayImage>> images;
  std::shared_ptr<const std::vector<float>> chroma;  // pm.ref_image.chroma
  std::vector<std::shared_ptr<const std::vector<float>>> depths;
  kernels::PatchMatchResult input;  // the input stage's planes and costs (pm.init_*)
  PlanarPriorModel prior;           // pm.prior_*
};

// Loads and assembles reference image p for stage stage_index; decides whether it is
// computed, resumed or skipped. Throws Error naming the file on damaged input.
std::unique_ptr<StageReference> PrepareStageReference(const RunPlan& plan, const DenseWorkspace& workspace,
                                                      StageStore* store, int stage_index,
                                                      const ReferenceProblem& p);

}  // namespace mpmvs

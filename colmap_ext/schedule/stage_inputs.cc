#include "colmap_ext/schedule/stage_inputs.h"

#include <algorithm>

namespace mpmvs {

StageInputs::StageInputs(const RunPlan& plan, const std::vector<ReferenceProblem>& problems) : plan_(plan) {
  int num_views = 0;
  for (const ReferenceProblem& p : problems) {
    num_views = std::max(num_views, p.ref + 1);
    for (int s : p.src) num_views = std::max(num_views, s + 1);
  }
  const auto& stages = plan.pipeline.stages;
  produces_.assign(stages.size(), std::vector<bool>(num_views, false));
  for (size_t s = 0; s < stages.size(); ++s) {
    for (const ReferenceProblem& p : problems) {
      const int in = stages[s].input;
      bool runs = in < 0 || produces_[in][p.ref];
      if (runs && in >= 0 && stages[s].schedule.geometric) {
        runs = std::any_of(p.src.begin(), p.src.end(), [&](int src) { return produces_[in][src]; });
      }
      produces_[s][p.ref] = runs;
    }
  }
}

bool StageInputs::Produces(int stage, int view) const {
  return view >= 0 && view < static_cast<int>(produces_[stage].size()) && produces_[stage][view];
}

std::vector<StageInputs::Input> StageInputs::Inputs(int stage, const ReferenceProblem& p) const {
  std::vector<Input> inputs;
  const StagePlan& st = plan_.pipeline.stages[stage];
  if (st.input < 0) return inputs;
  inputs.push_back({st.input, p.ref});
  if (!st.schedule.geometric) return inputs;
  for (int src : p.src) {
    if (Produces(st.input, src)) inputs.push_back({st.input, src});
  }
  return inputs;
}

}  // namespace mpmvs

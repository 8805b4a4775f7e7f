#include "colmap_ext/schedule/stage_inputs.h"

#include <algorithm>
#include <map>

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

std::vector<std::vector<char>> NeededStageResults(const RunPlan& plan, const std::vector<ReferenceProblem>& problems,
                                                  const std::vector<char>& done) {
  const std::vector<StagePlan>& stages = plan.pipeline.stages;
  std::map<int, size_t> index;
  for (size_t i = 0; i < problems.size(); ++i) index.emplace(problems[i].ref, i);
  std::vector<std::vector<char>> needed(problems.size(), std::vector<char>(stages.size(), 0));
  for (size_t i = 0; i < problems.size(); ++i) {
    if (!done[i]) needed[i].assign(stages.size(), 1);
  }
  for (int s = static_cast<int>(stages.size()) - 1; s >= 0; --s) {
    const int input = stages[s].input;
    if (input < 0) continue;
    for (size_t i = 0; i < problems.size(); ++i) {
      if (!needed[i][s]) continue;
      needed[i][input] = 1;
      if (!stages[s].schedule.geometric) continue;
      for (int src : problems[i].src) {
        const auto it = index.find(src);
        if (it != index.end()) needed[it->second][input] = 1;
      }
    }
  }
  return needed;
}

}  // namespace mpmvs

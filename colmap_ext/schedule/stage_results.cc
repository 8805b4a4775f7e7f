#include "colmap_ext/schedule/stage_results.h"

#include <algorithm>
#include <map>
#include <utility>

namespace mpmvs {
namespace {

// Needed(s, i), memoised for one look at the disk.
class Needs {
 public:
  Needs(const RunPlan& plan, const std::vector<ReferenceProblem>& problems, const StageInputs& inputs,
        StageStore* store)
      : plan_(plan), problems_(problems), inputs_(inputs), store_(store) {
    const size_t num_stages = plan.pipeline.stages.size();
    memo_.assign(problems.size(), std::vector<signed char>(num_stages, -1));
    std::map<int, size_t> index;
    for (size_t i = 0; i < problems.size(); ++i) index.emplace(problems[i].ref, i);
    // Who reads image i's results besides i itself: the images that have i as a source.
    source_of_.resize(problems.size());
    for (size_t r = 0; r < problems.size(); ++r) {
      for (int src : problems[r].src) {
        const auto it = index.find(src);
        if (it != index.end() && it->second != r) source_of_[it->second].push_back(r);
      }
    }
  }

  bool Needed(int s, size_t i) {
    signed char& memo = memo_[i][s];
    if (memo < 0) memo = Judge(s, i) ? 1 : 0;
    return memo == 1;
  }

 private:
  bool Judge(int s, size_t i) {
    const int view = problems_[i].ref;
    if (!inputs_.Produces(s, view)) return false;  // never made, never read
    if (plan_.overwrite) return true;               // everything is computed again
    const std::string type = StageMapType(plan_.pipeline, s);
    if (!type.empty() && !FinalMapsExist(view, type)) return true;  // its maps are still to write
    const std::vector<StagePlan>& stages = plan_.pipeline.stages;
    for (int u = s + 1; u < static_cast<int>(stages.size()); ++u) {
      if (stages[u].input != s) continue;
      if (ReaderNeeds(u, i)) return true;
      if (!stages[u].schedule.geometric) continue;
      for (size_t r : source_of_[i]) {
        if (ReaderNeeds(u, r)) return true;
      }
    }
    return false;
  }

  // Whether stage u of problem r still has to read its input: its result is needed and is not
  // there (it is computed), or its maps are written from its inputs and are not there yet.
  bool ReaderNeeds(int u, size_t r) {
    if (!Needed(u, r)) return false;
    const int view = problems_[r].ref;
    if (!store_->HasState(view, plan_.pipeline.stages[u].name)) return true;
    const std::string type = StageMapType(plan_.pipeline, u);
    return !type.empty() && WritesMapsFromInputs(plan_, u) && !FinalMapsExist(view, type);
  }

  // The store's check reads each map's record: once per view and type (an image is read by
  // every image that has it as a source).
  bool FinalMapsExist(int view, const std::string& type) {
    const auto key = std::make_pair(view, type);
    auto it = final_maps_exist_.find(key);
    if (it == final_maps_exist_.end()) it = final_maps_exist_.emplace(key, store_->FinalOutputsExist(view, type)).first;
    return it->second;
  }

  const RunPlan& plan_;
  const std::vector<ReferenceProblem>& problems_;
  const StageInputs& inputs_;
  StageStore* store_;
  std::vector<std::vector<size_t>> source_of_;
  std::vector<std::vector<signed char>> memo_;  // -1: not judged yet
  std::map<std::pair<int, std::string>, bool> final_maps_exist_;
};

}  // namespace

std::string StageMapType(const PipelinePlan& pipeline, int stage) {
  if (stage == pipeline.geometric_output) return "geometric";
  if (stage == pipeline.photometric_output) return "photometric";
  return "";
}

bool WritesMapsFromInputs(const RunPlan& plan, int stage) {
  const PipelinePlan& pipeline = plan.pipeline;
  const bool filtered = plan.filter && (stage == pipeline.geometric_output ||
                                        (stage == pipeline.photometric_output && pipeline.geometric_output < 0));
  const bool graph = plan.write_consistency_graph &&
                     (stage == pipeline.geometric_output || stage == pipeline.photometric_output);
  return pipeline.stages[stage].input >= 0 && (filtered || graph);
}

std::vector<std::vector<char>> NeededStageResults(const RunPlan& plan, const std::vector<ReferenceProblem>& problems,
                                                  const StageInputs& inputs, StageStore* store) {
  Needs needs(plan, problems, inputs, store);
  std::vector<std::vector<char>> needed(problems.size(), std::vector<char>(plan.pipeline.stages.size(), 0));
  for (size_t i = 0; i < problems.size(); ++i) {
    for (size_t s = 0; s < plan.pipeline.stages.size(); ++s) needed[i][s] = needs.Needed(static_cast<int>(s), i);
  }
  return needed;
}

bool StageResultNeeded(const RunPlan& plan, const std::vector<ReferenceProblem>& problems, const StageInputs& inputs,
                       StageStore* store, int stage, size_t problem) {
  return Needs(plan, problems, inputs, store).Needed(stage, problem);
}

}  // namespace mpmvs

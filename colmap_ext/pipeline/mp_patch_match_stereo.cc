#include "colmap_ext/pipeline/mp_patch_match_stereo.h"

#include <chrono>
#include <exception>
#include <map>
#include <memory>
#include <set>
#include <utility>

#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/pipeline/backend.h"
#include "colmap_ext/pipeline/output_maps.h"
#include "colmap_ext/pipeline/reference_problems.h"
#include "colmap_ext/pipeline/run_plan.h"
#include "colmap_ext/pipeline/stage_reference.h"
#include "colmap_ext/pipeline/stage_store.h"
#include "colmap_ext/pipeline/state_record.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void AddRunStatistics(const kernels::PatchMatchResult& result, StageSummary* summary) {
  ++summary->images_computed;
  summary->ncc_evaluations += result.init_ncc_evaluations;
  for (const auto& it : result.iterations) summary->ncc_evaluations += it.ncc_evaluations;
  summary->pixel_iterations += static_cast<uint64_t>(result.width) * result.height * result.iterations.size();
  if (summary->iterations.empty()) summary->iterations = result.iterations;
}

// Plan; then for each stage and reference image: prepare, run, finish, store.
class Controller {
 public:
  Controller(const MpPatchMatchRun& run, WorkspaceIo* io) : run_(run), io_(io) {}

  MpPatchMatchSummary Run();

 private:
  // Whether every runnable reference already has its final maps (nothing to do).
  bool AllFinalMapsExist() const;
  // needed_: which stage results each reference must have, its own final maps being done
  // or not: a reference to compute needs every stage, and each stage the results of its
  // input stage (its own and, in geometric stages, its sources').
  void PlanNeededStates();
  void CreateOutputDirectories() const;
  void RunStage(int stage_index, MpPatchMatchSummary* summary);
  // Output filter, geometric invalidation and the COLMAP maps of a stage that writes them.
  void WriteOutputs(int stage_index, const StageReference& ref, kernels::PatchMatchResult* result);

  MpPatchMatchRun run_;
  WorkspaceIo* io_;
  RunPlan plan_;
  DenseWorkspace workspace_;
  std::vector<ReferenceProblem> problems_;
  std::vector<char> done_;                  // final maps whole at the start (kept)
  std::vector<std::vector<char>> needed_;   // [problem][stage]
  std::set<int> written_;                   // views whose final maps this run wrote
  std::unique_ptr<StageStore> store_;
  std::unique_ptr<Backend> backend_;
};

MpPatchMatchSummary Controller::Run() {
  const auto start = std::chrono::steady_clock::now();
  MpPatchMatchSummary summary;
  plan_ = MakeRunPlan(run_.colmap_options, run_.options, run_.cpu_look_ahead);
  if (run_.workspace_format != "COLMAP") {
    throw Error("--workspace_format " + run_.workspace_format +
                " is not supported by mp-mvs; use a COLMAP workspace (image_undistorter --output_type COLMAP)");
  }
  LogHeading("mp_patch_match_stereo: loading workspace " + run_.workspace_path);
  workspace_ = io_->Load(run_.workspace_path, run_.colmap_options.max_image_size);
  if (!run_.colmap_options.geom_consistency && run_.options.PriorMode() == PlanarPriorMode::kGeometric) {
    LogWarning("--MPMVS.planar_prior geometric needs geometric consistency; with "
               "--PatchMatchStereo.geom_consistency 0 only the photometric stage runs");
  }
  ReferenceProblems loaded =
      LoadReferenceProblems(workspace_, run_.config_path, run_.colmap_options, plan_.max_source_images);
  problems_ = std::move(loaded.runnable);
  summary.num_skipped_no_sources = loaded.num_skipped_no_sources;
  summary.num_skipped_no_depth_range = loaded.num_skipped_no_depth_range;
  summary.num_skipped_missing_files = loaded.num_skipped_missing_files;
  summary.num_references = static_cast<int>(problems_.size()) + summary.num_skipped_no_sources +
                           summary.num_skipped_no_depth_range + summary.num_skipped_missing_files;
  if (problems_.empty()) {
    LogWarning("No reference image can run (" + std::to_string(summary.num_references) +
               " listed, all skipped as warned above); nothing written");
    summary.seconds = SecondsSince(start);
    return summary;
  }
  store_ = std::make_unique<StageStore>(workspace_, io_, plan_, problems_, StateOptionsText(run_.options));
  if (!plan_.overwrite) {
    for (const ReferenceProblem& p : problems_) store_->MoveAsideDamagedFinalOutputs(p.ref);
  }

  if (AllFinalMapsExist()) {
    summary.num_already_done = static_cast<int>(problems_.size());
    LogInfo("All " + std::to_string(problems_.size()) + " depth maps exist already (" + plan_.final_type +
            "); nothing to do. Use --MPMVS.overwrite 1 to recompute.");
    summary.seconds = SecondsSince(start);
    return summary;
  }
  for (const ReferenceProblem& p : problems_) {
    done_.push_back(!plan_.overwrite && store_->AllFinalOutputsExist(p.ref));
    summary.num_already_done += done_.back();
  }
  PlanNeededStates();

  backend_ = std::make_unique<Backend>(plan_.backend);
  summary.backend = backend_->Name();
  if (plan_.backend.gpu_index >= 0 && backend_->Name().rfind("CPU", 0) == 0) {
    // COLMAP scripts pass gpu_index 0 on machines without a GPU: keep running, but say so.
    LogWarning("--PatchMatchStereo.gpu_index " + run_.colmap_options.gpu_index +
               ": no such usable CUDA device; running on the CPU instead");
  }
  CreateOutputDirectories();
  std::string stage_names;
  for (const StagePlan& st : plan_.pipeline.stages) stage_names += (stage_names.empty() ? "" : " -> ") + st.name;
  LogInfo("Backend: " + backend_->Name() + "; " + std::to_string(problems_.size()) +
          " reference images; stages: " + stage_names);

  for (size_t s = 0; s < plan_.pipeline.stages.size(); ++s) RunStage(static_cast<int>(s), &summary);
  backend_->LogCacheStats();

  summary.num_written = static_cast<int>(written_.size());
  summary.seconds = SecondsSince(start);
  return summary;
}

bool Controller::AllFinalMapsExist() const {
  if (plan_.overwrite) return false;
  for (const ReferenceProblem& p : problems_) {
    if (!store_->AllFinalOutputsExist(p.ref)) return false;
  }
  return true;
}

void Controller::PlanNeededStates() {
  const std::vector<StagePlan>& stages = plan_.pipeline.stages;
  std::map<int, size_t> index;
  for (size_t i = 0; i < problems_.size(); ++i) index.emplace(problems_[i].ref, i);
  needed_.assign(problems_.size(), std::vector<char>(stages.size(), 0));
  for (size_t i = 0; i < problems_.size(); ++i) {
    if (!done_[i]) needed_[i].assign(stages.size(), 1);
  }
  for (int s = static_cast<int>(stages.size()) - 1; s >= 0; --s) {
    const int input = stages[s].input;
    if (input < 0) continue;
    for (size_t i = 0; i < problems_.size(); ++i) {
      if (!needed_[i][s]) continue;
      needed_[i][input] = 1;
      if (!stages[s].schedule.geometric) continue;
      for (int src : problems_[i].src) {
        const auto it = index.find(src);
        if (it != index.end()) needed_[it->second][input] = 1;
      }
    }
  }
}

void Controller::CreateOutputDirectories() const {
  CreateDirectories(workspace_.IntermediateDir());
  for (const ReferenceProblem& p : problems_) {
    const std::string& name = workspace_.views[p.ref].name;
    for (const std::string& file : {workspace_.DepthMapPath(p.ref, "x"), workspace_.NormalMapPath(p.ref, "x"),
                                    store_->StatePath(p.ref, "x")}) {
      CreateDirectories(ParentPath(file));
    }
    if (plan_.write_pictures) {
      CreateDirectories(ParentPath(JoinPaths(workspace_.IntermediateDir(), "pictures/" + name)));
    }
  }
}

void Controller::RunStage(int stage_index, MpPatchMatchSummary* summary) {
  const StagePlan& stage = plan_.pipeline.stages[stage_index];
  StageSummary stage_summary;
  stage_summary.name = stage.name;
  const auto start = std::chrono::steady_clock::now();
  LogHeading("Stage " + std::to_string(stage_index + 1) + "/" + std::to_string(plan_.pipeline.stages.size()) +
             ": " + stage.name + " (" + StageKindName(stage.kind) + ", " +
             std::to_string(stage.schedule.iterations.size()) + " iterations)");
  ProgressReporter progress("stage " + stage.name, static_cast<int>(problems_.size()));
  auto prepare = [&](size_t i) {
    return PrepareStageReference(plan_, workspace_, store_.get(), stage_index, problems_[i], done_[i],
                                 needed_[i][stage_index]);
  };

  // The next reference image, when the backend had it assembled while this one ran (CUDA:
  // its uploads overlap this image's kernels). Only within a stage: the first image of the
  // next stage reads this stage's results, the last of which is still being computed. An
  // error assembling it is raised where it would have been without looking ahead.
  std::unique_ptr<StageReference> ahead;
  std::exception_ptr ahead_error;
  for (size_t i = 0; i < problems_.size(); ++i) {
    if (ahead_error) std::rethrow_exception(ahead_error);
    const std::unique_ptr<StageReference> ref = ahead ? std::move(ahead) : prepare(i);
    const ReferenceProblem& p = *ref->problem;
    const std::string& name = workspace_.views[p.ref].name;
    kernels::PatchMatchResult result;
    switch (ref->action) {
      case StageReference::Action::kFinalMapsExist:
        ++stage_summary.images_resumed;
        progress.Step(name + " (final maps exist, skipped)");
        continue;
      case StageReference::Action::kNoSources:
        LogWarning(name + ": no usable source views in stage " + stage.name + "; skipped");
        progress.Step(name + " (skipped)");
        continue;
      case StageReference::Action::kResume:
        result = store_->ReadState(p.ref, stage.name);
        ++stage_summary.images_resumed;
        break;
      case StageReference::Action::kCompute: {
        auto next = [&, i]() -> const kernels::PatchMatchProblem* {
          if (i + 1 >= problems_.size()) return nullptr;
          try {
            ahead = prepare(i + 1);
          } catch (...) {
            ahead_error = std::current_exception();
            return nullptr;
          }
          return ahead->action == StageReference::Action::kCompute ? &ahead->pm : nullptr;
        };
        backend_->Run(ref->pm, stage.schedule, &result, next);
        store_->WriteState(p.ref, stage.name, result);
        if (plan_.write_pictures) {
          WriteStagePictures(workspace_, p, ref->pm.ref_camera, stage.name, result,
                             stage.kind == StageKind::kPlanarPrior ? &ref->prior : nullptr);
        }
        AddRunStatistics(result, &stage_summary);
        break;
      }
    }
    WriteOutputs(stage_index, *ref, &result);
    progress.Step(name + (ref->action == StageReference::Action::kResume ? " (resumed from stereo/mpmvs)" : ""));
  }
  stage_summary.seconds = SecondsSince(start);
  summary->stages.push_back(stage_summary);
}

void Controller::WriteOutputs(int stage_index, const StageReference& ref, kernels::PatchMatchResult* result) {
  const StagePlan& stage = plan_.pipeline.stages[stage_index];
  const ReferenceProblem& p = *ref.problem;
  if (!ref.write_final) return;  // kept from an earlier run; computed for another reference
  if (ref.filter_here && !ref.pm.sources.empty()) {
    const size_t removed =
        kernels::FilterResultCpu(ref.pm, stage.schedule.geometric, plan_.filter_params, plan_.num_threads, result);
    LogInfo(workspace_.views[p.ref].name + ": filter removed " + std::to_string(removed) + " pixels");
  }
  if (stage_index == plan_.pipeline.photometric_output &&
      (plan_.overwrite || !store_->FinalOutputsExist(p.ref, "photometric"))) {
    WriteFinalMaps(io_, workspace_, p, ref.pm, *result, "photometric", plan_.write_consistency_graph,
                   plan_.write_pictures);
    if (plan_.final_type == "photometric") written_.insert(p.ref);
  }
  if (stage_index == plan_.pipeline.geometric_output) {
    kernels::InvalidateGeometricallyInconsistent(stage.schedule.geom_max_error, result);
    WriteFinalMaps(io_, workspace_, p, ref.pm, *result, "geometric", plan_.write_consistency_graph,
                   plan_.write_pictures);
    written_.insert(p.ref);
  }
}

}  // namespace

MpPatchMatchSummary RunMpPatchMatchStereo(const MpPatchMatchRun& run, WorkspaceIo* io) {
  if (io == nullptr) throw Error("RunMpPatchMatchStereo: no workspace I/O given");
  Controller controller(run, io);
  return controller.Run();
}

MpPatchMatchSummary RunMpPatchMatchStereo(const MpPatchMatchRun& run) {
  MpMvsWorkspaceIo io;
  return RunMpPatchMatchStereo(run, &io);
}

}  // namespace mpmvs

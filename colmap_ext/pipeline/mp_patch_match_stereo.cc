#include "colmap_ext/pipeline/mp_patch_match_stereo.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <memory>
#include <set>
#include <utility>

#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/pipeline/backend.h"
#include "colmap_ext/pipeline/depth_check.h"
#include "colmap_ext/pipeline/run_eta.h"
#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/plan/run_plan.h"
#include "colmap_ext/plan/shard.h"
#include "colmap_ext/schedule/stage_scheduler.h"
#include "colmap_ext/store/output_maps.h"
#include "colmap_ext/store/result_fingerprint.h"
#include "colmap_ext/store/stage_reference.h"
#include "colmap_ext/store/stage_store.h"
#include "colmap_ext/store/state_record.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"
#include "kernels/half_resolution.h"

namespace mpmvs {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// What one more reference image in memory costs, per pixel: a stage result and the input
// state (plane, costs, view mask: 32 bytes each) and the planar prior.
constexpr size_t kReferenceBytesPerPixel = 96;

// The process's CPU time (user + system), seconds.
double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// A reference image that runs longer than this reports its iterations at this interval.
constexpr double kImageProgressSeconds = 30;

void AddRunStatistics(const kernels::PatchMatchResult& result, StageSummary* summary) {
  ++summary->images_computed;
  summary->ncc_evaluations += result.init_ncc_evaluations;
  for (const auto& it : result.iterations) summary->ncc_evaluations += it.ncc_evaluations;
  summary->pixel_iterations += static_cast<uint64_t>(result.width) * result.height * result.iterations.size();
  if (summary->iterations.empty()) summary->iterations = result.iterations;
}

// Plan; then for each stage, each reference image the scheduler hands out: run, write, store.
// An image's outputs are written while the next image of the stage runs, if the scheduler
// had it ready (side work, pipeline/backend.h); otherwise, and at the end of a stage, before
// anything else happens.
class Controller {
 public:
  Controller(const MpPatchMatchRun& run, WorkspaceIo* io) : run_(run), io_(io) {}

  MpPatchMatchSummary Run();

 private:
  // Plans the run, loads the workspace and selects this process's reference images; false
  // when there is nothing to do (summary says why).
  bool Plan(MpPatchMatchSummary* summary);
  // Registers the run with the scheduler, starts the backend, creates the output folders.
  void Start(MpPatchMatchSummary* summary);
  // Whether the CPU may keep two more reference images in memory for its side work (the
  // previous one's outputs and the next one, pipeline/backend.h): within the cache budget.
  bool SideWorkFitsCache() const;
  // Whether every reference of this process already has its final maps (nothing to do).
  bool AllFinalMapsExist() const;
  // One line for this process's maps made with other options or inputs (recomputed).
  void ReportMapsOfOtherOptions() const;
  void CreateOutputDirectories() const;
  // Bytes in stereo/mpmvs (states, pictures, claims).
  uint64_t IntermediateBytes() const { return DirectoryBytes(workspace_.IntermediateDir()); }
  void RunStage(int stage_index, MpPatchMatchSummary* summary);
  // Runs or resumes a prepared image; a computed image's outputs are then pending.
  void RunReference(int stage_index, std::unique_ptr<StageReference> ref, StageSummary* summary,
                    ProgressReporter* progress);
  // Writes the pending image's state, pictures and maps, releases its claim.
  void FinishPending();
  // Writes a computed image's state and pictures; counts it.
  void StoreComputed(int stage_index, const StageReference& ref, const kernels::PatchMatchResult& result,
                     StageSummary* summary);
  // Writes a computed or resumed image's outputs, releases its claim, reports progress.
  void FinishReference(int stage_index, const StageReference& ref, kernels::PatchMatchResult* result,
                       ProgressReporter* progress);
  // Counts an image done on the stage's progress line, with the whole run's time left.
  void ReportDone(int stage_index, int view, const std::string& detail, bool computed, ProgressReporter* progress);
  // Output filter, geometric invalidation and the COLMAP maps of a stage that writes them.
  void WriteOutputs(int stage_index, const StageReference& ref, kernels::PatchMatchResult* result);

  MpPatchMatchRun run_;
  WorkspaceIo* io_;
  RunPlan plan_;
  DenseWorkspace workspace_;
  std::vector<ReferenceProblem> problems_;  // every runnable reference (sources of mine_)
  std::vector<size_t> mine_;                // positions in problems_ this process runs
  std::set<int> written_;                   // views whose final maps this run wrote
  std::unique_ptr<StageStore> store_;
  std::unique_ptr<WorkClaims> claims_;  // this run's registration, until the scheduler takes it
  std::unique_ptr<StageScheduler> scheduler_;
  std::unique_ptr<Backend> backend_;
  std::unique_ptr<RunEta> eta_;  // of this process's stages and images
  struct Pending {  // a computed image whose outputs are not written yet
    int stage_index = -1;
    std::unique_ptr<StageReference> ref;
    kernels::PatchMatchResult result;
    StageSummary* summary = nullptr;
    ProgressReporter* progress = nullptr;
  };
  std::unique_ptr<Pending> pending_;
  double parallel_seconds_ = 0;  // wall time in the backend's runs and the depth check
};

MpPatchMatchSummary Controller::Run() {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = CpuSeconds();
  MpPatchMatchSummary summary;
  if (Plan(&summary)) {
    Start(&summary);
    for (size_t s = 0; s < plan_.pipeline.stages.size(); ++s) {
      if (plan_.only_stage < 0 || plan_.only_stage == static_cast<int>(s)) RunStage(static_cast<int>(s), &summary);
    }
    backend_->LogCacheStats();
    summary.num_written = static_cast<int>(written_.size());
    summary.intermediate_final_bytes = IntermediateBytes();
  }
  summary.seconds = SecondsSince(start);
  summary.cpu_seconds = CpuSeconds() - cpu_start;
  summary.serial_seconds = std::max(0.0, summary.seconds - parallel_seconds_);
  return summary;
}

bool Controller::Plan(MpPatchMatchSummary* summary) {
  plan_ = MakeRunPlan(run_.colmap_options, run_.options, run_.cpu_side_work);
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
      LoadReferenceProblems(workspace_, run_.config_path, run_.colmap_options, plan_.sources_per_reference);
  problems_ = std::move(loaded.runnable);
  const int written = plan_.pipeline.geometric_output;
  if (loaded.depth_check.relative > kDepthCheckBaseTolerance && written >= 0 &&
      plan_.pipeline.stages[written].kind == StageKind::kDepthCheck) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "the sparse points' mean reprojection error is %.2f px (%.2f mrad): the depth check confirms "
                  "depths within %.2f %% instead of 1 %%",
                  loaded.depth_check.mean_error_px, 1000 * loaded.depth_check.mean_error_rad,
                  100 * loaded.depth_check.relative);
    LogInfo(text);
  }
  summary->num_skipped_no_sources = loaded.num_skipped_no_sources;
  summary->num_skipped_no_depth_range = loaded.num_skipped_no_depth_range;
  summary->num_skipped_missing_files = loaded.num_skipped_missing_files;
  summary->num_references = static_cast<int>(problems_.size()) + summary->num_skipped_no_sources +
                            summary->num_skipped_no_depth_range + summary->num_skipped_missing_files;
  summary->num_not_references = static_cast<int>(workspace_.views.size()) - summary->num_references;
  if (problems_.empty()) {
    LogWarning("No reference image can run (" + std::to_string(summary->num_references) +
               " listed, all skipped as warned above); nothing written");
    return false;
  }
  const ResultFingerprint fingerprint = MakeResultFingerprint(run_.colmap_options, run_.options, workspace_, problems_);
  store_ = std::make_unique<StageStore>(workspace_, io_, plan_, problems_, fingerprint);
  mine_ = SelectShard(workspace_, problems_, plan_.image_names, plan_.shard);
  if (plan_.Partial()) {
    std::string names;
    for (size_t i : mine_) names += " " + workspace_.views[problems_[i].ref].name;
    LogInfo("Shard " + std::to_string(plan_.shard.index) + "/" + std::to_string(plan_.shard.count) + ": " +
            std::to_string(mine_.size()) + " of " + std::to_string(problems_.size()) + " reference images:" + names);
  }
  if (mine_.empty()) {
    LogInfo("This shard has no reference images; nothing to do.");
    return false;
  }
  if (AllFinalMapsExist()) {
    summary->num_already_done = static_cast<int>(mine_.size());
    LogInfo("All " + std::to_string(mine_.size()) + " depth maps exist already (" + plan_.final_type +
            "); nothing to do. Use --MPMVS.overwrite 1 to recompute.");
    return false;
  }
  // Before this run changes any file: a live run with other options refuses it.
  claims_ = JoinWorkspace(plan_, workspace_, fingerprint.RunTag(), run_.workspace_path);
  // Only this process's images: another process may be writing the others' maps.
  if (!plan_.overwrite) {
    ReportMapsOfOtherOptions();
    for (size_t i : mine_) store_->MoveAsideDamagedFinalOutputs(problems_[i].ref);
  }
  return true;
}

void Controller::ReportMapsOfOtherOptions() const {
  int count = 0;
  std::set<std::string> reasons;
  for (size_t i : mine_) {
    bool other = false;
    for (const std::string& type : {std::string("photometric"), plan_.final_type}) {
      const std::string why = store_->CheckFinalOutputs(problems_[i].ref, type).other_options;
      if (!why.empty()) reasons.insert(why);
      other = other || !why.empty();
    }
    count += other;
  }
  if (count == 0) return;
  std::string why;
  for (const std::string& reason : reasons) why += (why.empty() ? "" : "; ") + reason;
  LogInfo(std::to_string(count) + " of " + std::to_string(mine_.size()) +
          " reference images have maps made with other options (" + why +
          "): recomputing them and the intermediate results in stereo/mpmvs they build on");
  store_->SetOptionsChangeReported();
}

void Controller::Start(MpPatchMatchSummary* summary) {
  scheduler_ = std::make_unique<StageScheduler>(plan_, workspace_, store_.get(), problems_, mine_, std::move(claims_));
  plan_.backend.cpu_side_work = plan_.backend.cpu_side_work && SideWorkFitsCache();
  summary->num_already_done += scheduler_->NumDone();
  backend_ = std::make_unique<Backend>(plan_.backend);
  summary->backend = backend_->Name();
  if (plan_.backend.gpu_index >= 0 && backend_->Name().rfind("CPU", 0) == 0) {
    // COLMAP scripts pass gpu_index 0 on machines without a GPU: keep running, but say so.
    LogWarning("--PatchMatchStereo.gpu_index " + run_.colmap_options.gpu_index +
               ": no such usable CUDA device; running on the CPU instead");
  }
  CreateOutputDirectories();
  double units = 0;
  for (size_t s = 0; s < plan_.pipeline.stages.size(); ++s) {
    if (plan_.only_stage >= 0 && plan_.only_stage != static_cast<int>(s)) continue;
    const double iterations = kernels::IterationWork(plan_.pipeline.stages[s].schedule);
    for (size_t i : mine_) {
      const DenseView& view = workspace_.views[problems_[i].ref];
      units += RunEta::Units(view.width, view.height, iterations);
    }
  }
  eta_ = std::make_unique<RunEta>(units);
  std::string stage_names;
  for (const StagePlan& st : plan_.pipeline.stages) stage_names += (stage_names.empty() ? "" : " -> ") + st.name;
  LogInfo("Backend: " + backend_->Name() + "; " + std::to_string(mine_.size()) +
          " reference images; stages: " + stage_names);
  // Which views each reference matches against, once per image (as COLMAP's log says it).
  for (size_t i : mine_) {
    const ReferenceProblem& p = problems_[i];
    std::string sources;
    for (int src : p.src) sources += " " + workspace_.views[src].name;
    LogDetail(workspace_.views[p.ref].name + ": " + std::to_string(p.src.size()) + " source image" +
              (p.src.size() == 1 ? "" : "s") + ":" + sources);
  }
}

bool Controller::SideWorkFitsCache() const {
  size_t pixels = 0;
  for (size_t i : mine_) {
    const DenseView& view = workspace_.views[problems_[i].ref];
    pixels = std::max(pixels, static_cast<size_t>(view.width) * view.height);
  }
  const size_t bytes = 2 * pixels * kReferenceBytesPerPixel;
  if (bytes <= plan_.cache_bytes) return true;
  LogInfo("The CPU writes each image's outputs before it assembles the next image: doing both while an image "
          "runs keeps two more images' maps in memory (" + std::to_string(bytes >> 20) +
          " MB), more than --PatchMatchStereo.cache_size allows");
  return false;
}

bool Controller::AllFinalMapsExist() const {
  if (plan_.overwrite) return false;
  for (size_t i : mine_) {
    if (!store_->AllFinalOutputsExist(problems_[i].ref)) return false;
  }
  return true;
}

void Controller::CreateOutputDirectories() const {
  CreateDirectories(workspace_.IntermediateDir());
  for (size_t i : mine_) {
    const ReferenceProblem& p = problems_[i];
    const std::string& name = workspace_.views[p.ref].name;
    for (const std::string& file : {workspace_.DepthMapPath(p.ref, "x"), workspace_.NormalMapPath(p.ref, "x"),
                                    store_->StatePath(p.ref, "x")}) {
      CreateDirectories(ParentPath(file));
    }
    if (plan_.final_pictures) {
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
  scheduler_->BeginStage(stage_index);
  ProgressReporter progress("stage " + stage.name, static_cast<int>(mine_.size()));
  for (;;) {
    // Next() may prepare an image or wait for other processes: never with outputs pending
    // (another process may be waiting for them).
    if (!scheduler_->NextIsReady()) FinishPending();
    std::unique_ptr<StageReference> ref = scheduler_->Next();
    if (!ref) break;
    RunReference(stage_index, std::move(ref), &stage_summary, &progress);
  }
  FinishPending();  // the next stage reads this one's results
  stage_summary.seconds = SecondsSince(start);
  summary->stages.push_back(stage_summary);
  // The most stereo/mpmvs holds is just before the states this stage made unneeded go.
  summary->intermediate_peak_bytes = std::max(summary->intermediate_peak_bytes, IntermediateBytes());
  if (!plan_.keep_states) scheduler_->RemoveUnneededStates();
}

void Controller::RunReference(int stage_index, std::unique_ptr<StageReference> ref, StageSummary* summary,
                              ProgressReporter* progress) {
  const StagePlan& stage = plan_.pipeline.stages[stage_index];
  const ReferenceProblem& p = *ref->problem;
  const std::string& name = workspace_.views[p.ref].name;
  const bool runs_on_backend = ref->action == StageReference::Action::kCompute && stage.kind != StageKind::kDepthCheck;
  if (!runs_on_backend) FinishPending();
  kernels::PatchMatchResult result;
  switch (ref->action) {
    case StageReference::Action::kFinalMapsExist:
      ++summary->images_resumed;
      ReportDone(stage_index, p.ref, " (final maps exist, skipped)", false, progress);
      scheduler_->Release(*ref);  // no-op unless its state was needed
      return;
    case StageReference::Action::kNotNeeded:
      ++summary->images_resumed;
      ReportDone(stage_index, p.ref, " (its later stages are done, skipped)", false, progress);
      scheduler_->Release(*ref);
      return;
    case StageReference::Action::kNoSources:
      LogWarning(name + ": no usable source views in stage " + stage.name + "; skipped");
      ReportDone(stage_index, p.ref, " (skipped)", false, progress);
      scheduler_->Release(*ref);
      return;
    case StageReference::Action::kResume:
      result = store_->ReadState(p.ref, stage.name);
      ++summary->images_resumed;
      break;
    case StageReference::Action::kCompute:
      if (stage.kind == StageKind::kDepthCheck) {
        result = ref->input;
        const auto check_start = std::chrono::steady_clock::now();
        const DepthCheckCounts removed = RunDepthCheck(ref->pm, stage.schedule.geom_error_clamp,
                                                       stage.confirming_views, p.depth_check_tolerance,
                                                       plan_.num_threads, &result);
        parallel_seconds_ += SecondsSince(check_start);
        const size_t pixels = std::max<size_t>(1, result.photo_cost.size());
        char tolerance[120];
        std::snprintf(tolerance, sizeof(tolerance),
                      "at %.2f %% (its sources' maps hold its depths within a median %.3f %%)",
                      100 * removed.agreement.tolerance, 100 * removed.agreement.median_difference);
        LogDetail(name + ": depth check " + tolerance + " removed " + std::to_string(removed.unconfirmed) +
                " pixels (" + std::to_string(100 * removed.unconfirmed / pixels) +
                "%) that no source view's depth confirms and " +
                std::to_string(removed.speckles) + " (" + std::to_string(100 * removed.speckles / pixels) +
                "%) in depth segments under " + std::to_string(kDepthCheckMinSegmentPixels) + " pixels");
        // The state keeps no view selection: the graph is made here, where the sources' results are.
        if (plan_.write_consistency_graph && ref->write_final) {
          MarkConfirmingViews(ref->pm, removed.agreement.tolerance, plan_.num_threads, &result);
        }
      } else {
        // A long image reports its iterations now and then.
        const auto image_start = std::chrono::steady_clock::now();
        double next_report = kImageProgressSeconds;
        const auto iteration_done = [&](int done, int total) {
          const double elapsed = SecondsSince(image_start);
          if (elapsed < next_report || done >= total) return;
          next_report = elapsed + kImageProgressSeconds;
          LogProgress(name + ": stage " + stage.name + ", iteration " + std::to_string(done) + "/" +
                      std::to_string(total) + ", elapsed " + FormatDuration(elapsed) + ", ETA " +
                      FormatDuration(elapsed / done * (total - done)));
        };
        const auto run_start = std::chrono::steady_clock::now();
        std::exception_ptr side_error;  // raised here, not inside the backend's run
        backend_->Run(ref->pm, stage.schedule, &result, [this, &side_error]() -> const kernels::PatchMatchProblem* {
          try {
            FinishPending();
          } catch (...) {
            side_error = std::current_exception();
            return nullptr;
          }
          return scheduler_->LookAhead();
        }, iteration_done);
        parallel_seconds_ += SecondsSince(run_start);
        if (side_error) std::rethrow_exception(side_error);
        FinishPending();  // a backend that did not call back
        ref->input = kernels::PatchMatchResult();  // the run's initial state: not needed after it
        ref->pm.init_plane = nullptr;
        ref->pm.init_cost = nullptr;
        pending_ = std::make_unique<Pending>();
        pending_->stage_index = stage_index;
        pending_->ref = std::move(ref);
        pending_->result = std::move(result);
        pending_->summary = summary;
        pending_->progress = progress;
        return;
      }
      StoreComputed(stage_index, *ref, result, summary);
      break;
  }
  FinishReference(stage_index, *ref, &result, progress);
}

void Controller::StoreComputed(int stage_index, const StageReference& ref, const kernels::PatchMatchResult& result,
                               StageSummary* summary) {
  const StagePlan& stage = plan_.pipeline.stages[stage_index];
  store_->WriteState(ref.problem->ref, stage.name, result);
  if (plan_.stage_pictures) {
    WriteStagePictures(workspace_, *ref.problem, ref.pm.ref_camera, stage.name, result,
                       stage.kind == StageKind::kPlanarPrior ? &ref.prior : nullptr);
  }
  AddRunStatistics(result, summary);
}

void Controller::FinishPending() {
  if (!pending_) return;
  const std::unique_ptr<Pending> pending = std::move(pending_);
  StoreComputed(pending->stage_index, *pending->ref, pending->result, pending->summary);
  FinishReference(pending->stage_index, *pending->ref, &pending->result, pending->progress);
}

void Controller::FinishReference(int stage_index, const StageReference& ref, kernels::PatchMatchResult* result,
                                 ProgressReporter* progress) {
  WriteOutputs(stage_index, ref, result);
  scheduler_->Release(ref);
  const bool resumed = ref.action == StageReference::Action::kResume;
  ReportDone(stage_index, ref.problem->ref, resumed ? " (resumed from stereo/mpmvs)" : "", !resumed, progress);
}

void Controller::ReportDone(int stage_index, int view, const std::string& detail, bool computed,
                            ProgressReporter* progress) {
  const DenseView& v = workspace_.views[view];
  eta_->Done(RunEta::Units(v.width, v.height, kernels::IterationWork(plan_.pipeline.stages[stage_index].schedule)),
             computed);
  const double left = eta_->SecondsLeft();
  progress->Step(v.name + detail, left < 0 ? "" : ", run ETA " + FormatDuration(left));
}

void Controller::WriteOutputs(int stage_index, const StageReference& ref, kernels::PatchMatchResult* result) {
  const StagePlan& stage = plan_.pipeline.stages[stage_index];
  const ReferenceProblem& p = *ref.problem;
  if (!ref.write_final) return;  // kept from an earlier run; computed for another reference
  if (ref.filter_here && !ref.pm.sources.empty()) {
    const size_t removed =
        kernels::FilterResultCpu(ref.pm, stage.schedule.geometric, plan_.filter_params, plan_.num_threads, result);
    LogDetail(workspace_.views[p.ref].name + ": filter removed " + std::to_string(removed) + " pixels");
  }
  if (stage_index == plan_.pipeline.photometric_output &&
      (plan_.overwrite || !store_->FinalOutputsExist(p.ref, "photometric"))) {
    WriteFinalMaps(io_, *store_, workspace_, p, ref.pm, *result, "photometric", plan_.write_consistency_graph,
                   plan_.stage_pictures || (plan_.final_pictures && plan_.final_type == "photometric"));
    // Counted once the reference has its final maps (they may be older than this run).
    if (plan_.final_type == "photometric" || store_->FinalOutputsExist(p.ref, plan_.final_type)) {
      written_.insert(p.ref);
    }
  }
  if (stage_index == plan_.pipeline.geometric_output) {
    kernels::InvalidateGeometricallyInconsistent(stage.schedule.geom_error_clamp, result);
    WriteFinalMaps(io_, *store_, workspace_, p, ref.pm, *result, "geometric", plan_.write_consistency_graph,
                   plan_.final_pictures);
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

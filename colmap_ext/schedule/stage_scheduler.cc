#include "colmap_ext/schedule/stage_scheduler.h"

#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <utility>

#include "colmap_ext/schedule/stage_results.h"
#include "colmap_ext/store/state_record.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

std::atomic<int> g_wait_signal{0};
extern "C" void OnWaitSignal(int signal) { g_wait_signal = signal; }

// While a process waits for other processes, SIGINT and SIGTERM end the wait with an Error:
// the stack unwinds and the claims it holds (its run registration too) are released, where
// the default action would leave them behind. Outside the waits signals act as usual.
class InterruptibleWait {
 public:
  InterruptibleWait() {
    g_wait_signal = 0;
    struct sigaction action = {};
    action.sa_handler = OnWaitSignal;
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGINT, &action, &old_int_);
    ::sigaction(SIGTERM, &action, &old_term_);
  }
  // A signal that came after the last check acts as it would have without the wait.
  ~InterruptibleWait() {
    ::sigaction(SIGINT, &old_int_, nullptr);
    ::sigaction(SIGTERM, &old_term_, nullptr);
    if (const int signal = g_wait_signal.exchange(0)) ::raise(signal);
  }
  InterruptibleWait(const InterruptibleWait&) = delete;
  InterruptibleWait& operator=(const InterruptibleWait&) = delete;

  void ThrowIfInterrupted(const std::string& what) const {
    const int signal = g_wait_signal.exchange(0);
    if (signal != 0) {
      throw Error("interrupted (" + std::string(signal == SIGINT ? "SIGINT" : "SIGTERM") + ") while " + what +
                  "; this process's claims are released");
    }
  }

 private:
  struct sigaction old_int_ = {}, old_term_ = {};
};

// How long a run that needs results of other processes waits while no other run with its
// options is registered: long enough for runs started together to register.
constexpr int kAloneSeconds = 60;
// How often a waiting stage looks again at what it still needs (stage_results.h).
constexpr int kRejudgeSeconds = 5;

}  // namespace

std::unique_ptr<WorkClaims> JoinWorkspace(const RunPlan& plan, const DenseWorkspace& workspace,
                                          const std::string& run_tag, const std::string& workspace_path) {
  auto claims = std::make_unique<WorkClaims>(JoinPaths(workspace.IntermediateDir(), "claims"),
                                             plan.claim_lease_seconds);
  const std::vector<ClaimHolder> others = claims->RegisterRun(run_tag);
  if (!others.empty()) {
    throw Error("another mp_patch_match_stereo run with other options (" + others.front().Describe() +
                ") is working on " + workspace_path +
                "; the two would mix their results. Options that change results (--PatchMatchStereo.* such as "
                "max_image_size, filter, depth_min/depth_max; --MPMVS.* such as seed) and the patch-match.cfg "
                "(--config_path) must be the same. Wait for it to finish, or run on a copy of the workspace.");
  }
  return claims;
}

StageScheduler::StageScheduler(const RunPlan& plan, const DenseWorkspace& workspace, StageStore* store,
                               const std::vector<ReferenceProblem>& problems, const std::vector<size_t>& mine,
                               std::unique_ptr<WorkClaims> claims)
    : plan_(plan),
      workspace_(workspace),
      store_(store),
      problems_(problems),
      mine_(mine),
      claims_(std::move(claims)),
      inputs_(plan, problems) {
  // Over every runnable image: which results this process's images need from the others.
  for (size_t i = 0; i < problems_.size(); ++i) done_.push_back(FinalMapsDone(i));
  needed_ = NeededStageResults(plan_, problems_, inputs_, store_);
}

bool StageScheduler::FinalMapsDone(size_t i) const {
  return !plan_.overwrite && store_->AllFinalOutputsExist(problems_[i].ref);
}

int StageScheduler::NumDone() const {
  int n = 0;
  for (size_t i : mine_) n += done_[i];
  return n;
}

void StageScheduler::BeginStage(int stage_index) {
  stage_ = stage_index;
  next_ = 0;
  look_ahead_ = false;
  deferred_.clear();
  next_deferred_ = 0;
  ahead_.reset();
  ahead_error_ = nullptr;
  AwaitInputs();
}

std::unique_ptr<StageReference> StageScheduler::Next() {
  look_ahead_ = false;
  while (next_ < mine_.size()) {
    if (ahead_error_) std::rethrow_exception(ahead_error_);
    const size_t k = next_++;
    if (!ahead_ && std::find(deferred_.begin(), deferred_.end(), k) != deferred_.end()) continue;
    std::unique_ptr<StageReference> ref = ahead_ ? std::move(ahead_) : ClaimAndPrepare(k, false);
    if (!ref) {
      deferred_.push_back(k);
      continue;
    }
    running_ = k;
    look_ahead_ = true;
    return ref;
  }
  if (ahead_error_) std::rethrow_exception(ahead_error_);
  if (next_deferred_ < deferred_.size()) return ClaimAndPrepare(deferred_[next_deferred_++], true);
  return nullptr;
}

const kernels::PatchMatchProblem* StageScheduler::LookAhead() {
  if (!look_ahead_ || running_ + 1 >= mine_.size()) return nullptr;
  try {
    ahead_ = ClaimAndPrepare(running_ + 1, false);
  } catch (...) {
    ahead_error_ = std::current_exception();
    return nullptr;
  }
  if (!ahead_) deferred_.push_back(running_ + 1);
  return ahead_ && ahead_->action == StageReference::Action::kCompute ? &ahead_->pm : nullptr;
}

void StageScheduler::Release(const StageReference& ref) { claims_->Release(ClaimKey(ref.problem->ref, stage_)); }

int StageScheduler::RemoveUnneededStates() {
  const std::vector<std::vector<char>> needed = NeededStageResults(plan_, problems_, inputs_, store_);
  int removed = 0;
  for (size_t i = 0; i < problems_.size(); ++i) {
    for (size_t s = 0; s < plan_.pipeline.stages.size(); ++s) {
      const int view = problems_[i].ref;
      const std::string& name = plan_.pipeline.stages[s].name;
      // Only files that are there take a claim; whether they are usable does not matter.
      if (needed[i][s] || !store_->StateFilesExist(view, name)) continue;
      // A process that claimed this result after judging it needed may be reading it: its
      // claim keeps the state (it goes at a later removal).
      const std::string key = ClaimKey(view, static_cast<int>(s));
      const bool ours = claims_->Holds(key);
      if (!ours && claims_->TryClaim(key) == WorkClaims::Result::kHeld) continue;
      removed += store_->RemoveState(view, name);
      if (!ours) claims_->Release(key);
    }
  }
  return removed;
}

std::string StageScheduler::ClaimKey(int view, int stage) const {
  return workspace_.views[view].name + "." + plan_.pipeline.stages[stage].name;
}

void StageScheduler::AwaitInputs() {
  const auto start = std::chrono::steady_clock::now();
  auto last_company = start;  // when another run with this run's options was last seen
  const double alone_limit = std::min(kAloneSeconds, plan_.claim_lease_seconds);
  std::unique_ptr<InterruptibleWait> interruptible;  // while waiting
  double next_report = 0;
  auto last_judged = start;
  for (;;) {
    // Another process may have finished what this one waits to compute, and removed the
    // inputs that are no longer needed: judge again from the disk now and then.
    if (std::chrono::steady_clock::now() - last_judged > std::chrono::seconds(kRejudgeSeconds)) {
      needed_ = NeededStageResults(plan_, problems_, inputs_, store_);
      last_judged = std::chrono::steady_clock::now();
    }
    std::vector<std::string> missing;
    for (size_t i : mine_) {
      const ReferenceProblem& p = problems_[i];
      if (!needed_[i][stage_]) continue;
      // A result there is resumed without its inputs (which may be gone: stage_results.h),
      // unless its maps are still to be written from them.
      const std::string map_type = StageMapType(plan_.pipeline, stage_);
      const bool maps_from_inputs = WritesMapsFromInputs(plan_, stage_) && !done_[i] &&
                                    !store_->FinalOutputsExist(p.ref, map_type);
      if (!plan_.overwrite && store_->HasState(p.ref, plan_.pipeline.stages[stage_].name) && !maps_from_inputs) {
        continue;
      }
      for (const StageInputs::Input& in : inputs_.Inputs(stage_, p)) {
        const bool ours = std::any_of(mine_.begin(), mine_.end(), [&](size_t j) { return problems_[j].ref == in.view; });
        // In a whole run our own missing results stay missing (the source is left out, as
        // before). Another process computes every input a needed stage reads (needed_),
        // also of an image whose final maps exist.
        if (plan_.only_stage < 0 && ours) continue;
        // With allow_missing_files a source without its result is left out (a warning
        // where the image is prepared), as in a whole run; the image's own result is needed.
        if (plan_.only_stage >= 0 && plan_.allow_missing_files && in.view != p.ref) continue;
        const std::string& name = plan_.pipeline.stages[in.stage].name;
        if (!store_->HasState(in.view, name)) missing.push_back(store_->StatePath(in.view, name));
      }
    }
    std::sort(missing.begin(), missing.end());
    missing.erase(std::unique(missing.begin(), missing.end()), missing.end());
    if (missing.empty()) return;
    std::string list;
    for (size_t i = 0; i < missing.size() && i < 10; ++i) list += "\n  " + missing[i];
    if (missing.size() > 10) list += "\n  ... and " + std::to_string(missing.size() - 10) + " more";
    const std::string& stage = plan_.pipeline.stages[stage_].name;
    if (plan_.only_stage >= 0) {
      throw Error("--MPMVS.stage " + stage + " needs the results of the previous stage for all images and "
                  "their sources; " + std::to_string(missing.size()) + " are missing (run that stage first, or "
                  "leave sources without them out with --PatchMatchStereo.allow_missing_files 1):" + list);
    }
    const auto now = std::chrono::steady_clock::now();
    if (claims_->AnotherRunShares()) last_company = now;
    if (std::chrono::duration<double>(now - last_company).count() > alone_limit) {
      throw Error("Stage " + stage + " needs " + std::to_string(missing.size()) +
                  " results of images this run does not compute (--MPMVS.image_list_path / --MPMVS.shard), and "
                  "no other mp_patch_match_stereo run with the same options is working on this workspace:" + list +
                  "\nCompute them first (a run without --MPMVS.image_list_path and --MPMVS.shard, or runs for the "
                  "other images), or start the runs of all images within " + FormatNumber(alone_limit) +
                  " s of each other (colmap-mp slurm_submit does this on a cluster).");
    }
    const double elapsed = std::chrono::duration<double>(now - start).count();
    if (elapsed >= next_report) {
      LogInfo("Stage " + stage + ": waiting for " + std::to_string(missing.size()) +
              " results that other processes compute:" + list);
      next_report += 60;
    }
    if (!interruptible) interruptible = std::make_unique<InterruptibleWait>();
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    interruptible->ThrowIfInterrupted("waiting for the results of stage " + stage);
  }
}

std::unique_ptr<StageReference> StageScheduler::ClaimAndPrepare(size_t k, bool wait) {
  const size_t i = mine_[k];
  const ReferenceProblem& p = problems_[i];
  const std::string& stage = plan_.pipeline.stages[stage_].name;
  // Finished images whose results nobody needs take no claim: nothing of theirs is written.
  if (needed_[i][stage_]) {
    const std::string& name = workspace_.views[p.ref].name;
    ClaimHolder holder;
    bool told = false;
    std::unique_ptr<InterruptibleWait> interruptible;
    while (claims_->TryClaim(ClaimKey(p.ref, stage_), &holder) == WorkClaims::Result::kHeld) {
      if (!wait) {
        LogInfo(name + ": stage " + stage + " is being run by " + holder.Describe() + "; doing other images first");
        return nullptr;
      }
      if (!told) LogInfo(name + ": waiting for " + holder.Describe() + " to finish stage " + stage);
      told = true;
      if (!interruptible) interruptible = std::make_unique<InterruptibleWait>();
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      interruptible->ThrowIfInterrupted("waiting for " + holder.Describe() + " to finish stage " + stage + " of " + name);
    }
    // What was judged before may be out of date: another process of the run may have
    // finished this image meanwhile (its final maps are then whole) and removed the states
    // that no stage reads any more. Judged again now that the claim keeps them.
    done_[i] = FinalMapsDone(i);
    needed_[i][stage_] = StageResultNeeded(plan_, problems_, inputs_, store_, stage_, i);
  }
  return PrepareStageReference(plan_, workspace_, store_, stage_, p, done_[i], needed_[i][stage_]);
}

}  // namespace mpmvs

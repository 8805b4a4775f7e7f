#pragma once
// Which of this process's reference images runs next in a stage, and when: the coordination
// of the processes that share a workspace (Slurm array tasks, --MPMVS.shard, concurrent
// runs; work_claims.h), so that the controller only runs what it is handed.
//   - A stage starts once the results it reads exist (stage_inputs.h): those other processes
//     compute are waited for; in a --MPMVS.stage run a missing one is an Error.
//   - Each image is claimed (when its result is needed) before it is prepared
//     (store/stage_reference.h), and released when its results are written. An image
//     another live process holds is deferred ("doing other images first"); once the others
//     are done, the deferred ones are waited for in turn.
//   - What was judged at the start (final maps whole, results still needed) can be out of
//     date where other processes share the run: one may have finished an image and removed
//     the states no stage reads any more. An image is judged again from the disk when it is
//     claimed, and a state is removed under its claim, never while another process holds it.
//   - Look-ahead: while an image runs, the backend may ask for the next one (LookAhead),
//     which is claimed and prepared then and handed out next; an error preparing it is
//     raised by that Next(), where it would have been without looking ahead. Only within a
//     stage: the first image of the next stage reads this stage's results.
#include <cstddef>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/plan/run_plan.h"
#include "colmap_ext/schedule/stage_inputs.h"
#include "colmap_ext/schedule/work_claims.h"
#include "colmap_ext/store/stage_reference.h"
#include "colmap_ext/store/stage_store.h"
#include "kernels/patch_match.h"

namespace mpmvs {

// Registers this process as a run on the workspace under run_tag (ResultFingerprint::RunTag)
// and returns its claims; throws Error naming workspace_path when another live run with
// another tag works on it. Call it before the run changes any file of the workspace.
std::unique_ptr<WorkClaims> JoinWorkspace(const RunPlan& plan, const DenseWorkspace& workspace,
                                          const std::string& run_tag, const std::string& workspace_path);

class StageScheduler {
 public:
  // plan, workspace, store and problems (every runnable reference) must outlive the
  // scheduler; mine: the positions in problems this process runs, in order; claims: from
  // JoinWorkspace.
  StageScheduler(const RunPlan& plan, const DenseWorkspace& workspace, StageStore* store,
                 const std::vector<ReferenceProblem>& problems, const std::vector<size_t>& mine,
                 std::unique_ptr<WorkClaims> claims);

  // Of this process's images, how many had their final maps whole at the start (kept).
  int NumDone() const;

  // Starts stage stage_index: returns once the results it reads exist.
  void BeginStage(int stage_index);
  // The next image of the stage, claimed and prepared; nullptr when the stage is done.
  // Blocks while the only images left are held by other live processes. Throws what
  // preparing an image throws.
  std::unique_ptr<StageReference> Next();
  // Whether Next() returns an image LookAhead() prepared, without preparing or waiting.
  bool NextIsReady() const { return ahead_ != nullptr; }
  // For the backend while the image Next() returned runs: claims and prepares the image
  // after it and returns its problem when it is to be computed; nullptr otherwise (none,
  // held by another process, or not computed).
  const kernels::PatchMatchProblem* LookAhead();
  // Releases the claim on ref's image in this stage (a no-op when none was taken).
  void Release(const StageReference& ref);
  // Removes the states of every image of the run that no stage reads again (stage_results.h),
  // except those another process holds the claim of (it may be reading them); returns how many.
  int RemoveUnneededStates();

 private:
  // Waits for (or, in a --MPMVS.stage run, throws naming) the missing results the stage reads.
  void AwaitInputs();
  // Claims and prepares this process's k-th image; nullptr when another live process holds
  // it and wait is false.
  std::unique_ptr<StageReference> ClaimAndPrepare(size_t k, bool wait);
  // Whether image i's final maps are whole on the disk (and not to be recomputed).
  bool FinalMapsDone(size_t i) const;
  std::string ClaimKey(int view, int stage) const;

  const RunPlan& plan_;
  const DenseWorkspace& workspace_;
  StageStore* store_;
  const std::vector<ReferenceProblem>& problems_;
  std::vector<size_t> mine_;
  std::unique_ptr<WorkClaims> claims_;
  StageInputs inputs_;
  // [problem] final maps whole (kept): at the start, and again when the image is claimed.
  std::vector<char> done_;
  // [problem][stage], at the start, again while a stage waits for other processes (which
  // may meanwhile have finished this run's images and removed the states they read), and
  // for the image and stage when it is claimed.
  std::vector<std::vector<char>> needed_;  // (stage_results.h)

  // The stage under way.
  int stage_ = -1;
  size_t next_ = 0;                   // next position in mine_ to hand out
  size_t running_ = 0;                // position of the image handed out last (look-ahead)
  bool look_ahead_ = false;           // whether that image may look ahead
  std::vector<size_t> deferred_;      // positions held by other processes, in order
  size_t next_deferred_ = 0;          // next of deferred_ to wait for
  std::unique_ptr<StageReference> ahead_;  // prepared by LookAhead, handed out next
  std::exception_ptr ahead_error_;         // raised by the next Next()
};

}  // namespace mpmvs

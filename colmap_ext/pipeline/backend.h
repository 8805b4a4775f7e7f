#pragma once
// Runs a reference image's PatchMatch on the CPU or in one CUDA session kept for the whole
// run (device cache of images and depth maps, uploads of the next reference image while
// the current one runs: kernels/cuda_session.h), and returns the finished stage result.
#include <cstddef>
#include <memory>
#include <string>

#include "colmap_ext/plan/backend_options.h"
#include "kernels/cuda_session.h"
#include "kernels/patch_match.h"

namespace mpmvs {

class Backend {
 public:
  explicit Backend(const BackendOptions& options);
  ~Backend();

  // next: the controller's side work while this problem runs (writing the previous image's
  // outputs, assembling the next image, which it returns). The CUDA session calls it on this
  // thread while its kernels run; the CPU backend runs it on a thread of its own beside its
  // passes (cpu_side_work), so that no core waits for serial work; without cpu_side_work it
  // is not called (the controller then does it between images). An exception it throws is
  // raised after the run. The result is finished alike on both backends: the depths are
  // median-filtered, as the reference pipeline does after every run (docs/algorithm.md
  // §9.1); later stages, the planar prior and the outputs all see the filtered result.
  // progress: after each iteration, (done, total), on the thread that runs the passes.
  // A schedule that starts at half resolution (--MPMVS.half_resolution_scales) runs as two
  // runs on the same backend (kernels/half_resolution.h); next goes with the second.
  void Run(const kernels::PatchMatchProblem& problem, const kernels::PatchMatchSchedule& schedule,
           kernels::PatchMatchResult* result, const kernels::NextProblemCallback& next,
           const kernels::ProgressCallback& progress = nullptr);

  const std::string& Name() const { return name_; }
  void LogCacheStats() const;

 private:
  // One backend run; next: as Run's (nullptr: none).
  void RunOnce(const kernels::PatchMatchProblem& problem, const kernels::PatchMatchSchedule& schedule,
               kernels::PatchMatchResult* result, const kernels::NextProblemCallback& next,
               const kernels::ProgressCallback& progress, bool median_filter);

  BackendOptions options_;
  std::unique_ptr<kernels::CudaSession> cuda_;
  std::string name_;
};

}  // namespace mpmvs

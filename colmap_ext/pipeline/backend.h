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

  // next: the following reference image of the stage, assembled on demand. The CUDA session
  // calls it while this problem's kernels run; the CPU backend does not call it (the
  // controller then assembles that image after this one, as always), unless cpu_look_ahead.
  // The result is finished alike on both backends: the depths are median-filtered, as the
  // reference pipeline does after every run (docs/algorithm.md §9.1); later stages, the
  // planar prior and the outputs all see the filtered result.
  // progress: after each iteration, (done, total).
  void Run(const kernels::PatchMatchProblem& problem, const kernels::PatchMatchSchedule& schedule,
           kernels::PatchMatchResult* result, const kernels::NextProblemCallback& next,
           const kernels::ProgressCallback& progress = nullptr);

  const std::string& Name() const { return name_; }
  void LogCacheStats() const;

 private:
  BackendOptions options_;
  std::unique_ptr<kernels::CudaSession> cuda_;
  std::string name_;
};

}  // namespace mpmvs

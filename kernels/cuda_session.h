#pragma once
// A CUDA session: the GPU side of a run over many reference images. It keeps, across
// problems, a compute stream and a copy stream, the per-pixel state buffers (grown when a
// larger image comes) and a device cache of grey images and source depth maps under a byte
// budget (DeviceCachePlanner, device_cache_plan.h). While the kernels of one reference
// image run, the caller assembles the next problem (NextProblemCallback) and the session
// queues its missing uploads on the copy stream; the next run's kernels wait for them with
// an event. No CUDA types here: the host side compiles without the CUDA headers, and builds
// without CUDA get a constructor that throws (cuda_stubs.cc).
#include <cstddef>
#include <functional>
#include <memory>

#include "kernels/device_cache_plan.h"
#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {

struct CudaSessionOptions {
  int gpu_index = 0;
  // The host's cache size (COLMAP's --PatchMatchStereo.cache_size, in bytes); the device
  // cache budget is DeviceCacheBudget(cache_size_bytes, free device memory at start).
  size_t cache_size_bytes = static_cast<size_t>(32) << 30;

  // Throws std::invalid_argument with a message when inconsistent.
  void Check() const;
};

// Returns the next problem to upload ahead (the next reference image of the same stage:
// the session uses the current schedule for it) or nullptr. The problem and its host data
// must stay unchanged and alive until it has been passed to CudaSession::Run.
using NextProblemCallback = std::function<const PatchMatchProblem*()>;

class CudaSession {
 public:
  // Throws std::runtime_error when the device cannot be used.
  explicit CudaSession(const CudaSessionOptions& options);
  ~CudaSession();
  CudaSession(const CudaSession&) = delete;
  CudaSession& operator=(const CudaSession&) = delete;

  // Same contract as RunPatchMatchCpu. With `next`, calls it once while this problem's
  // kernels run and uploads the returned problem's missing inputs on the copy stream; the
  // next Run with that problem finds them there (another problem: the upload is dropped).
  void Run(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
           PatchMatchResult* result, const NextProblemCallback& next = nullptr,
           const ProgressCallback& progress = nullptr);

  DeviceCacheStats CacheStats() const;
  size_t CacheBudgetBytes() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace kernels
}  // namespace mpmvs

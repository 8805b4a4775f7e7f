#include "colmap_ext/pipeline/backend.h"

#include <algorithm>
#include <thread>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/thread_range.h"
#include "kernels/half_resolution.h"

namespace mpmvs {

Backend::Backend(const BackendOptions& options) : options_(options) {
  std::string why;
  const int device = options.gpu_index < 0 ? 0 : options.gpu_index;
  const std::string gpu = std::string(kernels::GpuRuntimeName()) + " device";  // "CUDA device"
  if (kernels::CudaDeviceAvailable(device, &why)) {
    kernels::CudaSessionOptions session;
    session.gpu_index = device;
    session.cache_size_bytes = options.cache_bytes;
    cuda_ = std::make_unique<kernels::CudaSession>(session);
    name_ = gpu + " " + std::to_string(device);
    LogInfo(name_ + " cache budget: " + std::to_string(cuda_->CacheBudgetBytes() >> 20) +
            " MB (--PatchMatchStereo.cache_size, at most half the free device memory)");
  } else {
    const int threads = options.num_threads > 0
                            ? options.num_threads
                            : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    name_ = "CPU (" + std::to_string(threads) + " threads)";
    // No GPU is the usual case, not a fault: one calm line. A device that is there but cannot
    // run the kernels is worth a warning with the reason.
    const std::string cpu = "running on the CPU with " + std::to_string(threads) + " threads";
#ifdef MPMVS_WITH_CUDA
    if (kernels::CudaDeviceCount() == 0) {
      LogInfo("No " + gpu + "; " + cpu);
    } else {
      LogWarning(gpu + " " + std::to_string(device) + " cannot be used (" + why + "); " + cpu);
    }
#else
    LogInfo("This build has no CUDA backend; " + cpu);
#endif
  }
}

Backend::~Backend() = default;

void Backend::Run(const kernels::PatchMatchProblem& problem, const kernels::PatchMatchSchedule& schedule,
                  kernels::PatchMatchResult* result, const kernels::NextProblemCallback& next,
                  const kernels::ProgressCallback& progress) {
  try {
    if (!kernels::HasHalfResolutionIterations(schedule)) {
      RunOnce(problem, schedule, result, next, progress, true);
      return;
    }
    // The half-resolution run is not median-filtered: mPM filters nothing between scales.
    kernels::RunWithHalfResolutionStart(
        problem, schedule,
        [&](const kernels::PatchMatchProblem& p, const kernels::PatchMatchSchedule& s, kernels::PatchMatchResult* r,
            const kernels::ProgressCallback& pr, bool last) { RunOnce(p, s, r, last ? next : nullptr, pr, last); },
        result, progress);
  } catch (const kernels::ThreadStartError& e) {
    throw Error(std::string(e.what()) + "; lower --PatchMatchStereo.num_threads");
  }
}

void Backend::RunOnce(const kernels::PatchMatchProblem& problem, const kernels::PatchMatchSchedule& schedule,
                      kernels::PatchMatchResult* result, const kernels::NextProblemCallback& next,
                      const kernels::ProgressCallback& progress, bool median_filter) {
  const auto compute = [&] {
    if (cuda_) {
      cuda_->Run(problem, schedule, result, next, progress);
    } else {
      kernels::RunPatchMatchCpu(problem, schedule, result, progress);
    }
    if (median_filter) {
      kernels::MedianFilterDepthsCpu(problem.ref_camera, problem.depth_min, problem.depth_max, options_.num_threads,
                                     result);
    }
  };
  if (!cuda_ && options_.cpu_side_work && next) {
    // Without a thread to spare the side work runs first, as without overlap.
    RunBeside([&] { next(); }, compute);
  } else {
    compute();
  }
}

void Backend::LogCacheStats() const {
  if (!cuda_) return;
  const kernels::DeviceCacheStats s = cuda_->CacheStats();
  LogInfo(name_ + " cache: " + std::to_string(s.misses) + " images/depth maps uploaded, " +
          std::to_string(s.hits) + " found on the device, " + std::to_string(s.evictions) +
          " evicted, peak " + std::to_string(s.peak_bytes >> 20) + " MB of " +
          std::to_string(cuda_->CacheBudgetBytes() >> 20) + " MB; " +
          std::to_string(s.uploaded_bytes >> 20) + " MB uploaded in all");
  if (s.over_budget_problems > 0) {
    LogWarning(std::to_string(s.over_budget_problems) +
               " reference images needed more device memory for their images and depth maps "
               "than the cache budget and ran over it; raise --PatchMatchStereo.cache_size");
  }
}

}  // namespace mpmvs

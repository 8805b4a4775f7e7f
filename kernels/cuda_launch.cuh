#pragma once
// The PatchMatch kernel launches (cuda_backend.cu), queued by the CUDA session
// (cuda_session.cu), which owns the memory they read and write.
#include "kernels/gpu_runtime.h"

#include <functional>

#include "kernels/cuda_passes.h"

namespace mpmvs {
namespace kernels {

// Device memory of one run.
struct DevicePassBuffers {
  PixelState state;
  const float* init_plane = nullptr;  // optional
  const float* init_cost = nullptr;   // optional
  unsigned long long* counters = nullptr;  // NumNccCounters(iterations), zeroed here
};

// Queues on `stream` the passes of `schedule` (LaunchPasses of cuda_passes.h: the
// initialisation pass, then a black and a red checkerboard pass per iteration);
// events[it] .. events[it + 1] bracket iteration it, so `events` holds iterations + 1 events. `params` points at device memory. before_first_wait
// (optional) is called once with kernels queued, before the host first waits for the
// device: after iteration 0 with a progress callback (which waits per iteration), otherwise
// after the last iteration. Returns without waiting for the last iteration.
void EnqueuePatchMatchPasses(const PatchMatchSchedule& schedule, const PassParams& params,
                             const DevicePassBuffers& buffers, cudaStream_t stream,
                             const cudaEvent_t* events,
                             const std::function<void()>& before_first_wait,
                             const ProgressCallback& progress);

}  // namespace kernels
}  // namespace mpmvs

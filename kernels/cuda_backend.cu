// CUDA backend: the same per-pixel functions as the CPU backend (patch_match_pixel.h with
// ScalarNcc), launched one thread per pixel. The host side here only queues the passes of
// cuda_passes.h (the shared pass loop, thread bodies and launch layouts); memory, uploads
// and streams are the CUDA session's (cuda_session.cu).
// See DESIGN_CUDA.md.
#include "kernels/gpu_runtime.h"

#include <stdexcept>
#include <string>
#include <type_traits>

#include "kernels/cuda_launch.cuh"
#include "kernels/cuda_passes.h"
#include "kernels/cuda_util.cuh"

namespace mpmvs {
namespace kernels {
namespace {

// Kernel parameters live in a 4 KB constant bank (the limit of pre-Volta devices and of
// older toolkits); PassParams carries the ~800-byte propagation pattern.
constexpr size_t kKernelParamBytes =
    sizeof(PassParams) + sizeof(PixelState) + 2 * sizeof(const float*) + sizeof(void*);
static_assert(kKernelParamBytes <= 4096, "PatchMatch kernel parameters exceed 4 KB");
// Kernel arguments and the SourceView upload are byte copies.
static_assert(std::is_trivially_copyable<PassParams>::value, "PassParams is copied bytewise");
static_assert(std::is_trivially_copyable<SourceView>::value, "SourceView is copied bytewise");

// The warp reduction of the NCC counter needs whole warps.
static_assert((kBlockSideX * kBlockSideY) % 32 == 0, "blocks must be whole warps");

// ---------------------------------------------------------------------------------------
// Device side: thin launchers around the shared per-pixel functions.

// blockIdx, blockDim, threadIdx (uint3 or dim3 in CUDA, HIP's own coordinate types).
template <typename Coordinates>
__device__ __forceinline__ Dim2 ToDim2(const Coordinates& d) {
  return Dim2{static_cast<int>(d.x), static_cast<int>(d.y)};
}

// Adds every thread's count to *counter: a warp sum, then one atomic per warp. HIP-CPU has no
// warps: its shuffles share one 64-lane scratchpad among all of a block's threads, so there
// each thread adds its own count.
__device__ __forceinline__ void AccumulateCount(uint32_t count, unsigned long long* counter) {
#if defined(MPMVS_HIP_CPU)
  if (count > 0) atomicAdd(counter, static_cast<unsigned long long>(count));
#else
  for (int offset = 16; offset > 0; offset >>= 1)
    count += ShuffleDown(count, offset);
  const unsigned lane = (threadIdx.y * blockDim.x + threadIdx.x) & 31u;
  if (lane == 0 && count > 0) atomicAdd(counter, static_cast<unsigned long long>(count));
#endif
}

__global__ void InitializeKernel(const PassParams params, const PixelState state,
                                 const float* init_plane, const float* init_cost,
                                 unsigned long long* ncc_counter) {
  uint32_t count = 0;
  InitializeThread(params, state, init_plane, init_cost, ToDim2(blockIdx), ToDim2(blockDim),
                   ToDim2(threadIdx), &count);
  AccumulateCount(count, ncc_counter);  // all threads: the reduction needs whole warps
}

__global__ void CheckerboardKernel(const PassParams params, const PixelState state,
                                   unsigned long long* ncc_counter) {
  uint32_t count = 0;
  CheckerboardThread(params, state, ToDim2(blockIdx), ToDim2(blockDim), ToDim2(threadIdx),
                     &count);
  AccumulateCount(count, ncc_counter);
}

dim3 ToDim3(const Dim2& d) {
  return dim3(static_cast<unsigned>(d.x), static_cast<unsigned>(d.y), 1u);
}

// LaunchPasses's launches on `stream`: the kernels, and events[mark] recorded at every
// mark. With a progress callback the host waits for each iteration; otherwise the whole run
// is queued at once.
struct DeviceLaunch {
  const DevicePassBuffers& buffers;
  cudaStream_t stream;
  const cudaEvent_t* events;
  int total;
  const std::function<void()>& before_first_wait;
  const ProgressCallback& progress;
  bool waited = false;

  void Run(PassKernel kernel, const LaunchLayout& layout, const PassParams& params,
           int counter) {
    unsigned long long* ncc_counter = buffers.counters + counter;
    if (kernel == PassKernel::kInitialize) {
      MPMVS_GPU_LAUNCH(InitializeKernel, ToDim3(layout.grid), ToDim3(layout.block), stream, params,
                       buffers.state, buffers.init_plane, buffers.init_cost, ncc_counter);
    } else {
      MPMVS_GPU_LAUNCH(CheckerboardKernel, ToDim3(layout.grid), ToDim3(layout.block), stream, params,
                       buffers.state, ncc_counter);
    }
    MPMVS_CUDA_CHECK(cudaGetLastError());
  }

  void Queued(int mark) {
    MPMVS_CUDA_CHECK(cudaEventRecord(events[mark], stream));
    if (mark == 0 || !progress) return;
    FirstWait();
    MPMVS_CUDA_CHECK(cudaEventSynchronize(events[mark]));
    progress(mark, total);
  }

  // before_first_wait, once, before the host first waits for the device.
  void FirstWait() {
    if (waited) return;
    waited = true;
    if (before_first_wait) before_first_wait();
  }
};

}  // namespace

const char* GpuRuntimeName() { return kGpuRuntimeName; }

int CudaDeviceCount() {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) {
    (void)cudaGetLastError();  // no driver or no device: clear it so later CUDA calls start clean
    return 0;
  }
  return count;
}

bool CudaDeviceAvailable(int gpu_index, std::string* why) {
  auto fail = [&](const std::string& reason) {
    (void)cudaGetLastError();  // clear a non-sticky error so later CUDA calls start clean
    if (why) *why = reason;
    return false;
  };
  auto cuda_reason = [](const char* call, cudaError_t error) {
    return std::string(call) + " failed: " + cudaGetErrorName(error) + ": " +
           cudaGetErrorString(error);
  };
  const std::string gpu = std::string(kGpuRuntimeName) + " device";
  int count = 0;
  cudaError_t error = cudaGetDeviceCount(&count);
  if (error != cudaSuccess) return fail(cuda_reason("cudaGetDeviceCount", error));
  if (count <= 0) return fail("no " + gpu + " found");
  if (gpu_index < 0 || gpu_index >= count) {
    return fail(gpu + " index " + std::to_string(gpu_index) +
                " out of range (" + std::to_string(count) + " device(s))");
  }
  error = cudaSetDevice(gpu_index);
  if (error != cudaSuccess) return fail(cuda_reason("cudaSetDevice", error));
  // Fails with cudaErrorNoKernelImageForDevice when the device's architecture is not among
  // the compiled ones (MPMVS_CUDA_ARCHITECTURES).
  cudaFuncAttributes attributes;
  error = cudaFuncGetAttributes(&attributes, reinterpret_cast<const void*>(&CheckerboardKernel));
  if (error != cudaSuccess) {
    return fail("the PatchMatch kernels cannot run on " + gpu + " " + std::to_string(gpu_index) + " (" +
                cuda_reason("cudaFuncGetAttributes", error) + ")");
  }
  if (why) why->clear();
  return true;
}

void EnqueuePatchMatchPasses(const PatchMatchSchedule& schedule, const PassParams& params,
                             const DevicePassBuffers& buffers, cudaStream_t stream,
                             const cudaEvent_t* events,
                             const std::function<void()>& before_first_wait,
                             const ProgressCallback& progress) {
  const int total = static_cast<int>(schedule.iterations.size());
  MPMVS_CUDA_CHECK(cudaMemsetAsync(buffers.counters, 0,
                                   NumNccCounters(total) * sizeof(unsigned long long), stream));
  DeviceLaunch launch{buffers, stream, events, total, before_first_wait, progress};
  LaunchPasses(schedule, params, &launch);
  launch.FirstWait();
}

}  // namespace kernels
}  // namespace mpmvs

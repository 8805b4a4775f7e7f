#pragma once
// The GPU runtime of the GPU backend (kernels/*.cu, *.cuh): CUDA's, or HIP's when the same
// sources are compiled by hipcc for AMD GPUs (-DMPMVS_ENABLE_HIP=ON). The backend is written
// against CUDA's names; under HIP each one it uses is HIP's function or constant of the same
// meaning. Kernels and launch syntax (<<<...>>>) are common to both: there is one copy of
// every kernel. A CUDA name used by the backend and missing here fails the HIP build.
// MPMVS_HIP_CPU: the same HIP code compiled by the host compiler against HIP-CPU, a runtime
// that runs HIP programs on the CPU (tests/gpu/run_on_hip_cpu.sh), which has no launch syntax
// and no memory pools.
#include <cstdint>

#if defined(__HIPCC__) || defined(MPMVS_HIP_CPU)
#include <hip/hip_runtime.h>

#define cudaDevAttrMemoryPoolsSupported hipDeviceAttributeMemoryPoolsSupported
#define cudaDeviceGetAttribute          hipDeviceGetAttribute
#define cudaDeviceGetDefaultMemPool     hipDeviceGetDefaultMemPool
#define cudaErrorNoKernelImageForDevice hipErrorNoKernelImageForDevice
#define cudaError_t                     hipError_t
#define cudaEventCreateWithFlags        hipEventCreateWithFlags
#define cudaEventDefault                hipEventDefault
#define cudaEventDestroy                hipEventDestroy
#define cudaEventDisableTiming          hipEventDisableTiming
#define cudaEventElapsedTime            hipEventElapsedTime
#define cudaEventRecord                 hipEventRecord
#define cudaEventSynchronize            hipEventSynchronize
#define cudaEvent_t                     hipEvent_t
#define cudaFree                        hipFree
#define cudaFreeAsync                   hipFreeAsync
#define cudaFreeHost                    hipHostFree
#define cudaFuncAttributes              hipFuncAttributes
#define cudaFuncGetAttributes           hipFuncGetAttributes
#define cudaGetDeviceCount              hipGetDeviceCount
#define cudaGetErrorName                hipGetErrorName
#define cudaGetErrorString              hipGetErrorString
#define cudaGetLastError                hipGetLastError
#define cudaMalloc                      hipMalloc
#define cudaMallocAsync                 hipMallocAsync
#define cudaMallocHost                  hipHostMalloc
#define cudaMemGetInfo                  hipMemGetInfo
#define cudaMemPoolAttrReleaseThreshold hipMemPoolAttrReleaseThreshold
#define cudaMemPoolSetAttribute         hipMemPoolSetAttribute
#define cudaMemPool_t                   hipMemPool_t
#define cudaMemcpyAsync                 hipMemcpyAsync
#define cudaMemcpyDeviceToHost          hipMemcpyDeviceToHost
#define cudaMemcpyHostToDevice          hipMemcpyHostToDevice
#define cudaMemsetAsync                 hipMemsetAsync
#define cudaSetDevice                   hipSetDevice
#define cudaStreamCreateWithFlags       hipStreamCreateWithFlags
#define cudaStreamDestroy               hipStreamDestroy
#define cudaStreamNonBlocking           hipStreamNonBlocking
#define cudaStreamSynchronize           hipStreamSynchronize
#define cudaStreamWaitEvent             hipStreamWaitEvent
#define cudaStream_t                    hipStream_t
#define cudaSuccess                     hipSuccess
#else
#include <cuda_runtime.h>
#endif

#if defined(MPMVS_HIP_CPU)
// HIP-CPU runs every stream's tasks on one thread and binds a queued wait to the event's
// latest record only when the wait runs: a wait queued on one stream could block the thread
// that has to run the other stream's record, and runs hung. The host waits instead (a
// stronger order than the stream's; HIP-CPU overlaps nothing anyway).
#undef cudaStreamWaitEvent
#define cudaStreamWaitEvent(stream, event, flags) ((void)(stream), (void)(flags), hipEventSynchronize(event))
#endif

namespace mpmvs {
namespace kernels {

#if defined(MPMVS_HIP_CPU)
constexpr const char* kGpuRuntimeName = "HIP-CPU";
#elif defined(__HIPCC__)
constexpr const char* kGpuRuntimeName = "HIP";
#else
constexpr const char* kGpuRuntimeName = "CUDA";
#endif

// value of the lane `offset` lanes up in the warp (CUDA's 32 lanes, or an AMD wavefront's
// 64: HIP has no mask form). Every lane of the warp must call it.
__device__ __forceinline__ uint32_t ShuffleDown(uint32_t value, int offset) {
#if defined(__HIPCC__)
  return __shfl_down(value, offset);
#else
  return __shfl_down_sync(0xffffffffu, value, offset);
#endif
}

}  // namespace kernels
}  // namespace mpmvs

// kernel<<<grid, block, 0, stream>>>(args...), in a form every runtime accepts.
#if defined(MPMVS_HIP_CPU)
#define MPMVS_GPU_LAUNCH(kernel, grid, block, stream, ...) \
  hipLaunchKernelGGL(kernel, grid, block, 0, stream, __VA_ARGS__)
#define MPMVS_GPU_HAS_MEMORY_POOLS 0
#else
#define MPMVS_GPU_LAUNCH(kernel, grid, block, stream, ...) kernel<<<grid, block, 0, stream>>>(__VA_ARGS__)
#define MPMVS_GPU_HAS_MEMORY_POOLS 1
#endif

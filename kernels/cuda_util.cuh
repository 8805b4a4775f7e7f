#pragma once
// Small CUDA helpers of the CUDA backend (.cu files only): error checks and RAII owners of
// streams, events, pinned host memory and device memory, so that errors (exceptions) do not
// leak them.
#include "kernels/gpu_runtime.h"

#include <cstddef>
#include <stdexcept>
#include <string>

namespace mpmvs {
namespace kernels {

[[noreturn]] inline void ThrowCudaError(cudaError_t error, const char* what, const char* file,
                                        int line) {
  throw std::runtime_error(std::string(kGpuRuntimeName) + " error in " + what + " (" + file + ":" +
                           std::to_string(line) + "): " + cudaGetErrorName(error) + ": " +
                           cudaGetErrorString(error));
}

#define MPMVS_CUDA_CHECK(expr)                                     \
  do {                                                             \
    const cudaError_t mpmvs_cuda_error = (expr);                   \
    if (mpmvs_cuda_error != cudaSuccess) {                         \
      ThrowCudaError(mpmvs_cuda_error, #expr, __FILE__, __LINE__); \
    }                                                              \
  } while (0)

class Stream {
 public:
  Stream() { MPMVS_CUDA_CHECK(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking)); }
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;
  ~Stream() { (void)cudaStreamDestroy(stream_); }
  cudaStream_t get() const { return stream_; }

 private:
  cudaStream_t stream_ = nullptr;
};

class Event {
 public:
  explicit Event(unsigned flags = cudaEventDefault) {
    // The flags' own type: an unsigned int in CUDA and HIP, an enum in HIP-CPU.
    MPMVS_CUDA_CHECK(cudaEventCreateWithFlags(&event_, static_cast<decltype(cudaEventDefault)>(flags)));
  }
  Event(const Event&) = delete;
  Event& operator=(const Event&) = delete;
  ~Event() { (void)cudaEventDestroy(event_); }
  cudaEvent_t get() const { return event_; }

 private:
  cudaEvent_t event_ = nullptr;
};

// Device memory, stream ordered (cudaMallocAsync/cudaFreeAsync) where the device supports
// memory pools: freeing then needs no device-wide synchronisation, which cudaFree does and
// which would make the host wait for the running kernels in the middle of an upload ahead.
class DeviceAllocator {
 public:
  explicit DeviceAllocator(bool stream_ordered = false) : stream_ordered_(stream_ordered) {}
  void* Allocate(size_t bytes, cudaStream_t stream) const {
    void* ptr = nullptr;
    if (bytes == 0) return ptr;
    if (stream_ordered_) {
      MPMVS_CUDA_CHECK(cudaMallocAsync(&ptr, bytes, stream));
    } else {
      MPMVS_CUDA_CHECK(cudaMalloc(&ptr, bytes));
    }
    return ptr;
  }
  // The caller guarantees that no queued work still uses ptr, other than work on `stream`.
  void Free(void* ptr, cudaStream_t stream) const {
    if (!ptr) return;
    if (stream_ordered_) {
      MPMVS_CUDA_CHECK(cudaFreeAsync(ptr, stream));
    } else {
      MPMVS_CUDA_CHECK(cudaFree(ptr));
    }
  }

 private:
  bool stream_ordered_ = false;
};

// A device buffer that grows (never shrinks) when a larger problem comes.
class GrowingDeviceBuffer {
 public:
  GrowingDeviceBuffer() = default;
  GrowingDeviceBuffer(const GrowingDeviceBuffer&) = delete;
  GrowingDeviceBuffer& operator=(const GrowingDeviceBuffer&) = delete;
  ~GrowingDeviceBuffer() {
    if (ptr_) (void)cudaFree(ptr_);  // the owner synchronised its streams; no throwing here
  }
  // Queued on `stream`; the previous contents are not kept.
  void Reserve(size_t bytes, const DeviceAllocator& alloc, cudaStream_t stream) {
    if (bytes <= capacity_) return;
    alloc.Free(ptr_, stream);
    ptr_ = nullptr;
    capacity_ = 0;
    ptr_ = static_cast<char*>(alloc.Allocate(bytes, stream));
    capacity_ = bytes;
  }
  char* get() const { return ptr_; }

 private:
  char* ptr_ = nullptr;
  size_t capacity_ = 0;
};

// Page-locked host memory: the only kind cudaMemcpyAsync copies without blocking the host.
class PinnedBuffer {
 public:
  PinnedBuffer() = default;
  PinnedBuffer(const PinnedBuffer&) = delete;
  PinnedBuffer& operator=(const PinnedBuffer&) = delete;
  ~PinnedBuffer() {
    if (ptr_) (void)cudaFreeHost(ptr_);
  }
  // The previous contents are not kept; the caller made sure no copy still reads them.
  void Reserve(size_t bytes) {
    if (bytes <= capacity_) return;
    if (ptr_) MPMVS_CUDA_CHECK(cudaFreeHost(ptr_));
    ptr_ = nullptr;
    capacity_ = 0;
    MPMVS_CUDA_CHECK(cudaMallocHost(reinterpret_cast<void**>(&ptr_), bytes));
    capacity_ = bytes;
  }
  char* get() const { return ptr_; }

 private:
  char* ptr_ = nullptr;
  size_t capacity_ = 0;
};

}  // namespace kernels
}  // namespace mpmvs

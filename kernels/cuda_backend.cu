// CUDA backend: the same per-pixel functions as the CPU backend (patch_match_pixel.h with
// ScalarNcc), launched one thread per pixel. The host side only moves data, sets up the
// passes with the shared functions of patch_match.h and maps threads to pixels with
// launch_layout.h; see DESIGN_CUDA.md.
#include <cuda_runtime.h>

#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "kernels/launch_layout.h"
#include "kernels/patch_match.h"

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

[[noreturn]] void ThrowCudaError(cudaError_t error, const char* what, const char* file, int line) {
  throw std::runtime_error(std::string("CUDA error in ") + what + " (" + file + ":" +
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

// ---------------------------------------------------------------------------------------
// Device side: thin launchers around the shared per-pixel functions.

__device__ __forceinline__ Dim2 ToDim2(const uint3& d) {
  return Dim2{static_cast<int>(d.x), static_cast<int>(d.y)};
}
__device__ __forceinline__ Dim2 ToDim2(const dim3& d) {
  return Dim2{static_cast<int>(d.x), static_cast<int>(d.y)};
}

// Adds every thread's count to *counter: a warp sum, then one atomic per warp.
__device__ __forceinline__ void AccumulateCount(uint32_t count, unsigned long long* counter) {
  for (int offset = 16; offset > 0; offset >>= 1)
    count += __shfl_down_sync(0xffffffffu, count, offset);
  const unsigned lane = (threadIdx.y * blockDim.x + threadIdx.x) & 31u;
  if (lane == 0 && count > 0) atomicAdd(counter, static_cast<unsigned long long>(count));
}

__global__ void InitializeKernel(const PassParams params, const PixelState state,
                                 const float* init_plane, const float* init_cost,
                                 unsigned long long* ncc_counter) {
  int u, v;
  uint32_t count = 0;
  if (ImageThreadPixel(params.ref_camera.width, params.ref_camera.height, ToDim2(blockIdx),
                       ToDim2(blockDim), ToDim2(threadIdx), &u, &v)) {
    InitializePixel<ScalarNcc>(params, state, init_plane, init_cost, u, v, &count);
  }
  AccumulateCount(count, ncc_counter);  // all threads: the reduction needs whole warps
}

__global__ void CheckerboardKernel(const PassParams params, const PixelState state,
                                   unsigned long long* ncc_counter) {
  int u, v;
  uint32_t count = 0;
  if (CheckerboardThreadPixel(params.ref_camera.width, params.ref_camera.height, params.color,
                              ToDim2(blockIdx), ToDim2(blockDim), ToDim2(threadIdx), &u, &v)) {
    UpdatePixel<ScalarNcc>(params, state, u, v, &count);
  }
  AccumulateCount(count, ncc_counter);
}

// ---------------------------------------------------------------------------------------
// Host side: RAII for device resources so errors (exceptions) do not leak them.

template <typename T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  explicit DeviceBuffer(size_t count) { Allocate(count); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  ~DeviceBuffer() {
    if (ptr_) cudaFree(ptr_);  // no throwing from a destructor
  }
  void Allocate(size_t count) {
    count_ = count;
    if (count > 0) MPMVS_CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&ptr_), count * sizeof(T)));
  }
  void Upload(const T* host, size_t count, cudaStream_t stream) {
    Allocate(count);
    if (count > 0) {
      MPMVS_CUDA_CHECK(
          cudaMemcpyAsync(ptr_, host, count * sizeof(T), cudaMemcpyHostToDevice, stream));
    }
  }
  void Download(T* host, cudaStream_t stream) const {
    if (count_ > 0) {
      MPMVS_CUDA_CHECK(
          cudaMemcpyAsync(host, ptr_, count_ * sizeof(T), cudaMemcpyDeviceToHost, stream));
    }
  }
  T* get() const { return ptr_; }

 private:
  T* ptr_ = nullptr;
  size_t count_ = 0;
};

class Stream {
 public:
  Stream() { MPMVS_CUDA_CHECK(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking)); }
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;
  ~Stream() { cudaStreamDestroy(stream_); }
  cudaStream_t get() const { return stream_; }

 private:
  cudaStream_t stream_ = nullptr;
};

class Event {
 public:
  Event() { MPMVS_CUDA_CHECK(cudaEventCreate(&event_)); }
  Event(const Event&) = delete;
  Event& operator=(const Event&) = delete;
  ~Event() { cudaEventDestroy(event_); }
  cudaEvent_t get() const { return event_; }

 private:
  cudaEvent_t event_ = nullptr;
};

dim3 ToDim3(const Dim2& d) {
  return dim3(static_cast<unsigned>(d.x), static_cast<unsigned>(d.y), 1u);
}

}  // namespace

bool CudaDeviceAvailable(int gpu_index, std::string* why) {
  auto fail = [&](const std::string& reason) {
    cudaGetLastError();  // clear a non-sticky error so later CUDA calls start clean
    if (why) *why = reason;
    return false;
  };
  auto cuda_reason = [](const char* call, cudaError_t error) {
    return std::string(call) + " failed: " + cudaGetErrorName(error) + ": " +
           cudaGetErrorString(error);
  };
  int count = 0;
  cudaError_t error = cudaGetDeviceCount(&count);
  if (error != cudaSuccess) return fail(cuda_reason("cudaGetDeviceCount", error));
  if (count <= 0) return fail("no CUDA device found");
  if (gpu_index < 0 || gpu_index >= count) {
    return fail("CUDA device index " + std::to_string(gpu_index) + " out of range (" +
                std::to_string(count) + " device(s))");
  }
  error = cudaSetDevice(gpu_index);
  if (error != cudaSuccess) return fail(cuda_reason("cudaSetDevice", error));
  // Fails with cudaErrorNoKernelImageForDevice when the device's architecture is not among
  // the compiled ones (MPMVS_CUDA_ARCHITECTURES).
  cudaFuncAttributes attributes;
  error = cudaFuncGetAttributes(&attributes, CheckerboardKernel);
  if (error != cudaSuccess) {
    return fail("the PatchMatch kernels cannot run on CUDA device " + std::to_string(gpu_index) +
                " (" + cuda_reason("cudaFuncGetAttributes", error) + ")");
  }
  if (why) why->clear();
  return true;
}

void RunPatchMatchCuda(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                       int gpu_index, PatchMatchResult* result, const ProgressCallback& progress) {
  schedule.Check();
  std::string why;
  if (!CudaDeviceAvailable(gpu_index, &why))
    throw std::runtime_error("CUDA backend unusable: " + why);
  MPMVS_CUDA_CHECK(cudaSetDevice(gpu_index));  // per host thread

  // Host copies of the source views; their pointers are replaced by device ones below.
  std::vector<SourceView> sources = MakeSourceViews(problem);
  PassParams params = MakePassParams(problem, schedule, sources.data());
  const int W = problem.ref_camera.width, H = problem.ref_camera.height;
  const StateLayout layout = MakeStateLayout(W, H);
  ResetResult(W, H, result);

  Stream stream;
  const cudaStream_t s = stream.get();

  // Inputs, uploaded asynchronously in stream order ahead of the kernels.
  const size_t num_sources = problem.sources.size();
  auto image_size = [](const ImageView& img) {
    return img.width > 0 && img.height > 0 ? static_cast<size_t>(img.width) * img.height : 0;
  };
  DeviceBuffer<float> ref_image;
  ref_image.Upload(problem.ref_image.data, image_size(problem.ref_image), s);
  params.ref_image.data = ref_image.get();
  std::vector<DeviceBuffer<float>> source_images(num_sources);
  std::vector<DeviceBuffer<float>> source_depths(num_sources);
  for (size_t i = 0; i < num_sources; ++i) {
    const PatchMatchSource& src = problem.sources[i];
    source_images[i].Upload(src.image.data, image_size(src.image), s);
    sources[i].image.data = source_images[i].get();
    sources[i].depth = nullptr;  // only read by geometric passes
    if (schedule.geometric) {
      source_depths[i].Upload(src.depth_map,
                              MakeStateLayout(src.camera.width, src.camera.height).num_pixels, s);
      sources[i].depth = source_depths[i].get();
    }
  }
  DeviceBuffer<SourceView> device_sources;
  device_sources.Upload(sources.data(), num_sources, s);
  params.sources = device_sources.get();

  DeviceBuffer<float> init_plane, init_cost;
  if (problem.init_plane) init_plane.Upload(problem.init_plane, layout.plane_floats, s);
  if (problem.init_cost) init_cost.Upload(problem.init_cost, layout.cost_floats, s);
  DeviceBuffer<float> prior_plane;
  DeviceBuffer<uint8_t> prior_label;
  params.prior.plane = nullptr;
  params.prior.label = nullptr;
  if (schedule.use_prior) {
    prior_plane.Upload(problem.prior_plane, layout.plane_floats, s);
    prior_label.Upload(problem.prior_label, layout.label_bytes, s);
    params.prior.plane = prior_plane.get();
    params.prior.label = prior_label.get();
  }

  // Per-pixel state; the initialisation pass writes every entry.
  DeviceBuffer<float> plane(layout.plane_floats), cost(layout.cost_floats),
      photo_cost(layout.cost_floats), geo_error(layout.cost_floats);
  DeviceBuffer<uint32_t> view_mask(layout.mask_words);
  PixelState state;
  state.plane = plane.get();
  state.cost = cost.get();
  state.photo_cost = photo_cost.get();
  state.geo_error = geo_error.get();
  state.view_mask = view_mask.get();

  // NCC counters: [0] initialisation, [1 + it] iteration it.
  const int total = static_cast<int>(schedule.iterations.size());
  DeviceBuffer<unsigned long long> counters(1 + total);
  MPMVS_CUDA_CHECK(cudaMemsetAsync(counters.get(), 0, (1 + total) * sizeof(unsigned long long), s));

  const bool empty = layout.num_pixels == 0;
  const LaunchLayout init_layout = ImageLaunchLayout(W, H);
  const LaunchLayout pass_layout = CheckerboardLaunchLayout(W, H);

  SetInitPass(schedule, &params);
  if (!empty) {
    InitializeKernel<<<ToDim3(init_layout.grid), ToDim3(init_layout.block), 0, s>>>(
        params, state, init_plane.get(), init_cost.get(), counters.get());
    MPMVS_CUDA_CHECK(cudaGetLastError());
  }

  // events[it] .. events[it + 1] bracket iteration it on the GPU.
  std::vector<Event> events(total + 1);
  MPMVS_CUDA_CHECK(cudaEventRecord(events[0].get(), s));
  for (int it = 0; it < total; ++it) {
    for (int color = 0; color < 2; ++color) {
      SetCheckerboardPass(schedule, it, color, &params);
      if (empty) continue;
      CheckerboardKernel<<<ToDim3(pass_layout.grid), ToDim3(pass_layout.block), 0, s>>>(
          params, state, counters.get() + 1 + it);
      MPMVS_CUDA_CHECK(cudaGetLastError());
    }
    MPMVS_CUDA_CHECK(cudaEventRecord(events[it + 1].get(), s));
    if (progress) {
      // Only wait per iteration when someone is watching; otherwise the whole run is queued.
      MPMVS_CUDA_CHECK(cudaEventSynchronize(events[it + 1].get()));
      progress(it + 1, total);
    }
  }

  plane.Download(result->plane.data(), s);
  cost.Download(result->cost.data(), s);
  photo_cost.Download(result->photo_cost.data(), s);
  geo_error.Download(result->geo_error.data(), s);
  view_mask.Download(result->view_mask.data(), s);
  std::vector<unsigned long long> evaluations(1 + total, 0ull);
  counters.Download(evaluations.data(), s);
  MPMVS_CUDA_CHECK(cudaStreamSynchronize(s));

  result->init_ncc_evaluations = evaluations[0];
  for (int it = 0; it < total; ++it) {
    float ms = 0.f;
    MPMVS_CUDA_CHECK(cudaEventElapsedTime(&ms, events[it].get(), events[it + 1].get()));
    result->iterations.push_back(MakeIterationStats(schedule, it, evaluations[1 + it], 1e-3 * ms));
  }
}

}  // namespace kernels
}  // namespace mpmvs

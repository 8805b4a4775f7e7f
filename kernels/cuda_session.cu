// The CUDA session (cuda_session.h): executes the upload plans of DeviceCachePlanner with
// two streams and events, and runs the passes of cuda_backend.cu. Which uploads happen,
// which entries are evicted and where each input goes is decided by the (CPU-tested)
// planner; this file only carries it out. See DESIGN_CUDA.md.
#include "kernels/gpu_runtime.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/cuda_launch.cuh"
#include "kernels/cuda_session.h"
#include "kernels/cuda_util.cuh"

namespace mpmvs {
namespace kernels {
namespace {

// A problem whose inputs are queued on the copy stream, with their device addresses.
struct DeviceProblem {
  UploadPlan plan;
  std::vector<DeviceInput> inputs;
  const float* ref_image = nullptr;
  const float* ref_chroma = nullptr;
  const SourceView* sources = nullptr;
  const float* init_plane = nullptr;
  const float* init_cost = nullptr;
  const float* prior_plane = nullptr;
  const uint8_t* prior_label = nullptr;
};

int SelectDevice(const CudaSessionOptions& options) {
  std::string why;
  options.Check();
  if (!CudaDeviceAvailable(options.gpu_index, &why)) {
    throw std::runtime_error("CUDA backend unusable: " + why);
  }
  MPMVS_CUDA_CHECK(cudaSetDevice(options.gpu_index));
  return options.gpu_index;
}

bool SupportsStreamOrderedAllocation(int device) {
#if !MPMVS_GPU_HAS_MEMORY_POOLS
  (void)device;
  return false;
#else
  int supported = 0;
  if (cudaDeviceGetAttribute(&supported, cudaDevAttrMemoryPoolsSupported, device) !=
      cudaSuccess) {
    (void)cudaGetLastError();  // not sticky: treat as "not supported"
    return false;
  }
  if (supported) {
    // Keep memory freed by evictions in the pool for the next upload instead of handing it
    // back to the driver at every synchronisation.
    cudaMemPool_t pool;
    MPMVS_CUDA_CHECK(cudaDeviceGetDefaultMemPool(&pool, device));
    uint64_t keep = UINT64_MAX;
    MPMVS_CUDA_CHECK(cudaMemPoolSetAttribute(pool, cudaMemPoolAttrReleaseThreshold, &keep));
  }
  return supported != 0;
#endif
}

size_t CacheBudget(const CudaSessionOptions& options) {
  size_t free_bytes = 0, total_bytes = 0;
  MPMVS_CUDA_CHECK(cudaMemGetInfo(&free_bytes, &total_bytes));
  return DeviceCacheBudget(options.cache_size_bytes, free_bytes);
}

}  // namespace

class CudaSession::Impl {
 public:
  explicit Impl(const CudaSessionOptions& options)
      : device_(SelectDevice(options)),
        alloc_(SupportsStreamOrderedAllocation(device_)),
        planner_(CacheBudget(options)) {
    // Each slot's event starts recorded (on the empty copy stream, so already complete): the
    // first upload into a slot waits for it like every later one. CUDA and HIP would also
    // accept waiting for an event never recorded; HIP-CPU refuses it.
    for (Slot& slot : slots_) MPMVS_CUDA_CHECK(cudaEventRecord(slot.uploaded.get(), copy_.get()));
  }

  ~Impl() {
    // Nothing queued may still use the memory freed here; no throwing from a destructor.
    (void)cudaSetDevice(device_);
    (void)cudaStreamSynchronize(copy_.get());
    (void)cudaStreamSynchronize(compute_.get());
    for (auto& entry : entries_) (void)cudaFree(entry.second);
  }

  void Run(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
           PatchMatchResult* result, const NextProblemCallback& next,
           const ProgressCallback& progress);

  DeviceCacheStats CacheStats() const { return planner_.stats(); }
  size_t CacheBudgetBytes() const { return planner_.budget_bytes(); }

 private:
  // Buffers of one of the two problems in flight (the running one, the one uploaded ahead).
  struct Slot {
    GrowingDeviceBuffer inputs;  // per-problem inputs (initial planes, prior, source views)
    PinnedBuffer staging;        // host side of this slot's uploads
    Event uploaded{cudaEventDisableTiming};  // recorded on the copy stream after them
  };

  std::unique_ptr<DeviceProblem> Upload(const PatchMatchProblem& problem,
                                        std::vector<DeviceInput> inputs);
  void Execute(const PatchMatchProblem& problem, DeviceProblem* dp);
  void UploadAhead(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule);
  void DropAhead();
  PixelState ReserveState(int width, int height, bool settled_skips);
  void Download(const PatchMatchSchedule& schedule, const DevicePassBuffers& buffers,
                const std::vector<cudaEvent_t>& events, PatchMatchResult* result);

  int device_;
  Stream compute_;  // kernels, per-pixel state, downloads
  Stream copy_;     // uploads, cache allocations and evictions
  DeviceAllocator alloc_;
  DeviceCachePlanner planner_;
  std::map<uint64_t, void*> entries_;  // cache entry -> device memory
  Slot slots_[DeviceCachePlanner::kNumSlots];
  GrowingDeviceBuffer state_, counters_;
  std::vector<std::unique_ptr<Event>> iteration_events_;
  std::unique_ptr<DeviceProblem> ahead_;
};

std::unique_ptr<DeviceProblem> CudaSession::Impl::Upload(const PatchMatchProblem& problem,
                                                         std::vector<DeviceInput> inputs) {
  auto dp = std::make_unique<DeviceProblem>();
  dp->plan = planner_.Plan(inputs);
  dp->inputs = std::move(inputs);
  try {
    Execute(problem, dp.get());
  } catch (...) {
    planner_.Release(dp->plan.ticket);
    throw;
  }
  return dp;
}

void CudaSession::Impl::Execute(const PatchMatchProblem& problem, DeviceProblem* dp) {
  const UploadPlan& plan = dp->plan;
  Slot& slot = slots_[plan.slot];
  const cudaStream_t copy = copy_.get();
  // The staging memory is rewritten below, so the slot's previous copies must be done. They
  // are (the run of that problem waited for them), unless it was a dropped upload ahead.
  MPMVS_CUDA_CHECK(cudaEventSynchronize(slot.uploaded.get()));
  // Evicted entries are no longer read by any queued kernel (the planner keeps the entries
  // of the problems in flight); freeing on the copy stream orders it after earlier copies.
  for (uint64_t id : plan.evictions) {
    auto it = entries_.find(id);
    alloc_.Free(it->second, copy);
    entries_.erase(it);
  }
  for (const PlannedAllocation& a : plan.allocations) {
    entries_[a.entry] = alloc_.Allocate(a.bytes, copy);
  }
  slot.inputs.Reserve(plan.slot_bytes, alloc_, copy);
  slot.staging.Reserve(plan.staging_bytes);

  std::vector<char*> device(dp->inputs.size(), nullptr);
  for (size_t i = 0; i < dp->inputs.size(); ++i) {
    const DeviceInputPlacement& at = plan.placements[i];
    device[i] = at.in_cache ? static_cast<char*>(entries_.at(at.entry))
                            : slot.inputs.get() + at.slot_offset;
  }
  // Source views with device pointers; absent inputs stay null (depth maps outside
  // geometric schedules, the CPU-only quads).
  std::vector<SourceView> views = MakeSourceViews(problem);
  for (SourceView& view : views) {
    view.image.data = nullptr;
    view.image.quads = nullptr;
    view.depth = nullptr;
  }
  for (size_t i = 0; i < dp->inputs.size(); ++i) {
    const DeviceInput& in = dp->inputs[i];
    const float* floats = reinterpret_cast<const float*>(device[i]);
    switch (in.role) {
      case DeviceInputRole::kRefImage: dp->ref_image = floats; break;
      case DeviceInputRole::kRefChroma: dp->ref_chroma = floats; break;
      case DeviceInputRole::kSourceImage: views[in.source].image.data = floats; break;
      case DeviceInputRole::kSourceDepth: views[in.source].depth = floats; break;
      case DeviceInputRole::kInitPlane: dp->init_plane = floats; break;
      case DeviceInputRole::kInitCost: dp->init_cost = floats; break;
      case DeviceInputRole::kPriorPlane: dp->prior_plane = floats; break;
      case DeviceInputRole::kPriorLabel:
        dp->prior_label = reinterpret_cast<const uint8_t*>(device[i]);
        break;
      case DeviceInputRole::kSourceViews:
        dp->sources = reinterpret_cast<const SourceView*>(device[i]);
        break;
    }
  }
  // Host -> pinned staging -> device: only copies from page-locked memory are asynchronous.
  for (const PlannedUpload& up : plan.uploads) {
    const DeviceInput& in = dp->inputs[up.input];
    const void* host = in.host;
    if (in.role == DeviceInputRole::kSourceViews) {
      if (views.size() * sizeof(SourceView) != up.bytes) {
        throw std::logic_error("CUDA session: source view upload of the wrong size");
      }
      host = views.data();
    }
    char* staged = slot.staging.get() + up.staging_offset;
    std::memcpy(staged, host, up.bytes);
    MPMVS_CUDA_CHECK(cudaMemcpyAsync(device[up.input], staged, up.bytes, cudaMemcpyHostToDevice,
                                     copy));
  }
  // Also covers the earlier copies this problem's cache hits depend on (one copy stream).
  MPMVS_CUDA_CHECK(cudaEventRecord(slot.uploaded.get(), copy));
}

void CudaSession::Impl::DropAhead() {
  if (!ahead_) return;
  // Its copies may still be queued: the entries they fill become evictable, which frees
  // them on the copy stream after those copies; its slot waits for them before reuse.
  planner_.Release(ahead_->plan.ticket);
  ahead_.reset();
}

void CudaSession::Impl::UploadAhead(const PatchMatchProblem& problem,
                                    const PatchMatchSchedule& schedule) {
  DropAhead();
  std::vector<DeviceInput> inputs;
  try {
    MakePassParams(problem, schedule, nullptr);  // the checks only
    inputs = ListDeviceInputs(problem, schedule);
  } catch (const std::invalid_argument&) {
    return;  // not uploaded; the Run of that problem reports the error
  }
  ahead_ = Upload(problem, std::move(inputs));
}

PixelState CudaSession::Impl::ReserveState(int width, int height, bool settled_skips) {
  const StateLayout layout = MakeStateLayout(width, height);
  const size_t plane = layout.plane_floats * sizeof(float);
  const size_t cost = layout.cost_floats * sizeof(float);
  // plane, then three cost-sized arrays (cost, photo cost, geometric error), then the masks,
  // then the skip counts (zeroed by the initialisation kernel).
  size_t offsets[5] = {0, AlignUp(plane)};
  for (int k = 2; k < 5; ++k) offsets[k] = offsets[k - 1] + AlignUp(cost);
  const size_t skips = offsets[4] + AlignUp(layout.mask_words * sizeof(uint32_t));
  const size_t total = skips + (settled_skips ? layout.skip_bytes : 0);
  PixelState state;
  if (layout.num_pixels == 0) return state;
  // Stream ordered on the compute stream: the previous run's kernels are its only users.
  state_.Reserve(total, alloc_, compute_.get());
  char* base = state_.get();
  state.plane = reinterpret_cast<float*>(base + offsets[0]);
  state.cost = reinterpret_cast<float*>(base + offsets[1]);
  state.photo_cost = reinterpret_cast<float*>(base + offsets[2]);
  state.geo_error = reinterpret_cast<float*>(base + offsets[3]);
  state.view_mask = reinterpret_cast<uint32_t*>(base + offsets[4]);
  if (settled_skips) state.skips_left = reinterpret_cast<uint8_t*>(base + skips);
  return state;
}

void CudaSession::Impl::Run(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                            PatchMatchResult* result, const NextProblemCallback& next,
                            const ProgressCallback& progress) {
  schedule.Check();
  MPMVS_CUDA_CHECK(cudaSetDevice(device_));  // per host thread
  PassParams params = MakePassParams(problem, schedule, nullptr);  // checks before uploads
  std::vector<DeviceInput> inputs = ListDeviceInputs(problem, schedule);
  std::unique_ptr<DeviceProblem> current;
  if (ahead_ && SameDeviceInputs(ahead_->inputs, inputs)) {
    current = std::move(ahead_);
  } else {
    DropAhead();
    current = Upload(problem, std::move(inputs));
  }
  // However the run ends: wait for its kernels before its entries become evictable.
  struct Finish {
    Impl* self;
    uint64_t ticket;
    ~Finish() {
      (void)cudaStreamSynchronize(self->compute_.get());
      self->planner_.Release(ticket);
    }
  } finish{this, current->plan.ticket};

  const int W = problem.ref_camera.width, H = problem.ref_camera.height;
  ResetResult(W, H, result);
  params.ref_image.data = current->ref_image;
  params.ref_image.quads = nullptr;
  params.ref_image.chroma = current->ref_chroma;
  params.sources = current->sources;
  params.prior.plane = current->prior_plane;
  params.prior.label = current->prior_label;

  const cudaStream_t compute = compute_.get();
  const int total = static_cast<int>(schedule.iterations.size());
  DevicePassBuffers buffers;
  buffers.state = ReserveState(W, H, schedule.settled_skips > 0);
  buffers.init_plane = current->init_plane;
  buffers.init_cost = current->init_cost;
  counters_.Reserve(NumNccCounters(total) * sizeof(unsigned long long), alloc_, compute);
  buffers.counters = reinterpret_cast<unsigned long long*>(counters_.get());
  while (iteration_events_.size() < static_cast<size_t>(total + 1)) {
    iteration_events_.push_back(std::make_unique<Event>());
  }
  std::vector<cudaEvent_t> events(total + 1);
  for (int i = 0; i <= total; ++i) events[i] = iteration_events_[i]->get();

  // The kernels start once this problem's uploads (and all earlier copies) are done.
  MPMVS_CUDA_CHECK(
      cudaStreamWaitEvent(compute, slots_[current->plan.slot].uploaded.get(), 0));
  // While they run: assemble the next problem on the host and queue its uploads.
  auto look_ahead = [&] {
    if (!next) return;
    const PatchMatchProblem* following = next();
    if (following) UploadAhead(*following, schedule);
  };
  EnqueuePatchMatchPasses(schedule, params, buffers, compute, events.data(), look_ahead, progress);

  Download(schedule, buffers, events, result);
}

// Copies the run's per-pixel state and NCC counters into result on the compute stream,
// waits for them, and adds the iteration statistics (times from the iteration events).
void CudaSession::Impl::Download(const PatchMatchSchedule& schedule,
                                 const DevicePassBuffers& buffers,
                                 const std::vector<cudaEvent_t>& events,
                                 PatchMatchResult* result) {
  const cudaStream_t compute = compute_.get();
  const StateLayout layout = MakeStateLayout(result->width, result->height);
  const int total = static_cast<int>(schedule.iterations.size());
  auto download = [&](void* host, const void* dev, size_t bytes) {
    if (bytes > 0) {
      MPMVS_CUDA_CHECK(cudaMemcpyAsync(host, dev, bytes, cudaMemcpyDeviceToHost, compute));
    }
  };
  if (layout.num_pixels > 0) {
    download(result->plane.data(), buffers.state.plane, layout.plane_floats * sizeof(float));
    download(result->cost.data(), buffers.state.cost, layout.cost_floats * sizeof(float));
    download(result->photo_cost.data(), buffers.state.photo_cost,
             layout.cost_floats * sizeof(float));
    download(result->geo_error.data(), buffers.state.geo_error,
             layout.cost_floats * sizeof(float));
    download(result->view_mask.data(), buffers.state.view_mask,
             layout.mask_words * sizeof(uint32_t));
  }
  std::vector<unsigned long long> evaluations(NumNccCounters(total), 0ull);
  download(evaluations.data(), buffers.counters, evaluations.size() * sizeof(unsigned long long));
  MPMVS_CUDA_CHECK(cudaStreamSynchronize(compute));

  result->init_ncc_evaluations = evaluations[kInitCounter];
  for (int it = 0; it < total; ++it) {
    float ms = 0.f;
    MPMVS_CUDA_CHECK(cudaEventElapsedTime(&ms, events[it], events[it + 1]));
    result->iterations.push_back(
        MakeIterationStats(schedule, it, evaluations[IterationCounter(it)], 1e-3 * ms));
  }
}

CudaSession::CudaSession(const CudaSessionOptions& options)
    : impl_(std::make_unique<Impl>(options)) {}
CudaSession::~CudaSession() = default;

void CudaSession::Run(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                      PatchMatchResult* result, const NextProblemCallback& next,
                      const ProgressCallback& progress) {
  impl_->Run(problem, schedule, result, next, progress);
}

DeviceCacheStats CudaSession::CacheStats() const { return impl_->CacheStats(); }
size_t CudaSession::CacheBudgetBytes() const { return impl_->CacheBudgetBytes(); }

// One problem: a session of its own, released on return.
void RunPatchMatchCuda(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                       int gpu_index, PatchMatchResult* result, const ProgressCallback& progress) {
  schedule.Check();
  CudaSessionOptions options;
  options.gpu_index = gpu_index;
  CudaSession session(options);
  session.Run(problem, schedule, result, nullptr, progress);
}

}  // namespace kernels
}  // namespace mpmvs

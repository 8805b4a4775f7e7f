#pragma once
// Host-side bookkeeping of the CUDA session (cuda_session.h): for each PatchMatch problem,
// which inputs are uploaded and which are already on the device, which cached entries are
// evicted under the byte budget, where the per-problem inputs go, and how the uploads are
// ordered before the problem's kernels. Plain data and no CUDA, so that the plan is unit
// tested on machines without a GPU (tests/kernels/device_cache_plan_test.cc); cuda_session.cu only
// executes it (allocations, cudaMemcpyAsync, cudaEventRecord, cudaStreamWaitEvent).
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {

// What an input is for: decides where its device pointer goes (PassParams, SourceView).
enum class DeviceInputRole : uint8_t {
  kRefImage,
  kRefChroma,  // the reference's chroma guide (ImageView::chroma), this problem only
  kSourceImage,
  kSourceDepth,
  kInitPlane,
  kInitCost,
  kPriorPlane,
  kPriorLabel,
  kSourceViews,  // the SourceView array, built by the session with device pointers
};

enum class DeviceDataKind : uint8_t { kImage, kDepthMap };

// Identity of a cached input. A grey image is the same in every stage; a depth map is the
// result of one stage, so the stage is part of its key.
struct DeviceCacheKey {
  uint32_t image_id = kNoImageId;
  DeviceDataKind kind = DeviceDataKind::kImage;
  int32_t stage = -1;  // depth maps: PatchMatchProblem::depth_maps_stage; images: -1

  bool operator<(const DeviceCacheKey& other) const;
  bool operator==(const DeviceCacheKey& other) const;
};
std::string DescribeKey(const DeviceCacheKey& key);

struct DeviceInput {
  DeviceInputRole role = DeviceInputRole::kRefImage;
  int source = -1;      // kSourceImage / kSourceDepth: index into problem.sources
  bool cached = false;  // true: a device cache entry under `key`; false: this problem only
  DeviceCacheKey key;
  size_t bytes = 0;
  const void* host = nullptr;  // where the bytes are; nullptr for kSourceViews
};

// The device inputs of `problem` run with `schedule`, in this order: reference image, per
// source its image (and its depth map for geometric schedules), initial planes and costs,
// planar prior (prior schedules), source views. Images and depth maps with an id are
// cached; everything else is per problem. Inputs of 0 bytes are left out (their device
// pointer stays null, as the kernels expect for absent inputs).
std::vector<DeviceInput> ListDeviceInputs(const PatchMatchProblem& problem,
                                          const PatchMatchSchedule& schedule);
// Same inputs from the same host memory: a problem uploaded ahead is the one being run.
bool SameDeviceInputs(const std::vector<DeviceInput>& a, const std::vector<DeviceInput>& b);

// Byte budget of the device cache: the host cache size (--PatchMatchStereo.cache_size; more
// than the host keeps would rarely be hit) but at most half the device memory free at
// session start, leaving the other half to the per-pixel state, the per-problem inputs of
// the two problems in flight and the driver.
size_t DeviceCacheBudget(size_t cache_size_bytes, size_t free_device_bytes);

// Where input i of a plan lives on the device.
struct DeviceInputPlacement {
  bool in_cache = false;
  uint64_t entry = 0;        // in_cache: the cache entry
  size_t slot_offset = 0;    // !in_cache: offset in the plan's slot buffer
  bool uploaded = false;     // false: a cache hit (or a repeat of an input of this problem)
  uint64_t copy_sequence = 0;  // the copy that filled it (1-based, in copy-stream order)
};

struct PlannedUpload {
  int input = 0;  // index into the inputs given to Plan
  size_t bytes = 0;
  size_t staging_offset = 0;  // in the slot's pinned staging buffer
  uint64_t copy_sequence = 0;
};

struct PlannedAllocation {
  uint64_t entry = 0;
  size_t bytes = 0;
};

struct UploadPlan {
  uint64_t ticket = 0;  // hand back to Release once the problem's kernels have finished
  // Per-problem buffers of this problem: device slot buffer, pinned staging buffer and
  // upload event. Two slots: one for the running problem, one for the next, uploaded ahead.
  int slot = 0;
  std::vector<uint64_t> evictions;  // free these first (no problem in flight uses them)
  std::vector<PlannedAllocation> allocations;
  std::vector<DeviceInputPlacement> placements;  // one per input
  std::vector<PlannedUpload> uploads;            // in copy-stream order
  size_t slot_bytes = 0;
  size_t staging_bytes = 0;
  // The session records the slot's upload event on the copy stream after `uploads` and the
  // problem's kernels wait for it on the compute stream. One copy stream runs in order, so
  // the event also covers every earlier copy, up to copy_sequence `ready_after_copy`:
  // the uploads of the entries this problem finds already cached included.
  uint64_t ready_after_copy = 0;
  // The problem's cached inputs did not fit the budget next to the entries the problems in
  // flight use; they were placed anyway (see DeviceCachePlanner).
  bool over_budget = false;
};

struct DeviceCacheStats {
  uint64_t problems = 0;           // plans made
  uint64_t hits = 0;               // cached inputs found on the device
  uint64_t misses = 0;             // cached inputs uploaded
  uint64_t transient_uploads = 0;  // per-problem inputs uploaded
  uint64_t evictions = 0;
  uint64_t uploaded_bytes = 0;
  size_t peak_bytes = 0;           // largest cached total
  uint64_t over_budget_problems = 0;
};

// Plans the uploads of a sequence of problems, at most two in flight (the running one and
// the next one, uploaded ahead). Cached entries are evicted least recently used first, and
// only when no problem in flight uses them. A problem whose cached inputs do not fit the
// budget still runs: its inputs are placed over budget (the budget bounds what is kept
// between problems, not what one problem needs) and the excess is evicted by the next plan
// made once no problem in flight uses it.
class DeviceCachePlanner {
 public:
  static constexpr int kNumSlots = 2;
  static constexpr size_t kAlignment = 256;  // device and staging offsets

  explicit DeviceCachePlanner(size_t budget_bytes);

  // Throws std::logic_error when two problems are in flight already, std::invalid_argument
  // when a cached key comes with another size than it was cached with.
  UploadPlan Plan(const std::vector<DeviceInput>& inputs);
  // The problem's kernels have finished: its entries may be evicted, its slot reused.
  void Release(uint64_t ticket);

  bool Contains(const DeviceCacheKey& key) const { return entries_.count(key) > 0; }
  size_t cached_bytes() const { return cached_bytes_; }
  size_t num_entries() const { return entries_.size(); }
  size_t budget_bytes() const { return budget_bytes_; }
  int problems_in_flight() const { return static_cast<int>(in_flight_.size()); }
  const DeviceCacheStats& stats() const { return stats_; }

 private:
  struct Entry {
    uint64_t id = 0;
    size_t bytes = 0;
    uint64_t last_use = 0;
    int pins = 0;  // problems in flight that use it
    uint64_t copy_sequence = 0;
  };
  struct Flight {
    int slot = 0;
    std::vector<DeviceCacheKey> pinned;
  };
  using EntryMap = std::map<DeviceCacheKey, Entry>;
  // Evicts the least recently used unpinned entry into plan; false when there is none.
  bool EvictOne(UploadPlan* plan);
  void Pin(const DeviceCacheKey& key, Entry* entry, Flight* flight);
  // Steps of Plan for inputs[index]: found in the cache at `it` (pinned); not found (a new
  // entry, room made by evictions); its upload through the staging buffer.
  void PlaceHit(const DeviceInput& input, size_t index, EntryMap::iterator it, Flight* flight,
                UploadPlan* plan);
  void PlaceMiss(const DeviceInput& input, size_t index, Flight* flight, UploadPlan* plan);
  void QueueUpload(const DeviceInput& input, int index, UploadPlan* plan);

  size_t budget_bytes_;
  size_t cached_bytes_ = 0;
  uint64_t clock_ = 0;
  uint64_t next_entry_ = 0;
  uint64_t next_ticket_ = 0;
  uint64_t copy_sequence_ = 0;
  EntryMap entries_;
  std::map<uint64_t, Flight> in_flight_;
  DeviceCacheStats stats_;
};

// n rounded up to the device and staging alignment.
inline size_t AlignUp(size_t n) {
  constexpr size_t a = DeviceCachePlanner::kAlignment;
  return (n + a - 1) / a * a;
}

}  // namespace kernels
}  // namespace mpmvs

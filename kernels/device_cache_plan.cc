#include "kernels/device_cache_plan.h"

#include <algorithm>
#include <stdexcept>
#include <tuple>

namespace mpmvs {
namespace kernels {
namespace {

size_t ImageBytes(int width, int height) {
  return MakeStateLayout(width, height).num_pixels * sizeof(float);
}

}  // namespace

bool DeviceCacheKey::operator<(const DeviceCacheKey& other) const {
  return std::tie(image_id, kind, stage) < std::tie(other.image_id, other.kind, other.stage);
}

bool DeviceCacheKey::operator==(const DeviceCacheKey& other) const {
  return image_id == other.image_id && kind == other.kind && stage == other.stage;
}

std::string DescribeKey(const DeviceCacheKey& key) {
  if (key.kind == DeviceDataKind::kImage) return "image " + std::to_string(key.image_id);
  return "depth map " + std::to_string(key.image_id) + " of stage " + std::to_string(key.stage);
}

std::vector<DeviceInput> ListDeviceInputs(const PatchMatchProblem& problem,
                                          const PatchMatchSchedule& schedule) {
  std::vector<DeviceInput> inputs;
  auto add = [&](DeviceInputRole role, int source, const DeviceCacheKey* key, size_t bytes,
                 const void* host) {
    if (bytes == 0) return;
    // Checked here, before any plan records an entry that would then never be filled.
    if (!host && role != DeviceInputRole::kSourceViews) {
      throw std::invalid_argument("CUDA session: an input of the problem has no data");
    }
    DeviceInput in;
    in.role = role;
    in.source = source;
    in.cached = key != nullptr;
    if (key) in.key = *key;
    in.bytes = bytes;
    in.host = host;
    inputs.push_back(in);
  };
  auto image_key = [](uint32_t id) {
    DeviceCacheKey key;
    key.image_id = id;
    key.kind = DeviceDataKind::kImage;
    return key;
  };

  const DeviceCacheKey ref_key = image_key(problem.ref_image_id);
  add(DeviceInputRole::kRefImage, -1, problem.ref_image_id != kNoImageId ? &ref_key : nullptr,
      ImageBytes(problem.ref_image.width, problem.ref_image.height), problem.ref_image.data);
  if (problem.ref_image.chroma) {
    add(DeviceInputRole::kRefChroma, -1, nullptr,
        2 * ImageBytes(problem.ref_image.width, problem.ref_image.height), problem.ref_image.chroma);
  }
  for (size_t s = 0; s < problem.sources.size(); ++s) {
    const PatchMatchSource& src = problem.sources[s];
    const int index = static_cast<int>(s);
    const DeviceCacheKey key = image_key(src.image_id);
    const bool has_id = src.image_id != kNoImageId;
    add(DeviceInputRole::kSourceImage, index, has_id ? &key : nullptr,
        ImageBytes(src.image.width, src.image.height), src.image.data);
    if (schedule.geometric) {
      DeviceCacheKey depth_key;
      depth_key.image_id = src.image_id;
      depth_key.kind = DeviceDataKind::kDepthMap;
      depth_key.stage = problem.depth_maps_stage;
      const bool cached = has_id && problem.depth_maps_stage >= 0;
      add(DeviceInputRole::kSourceDepth, index, cached ? &depth_key : nullptr,
          ImageBytes(src.camera.width, src.camera.height), src.depth_map);
    }
  }
  const StateLayout layout =
      MakeStateLayout(problem.ref_camera.width, problem.ref_camera.height);
  if (problem.init_plane) {
    add(DeviceInputRole::kInitPlane, -1, nullptr, layout.plane_floats * sizeof(float),
        problem.init_plane);
  }
  if (problem.init_cost) {
    add(DeviceInputRole::kInitCost, -1, nullptr, layout.cost_floats * sizeof(float),
        problem.init_cost);
  }
  if (schedule.use_prior) {
    add(DeviceInputRole::kPriorPlane, -1, nullptr, layout.plane_floats * sizeof(float),
        problem.prior_plane);
    add(DeviceInputRole::kPriorLabel, -1, nullptr, layout.label_bytes, problem.prior_label);
  }
  add(DeviceInputRole::kSourceViews, -1, nullptr, problem.sources.size() * sizeof(SourceView),
      nullptr);
  return inputs;
}

bool SameDeviceInputs(const std::vector<DeviceInput>& a, const std::vector<DeviceInput>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].role != b[i].role || a[i].source != b[i].source || a[i].cached != b[i].cached ||
        !(a[i].key == b[i].key) || a[i].bytes != b[i].bytes || a[i].host != b[i].host) {
      return false;
    }
  }
  return true;
}

size_t DeviceCacheBudget(size_t cache_size_bytes, size_t free_device_bytes) {
  return std::min(cache_size_bytes, free_device_bytes / 2);
}

DeviceCachePlanner::DeviceCachePlanner(size_t budget_bytes) : budget_bytes_(budget_bytes) {}

void DeviceCachePlanner::Pin(const DeviceCacheKey& key, Entry* entry, Flight* flight) {
  entry->last_use = ++clock_;
  // A key listed twice by one problem is pinned once.
  if (std::find(flight->pinned.begin(), flight->pinned.end(), key) != flight->pinned.end()) return;
  ++entry->pins;
  flight->pinned.push_back(key);
}

bool DeviceCachePlanner::EvictOne(UploadPlan* plan) {
  auto victim = entries_.end();
  for (auto it = entries_.begin(); it != entries_.end(); ++it) {
    if (it->second.pins > 0) continue;  // a problem in flight reads it
    if (victim == entries_.end() || it->second.last_use < victim->second.last_use) victim = it;
  }
  if (victim == entries_.end()) return false;
  plan->evictions.push_back(victim->second.id);
  cached_bytes_ -= victim->second.bytes;
  entries_.erase(victim);
  ++stats_.evictions;
  return true;
}

void DeviceCachePlanner::QueueUpload(const DeviceInput& input, int index, UploadPlan* plan) {
  PlannedUpload up;
  up.input = index;
  up.bytes = input.bytes;
  up.staging_offset = AlignUp(plan->staging_bytes);
  plan->staging_bytes = up.staging_offset + up.bytes;
  up.copy_sequence = ++copy_sequence_;
  stats_.uploaded_bytes += up.bytes;
  plan->uploads.push_back(up);
  plan->placements[index].uploaded = true;
  plan->placements[index].copy_sequence = up.copy_sequence;
}

void DeviceCachePlanner::PlaceHit(const DeviceInput& input, size_t index, EntryMap::iterator it,
                                  Flight* flight, UploadPlan* plan) {
  if (it->second.bytes != input.bytes) {
    throw std::invalid_argument("device cache: " + DescribeKey(input.key) + " has " +
                                std::to_string(input.bytes) + " bytes but was cached with " +
                                std::to_string(it->second.bytes) +
                                " (one id must mean one image for the whole session)");
  }
  Pin(it->first, &it->second, flight);
  plan->placements[index].in_cache = true;
  plan->placements[index].entry = it->second.id;
  plan->placements[index].copy_sequence = it->second.copy_sequence;
  ++stats_.hits;
}

void DeviceCachePlanner::PlaceMiss(const DeviceInput& input, size_t index, Flight* flight,
                                   UploadPlan* plan) {
  while (cached_bytes_ + input.bytes > budget_bytes_ && EvictOne(plan)) {
  }
  if (cached_bytes_ + input.bytes > budget_bytes_) plan->over_budget = true;
  Entry entry;
  entry.id = ++next_entry_;
  entry.bytes = input.bytes;
  auto inserted = entries_.emplace(input.key, entry).first;
  cached_bytes_ += entry.bytes;
  Pin(inserted->first, &inserted->second, flight);
  plan->allocations.push_back(PlannedAllocation{entry.id, entry.bytes});
  plan->placements[index].in_cache = true;
  plan->placements[index].entry = entry.id;
  QueueUpload(input, static_cast<int>(index), plan);
  inserted->second.copy_sequence = plan->placements[index].copy_sequence;
  ++stats_.misses;
}

UploadPlan DeviceCachePlanner::Plan(const std::vector<DeviceInput>& inputs) {
  if (static_cast<int>(in_flight_.size()) >= kNumSlots) {
    throw std::logic_error(
        "device cache: two problems are in flight already (one running, one uploaded ahead); "
        "release one before planning another");
  }
  UploadPlan plan;
  plan.ticket = ++next_ticket_;
  bool slot_used[kNumSlots] = {false, false};
  for (const auto& flight : in_flight_) slot_used[flight.second.slot] = true;
  plan.slot = slot_used[0] ? 1 : 0;
  Flight flight;
  flight.slot = plan.slot;
  plan.placements.resize(inputs.size());

  // 1. Pin what is on the device already, so that making room below cannot evict it.
  for (size_t i = 0; i < inputs.size(); ++i) {
    if (!inputs[i].cached) continue;
    auto it = entries_.find(inputs[i].key);
    if (it != entries_.end()) PlaceHit(inputs[i], i, it, &flight, &plan);
  }

  // 2. Give back what an earlier over-budget problem left beyond the budget.
  while (cached_bytes_ > budget_bytes_ && EvictOne(&plan)) {
  }

  // 3. Upload the missing cached inputs, evicting least recently used entries for room.
  for (size_t i = 0; i < inputs.size(); ++i) {
    if (!inputs[i].cached || plan.placements[i].in_cache) continue;
    auto it = entries_.find(inputs[i].key);
    if (it != entries_.end()) {  // listed earlier by this problem and uploaded just now
      PlaceHit(inputs[i], i, it, &flight, &plan);
    } else {
      PlaceMiss(inputs[i], i, &flight, &plan);
    }
  }

  // 4. Per-problem inputs: packed into the slot buffer, uploaded every time.
  for (size_t i = 0; i < inputs.size(); ++i) {
    if (inputs[i].cached) continue;
    plan.placements[i].slot_offset = AlignUp(plan.slot_bytes);
    plan.slot_bytes = plan.placements[i].slot_offset + inputs[i].bytes;
    QueueUpload(inputs[i], static_cast<int>(i), &plan);
    ++stats_.transient_uploads;
  }

  plan.ready_after_copy = copy_sequence_;
  ++stats_.problems;
  if (plan.over_budget) ++stats_.over_budget_problems;
  stats_.peak_bytes = std::max(stats_.peak_bytes, cached_bytes_);
  in_flight_.emplace(plan.ticket, std::move(flight));
  return plan;
}

void DeviceCachePlanner::Release(uint64_t ticket) {
  auto it = in_flight_.find(ticket);
  if (it == in_flight_.end()) {
    throw std::logic_error("device cache: ticket " + std::to_string(ticket) + " is not in flight");
  }
  for (const DeviceCacheKey& key : it->second.pinned) {
    auto entry = entries_.find(key);
    if (entry != entries_.end()) --entry->second.pins;  // pinned entries are never evicted
  }
  in_flight_.erase(it);
}

}  // namespace kernels
}  // namespace mpmvs

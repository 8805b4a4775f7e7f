// The CUDA session's host-side plan (kernels/device_cache_plan.h), checked on the CPU: which
// inputs of a sequence of problems are uploaded, what the device cache keeps and evicts
// under a byte budget, that inputs of problems in flight are never evicted, and how the
// uploads are ordered before the runs that read them.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>
#include <vector>

#include "tests/kernel_schedule_util.h"
#include "kernels/device_cache_plan.h"

namespace mpmvs {
namespace kernels {
namespace {

constexpr size_t kImageBytes = 1000;
const float kHostData[4] = {1.f, 2.f, 3.f, 4.f};  // stands in for host images

DeviceCacheKey ImageKey(uint32_t id) {
  DeviceCacheKey key;
  key.image_id = id;
  key.kind = DeviceDataKind::kImage;
  return key;
}

DeviceInput CachedImage(uint32_t id, size_t bytes = kImageBytes) {
  DeviceInput in;
  in.role = DeviceInputRole::kSourceImage;
  in.cached = true;
  in.key = ImageKey(id);
  in.bytes = bytes;
  in.host = kHostData;
  return in;
}

DeviceInput PerProblem(DeviceInputRole role, size_t bytes) {
  DeviceInput in;
  in.role = role;
  in.bytes = bytes;
  in.host = kHostData;
  return in;
}

// A problem's inputs as ListDeviceInputs orders them: the reference image, the source
// images, then the per-problem source view array.
std::vector<DeviceInput> Problem(uint32_t ref, const std::vector<uint32_t>& sources) {
  std::vector<DeviceInput> inputs{CachedImage(ref)};
  inputs.front().role = DeviceInputRole::kRefImage;
  for (uint32_t s : sources) inputs.push_back(CachedImage(s));
  inputs.push_back(PerProblem(DeviceInputRole::kSourceViews, 96 * sources.size()));
  return inputs;
}

// Image ids uploaded by a plan.
std::set<uint32_t> UploadedImages(const UploadPlan& plan, const std::vector<DeviceInput>& inputs) {
  std::set<uint32_t> ids;
  for (const PlannedUpload& up : plan.uploads) {
    if (inputs[up.input].cached) ids.insert(inputs[up.input].key.image_id);
  }
  return ids;
}

// Cache entry of each cached image id of a plan.
std::map<uint32_t, uint64_t> EntriesOf(const UploadPlan& plan, const std::vector<DeviceInput>& inputs) {
  std::map<uint32_t, uint64_t> entries;
  for (size_t i = 0; i < inputs.size(); ++i) {
    if (inputs[i].cached) entries[inputs[i].key.image_id] = plan.placements[i].entry;
  }
  return entries;
}

// Four reference images of a stage whose source sets overlap (image 3 is new in the third).
const std::vector<std::pair<uint32_t, std::vector<uint32_t>>> kStage = {
    {0, {1, 2}}, {1, {0, 2}}, {2, {0, 1, 3}}, {3, {1, 2}}};

TEST(DeviceCachePlan, SharedSourcesAreUploadedOnceUnderALargeBudget) {
  // The session's order: problem k+1 is planned (uploaded ahead) while problem k runs, and
  // k is released when its kernels have finished.
  DeviceCachePlanner planner(100 * kImageBytes);
  std::vector<UploadPlan> plans;
  std::vector<std::vector<DeviceInput>> inputs;
  std::map<uint32_t, int> uploads_per_image;
  for (size_t k = 0; k < kStage.size(); ++k) {
    inputs.push_back(Problem(kStage[k].first, kStage[k].second));
    plans.push_back(planner.Plan(inputs.back()));
    for (uint32_t id : UploadedImages(plans.back(), inputs.back())) ++uploads_per_image[id];
    EXPECT_FALSE(plans.back().over_budget);
    EXPECT_TRUE(plans.back().evictions.empty());
    if (k > 0) planner.Release(plans[k - 1].ticket);
  }
  planner.Release(plans.back().ticket);
  EXPECT_EQ(planner.problems_in_flight(), 0);

  EXPECT_EQ(UploadedImages(plans[0], inputs[0]), (std::set<uint32_t>{0, 1, 2}));
  EXPECT_TRUE(UploadedImages(plans[1], inputs[1]).empty());
  EXPECT_EQ(UploadedImages(plans[2], inputs[2]), (std::set<uint32_t>{3}));
  EXPECT_TRUE(UploadedImages(plans[3], inputs[3]).empty());
  for (uint32_t id = 0; id < 4; ++id) EXPECT_EQ(uploads_per_image[id], 1) << "image " << id;

  const DeviceCacheStats& stats = planner.stats();
  EXPECT_EQ(stats.problems, 4u);
  EXPECT_EQ(stats.misses, 4u);
  EXPECT_EQ(stats.hits, 3u + 3u + 4u + 3u - 4u);  // cached inputs of all problems - misses
  EXPECT_EQ(stats.transient_uploads, 4u);        // the source view array, every problem
  EXPECT_EQ(stats.evictions, 0u);
  EXPECT_EQ(planner.num_entries(), 4u);
  EXPECT_EQ(planner.cached_bytes(), 4 * kImageBytes);
  // An image keeps its entry (device memory) whether it is a reference or a source.
  EXPECT_EQ(EntriesOf(plans[0], inputs[0]).at(1), EntriesOf(plans[1], inputs[1]).at(1));
  EXPECT_EQ(EntriesOf(plans[0], inputs[0]).at(2), EntriesOf(plans[3], inputs[3]).at(2));
}

TEST(DeviceCachePlan, EvictsLeastRecentlyUsedUnderASmallBudget) {
  DeviceCachePlanner planner(3 * kImageBytes);
  auto run = [&](const std::vector<DeviceInput>& in) {
    UploadPlan plan = planner.Plan(in);
    planner.Release(plan.ticket);  // one problem at a time
    return plan;
  };
  const std::vector<DeviceInput> first = {CachedImage(1), CachedImage(2), CachedImage(3)};
  const std::map<uint32_t, uint64_t> entry = EntriesOf(run(first), first);
  run({CachedImage(1)});  // image 1 is now the most recently used, image 2 the least

  const UploadPlan fourth = run({CachedImage(4)});
  EXPECT_EQ(fourth.evictions, std::vector<uint64_t>{entry.at(2)});
  EXPECT_TRUE(planner.Contains(ImageKey(1)));
  EXPECT_FALSE(planner.Contains(ImageKey(2)));
  EXPECT_TRUE(planner.Contains(ImageKey(3)));
  EXPECT_TRUE(planner.Contains(ImageKey(4)));
  EXPECT_EQ(planner.cached_bytes(), 3 * kImageBytes);

  // Image 2 comes back: uploaded again, in place of image 3 (now the least recently used).
  const std::vector<DeviceInput> again = {CachedImage(2)};
  const UploadPlan fifth = run(again);
  EXPECT_EQ(UploadedImages(fifth, again), std::set<uint32_t>{2});
  EXPECT_EQ(fifth.evictions, std::vector<uint64_t>{entry.at(3)});
  EXPECT_EQ(planner.stats().evictions, 2u);
  EXPECT_LE(planner.cached_bytes(), planner.budget_bytes());
}

TEST(DeviceCachePlan, NeverEvictsInputsOfProblemsInFlight) {
  DeviceCachePlanner planner(4 * kImageBytes);
  const std::vector<DeviceInput> running = {CachedImage(1), CachedImage(2), CachedImage(3)};
  const UploadPlan run = planner.Plan(running);
  const std::map<uint32_t, uint64_t> running_entries = EntriesOf(run, running);

  // Uploaded ahead while `running` runs: images 1-3 are in use, so image 5 goes over budget
  // rather than evicting one of them.
  const std::vector<DeviceInput> ahead_inputs = {CachedImage(4), CachedImage(5)};
  const UploadPlan ahead = planner.Plan(ahead_inputs);
  EXPECT_TRUE(ahead.evictions.empty());
  EXPECT_TRUE(ahead.over_budget);
  for (uint32_t id : {1, 2, 3, 4, 5}) EXPECT_TRUE(planner.Contains(ImageKey(id))) << id;
  EXPECT_EQ(planner.cached_bytes(), 5 * kImageBytes);
  EXPECT_EQ(planner.stats().over_budget_problems, 1u);

  // `running` finished, `ahead` runs, a third problem is planned: the cache shrinks back to
  // the budget by evicting images 1 and 2 (least recently used, no longer in use); 4 and 5,
  // which `ahead` uses, stay.
  planner.Release(run.ticket);
  const UploadPlan third = planner.Plan({CachedImage(6)});
  EXPECT_EQ(third.evictions, (std::vector<uint64_t>{running_entries.at(1), running_entries.at(2)}));
  EXPECT_FALSE(third.over_budget);
  EXPECT_TRUE(planner.Contains(ImageKey(4)));
  EXPECT_TRUE(planner.Contains(ImageKey(5)));
  EXPECT_EQ(planner.cached_bytes(), 4 * kImageBytes);
  planner.Release(ahead.ticket);
  planner.Release(third.ticket);
}

TEST(DeviceCachePlan, ProblemLargerThanTheBudgetRunsOverBudgetThenShrinksBack) {
  // Documented fallback: the problem still gets all its inputs; the excess goes with the
  // next plan made once no problem in flight uses it.
  DeviceCachePlanner planner(kImageBytes + kImageBytes / 2);
  const std::vector<DeviceInput> big = {CachedImage(1), CachedImage(2), CachedImage(3)};
  const UploadPlan plan = planner.Plan(big);
  EXPECT_EQ(UploadedImages(plan, big), (std::set<uint32_t>{1, 2, 3}));
  EXPECT_TRUE(plan.over_budget);
  EXPECT_TRUE(plan.evictions.empty());
  EXPECT_EQ(planner.cached_bytes(), 3 * kImageBytes);

  // Uploaded ahead while the big problem runs: nothing of it may go, not even to get back
  // under the budget.
  const UploadPlan ahead = planner.Plan({CachedImage(4)});
  EXPECT_TRUE(ahead.evictions.empty());
  EXPECT_TRUE(ahead.over_budget);
  planner.Release(plan.ticket);
  planner.Release(ahead.ticket);

  const UploadPlan next = planner.Plan({CachedImage(5)});
  EXPECT_EQ(next.evictions.size(), 4u);
  EXPECT_FALSE(next.over_budget);
  EXPECT_EQ(planner.cached_bytes(), kImageBytes);
  EXPECT_EQ(planner.stats().over_budget_problems, 2u);
  EXPECT_EQ(planner.stats().peak_bytes, 4 * kImageBytes);
  planner.Release(next.ticket);

  // A budget of 0 keeps nothing but the inputs of the last problem, until the next plan.
  DeviceCachePlanner none(0);
  const std::vector<DeviceInput> first = {CachedImage(1)}, second = {CachedImage(2)};
  const UploadPlan a = none.Plan(first);
  EXPECT_TRUE(a.over_budget);
  none.Release(a.ticket);
  const UploadPlan b = none.Plan(second);
  EXPECT_EQ(b.evictions, std::vector<uint64_t>{a.placements[0].entry});
  EXPECT_EQ(UploadedImages(b, second), std::set<uint32_t>{2});
  EXPECT_FALSE(none.Contains(ImageKey(1)));
  EXPECT_EQ(none.cached_bytes(), kImageBytes);
  none.Release(b.ticket);
}

TEST(DeviceCachePlan, AtMostTwoProblemsInFlightOnAlternatingSlots) {
  DeviceCachePlanner planner(100 * kImageBytes);
  const UploadPlan a = planner.Plan(Problem(0, {1}));
  const UploadPlan b = planner.Plan(Problem(1, {0}));
  EXPECT_EQ(a.slot, 0);
  EXPECT_EQ(b.slot, 1);
  EXPECT_THROW(planner.Plan(Problem(2, {0})), std::logic_error);
  planner.Release(a.ticket);
  const UploadPlan c = planner.Plan(Problem(2, {0}));
  EXPECT_EQ(c.slot, 0);  // the slot of the finished problem, not the one uploaded ahead
  planner.Release(b.ticket);
  EXPECT_THROW(planner.Release(b.ticket), std::logic_error);
  planner.Release(c.ticket);
  EXPECT_EQ(planner.problems_in_flight(), 0);
}

TEST(DeviceCachePlan, UploadsAreOrderedBeforeTheRunThatReadsThem) {
  DeviceCachePlanner planner(100 * kImageBytes);
  uint64_t previous_ready = 0;
  std::vector<uint64_t> in_flight;
  for (const auto& ref : kStage) {
    const std::vector<DeviceInput> inputs = Problem(ref.first, ref.second);
    const UploadPlan plan = planner.Plan(inputs);
    for (const PlannedUpload& up : plan.uploads) {
      // In copy-stream order, after everything the previous problem waits for.
      EXPECT_GT(up.copy_sequence, previous_ready);
      EXPECT_LE(up.copy_sequence, plan.ready_after_copy);
    }
    for (size_t i = 0; i < inputs.size(); ++i) {
      const DeviceInputPlacement& at = plan.placements[i];
      // Every input, uploaded now or found in the cache, was filled by a copy that the
      // problem's ready event covers.
      EXPECT_GT(at.copy_sequence, 0u);
      EXPECT_LE(at.copy_sequence, plan.ready_after_copy);
      if (!at.uploaded) EXPECT_LE(at.copy_sequence, previous_ready) << "a hit was uploaded earlier";
    }
    previous_ready = plan.ready_after_copy;
    in_flight.push_back(plan.ticket);
    if (in_flight.size() == 2) {
      planner.Release(in_flight.front());
      in_flight.erase(in_flight.begin());
    }
  }
}

TEST(DeviceCachePlan, StagingAndSlotRangesAreAlignedAndDisjoint) {
  DeviceCachePlanner planner(100 * kImageBytes);
  std::vector<DeviceInput> inputs = {CachedImage(1, 1001), CachedImage(2, 77),
                                     PerProblem(DeviceInputRole::kInitPlane, 4 * 333),
                                     PerProblem(DeviceInputRole::kInitCost, 333),
                                     PerProblem(DeviceInputRole::kPriorLabel, 5),
                                     PerProblem(DeviceInputRole::kSourceViews, 2 * 96)};
  const UploadPlan plan = planner.Plan(inputs);
  ASSERT_EQ(plan.uploads.size(), inputs.size());
  ASSERT_EQ(plan.allocations.size(), 2u);
  std::vector<std::pair<size_t, size_t>> staging, slot;
  for (const PlannedUpload& up : plan.uploads) {
    EXPECT_EQ(up.staging_offset % DeviceCachePlanner::kAlignment, 0u);
    EXPECT_LE(up.staging_offset + up.bytes, plan.staging_bytes);
    staging.emplace_back(up.staging_offset, up.staging_offset + up.bytes);
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    EXPECT_EQ(plan.placements[i].in_cache, inputs[i].cached);
    if (inputs[i].cached) continue;
    EXPECT_EQ(plan.placements[i].slot_offset % DeviceCachePlanner::kAlignment, 0u);
    EXPECT_LE(plan.placements[i].slot_offset + inputs[i].bytes, plan.slot_bytes);
    slot.emplace_back(plan.placements[i].slot_offset, plan.placements[i].slot_offset + inputs[i].bytes);
  }
  for (auto* ranges : {&staging, &slot}) {
    std::sort(ranges->begin(), ranges->end());
    for (size_t k = 1; k < ranges->size(); ++k) {
      EXPECT_LE((*ranges)[k - 1].second, (*ranges)[k].first) << "overlapping ranges";
    }
  }
  EXPECT_EQ(slot.size(), 4u);
  planner.Release(plan.ticket);
}

TEST(DeviceCachePlan, RepeatedInputOfOneProblemIsUploadedOnce) {
  DeviceCachePlanner planner(100 * kImageBytes);
  const std::vector<DeviceInput> inputs = {CachedImage(7), CachedImage(8), CachedImage(7)};
  const UploadPlan plan = planner.Plan(inputs);
  EXPECT_EQ(plan.uploads.size(), 2u);
  EXPECT_EQ(plan.allocations.size(), 2u);
  EXPECT_EQ(plan.placements[0].entry, plan.placements[2].entry);
  EXPECT_TRUE(plan.placements[0].uploaded);
  EXPECT_FALSE(plan.placements[2].uploaded);
  planner.Release(plan.ticket);
  // Pinned once, released once: evictable afterwards.
  DeviceCachePlanner small(kImageBytes);
  const UploadPlan a = small.Plan({CachedImage(7), CachedImage(7)});
  small.Release(a.ticket);
  EXPECT_EQ(small.Plan({CachedImage(9)}).evictions.size(), 1u);
}

TEST(DeviceCachePlan, SameIdWithAnotherSizeIsRejected) {
  DeviceCachePlanner planner(100 * kImageBytes);
  const UploadPlan a = planner.Plan({CachedImage(1, 100)});
  planner.Release(a.ticket);
  EXPECT_THROW(planner.Plan({CachedImage(1, 200)}), std::invalid_argument);
  EXPECT_EQ(planner.problems_in_flight(), 0);
}

TEST(DeviceCachePlan, BudgetIsCacheSizeCappedByHalfTheFreeDeviceMemory) {
  const size_t GB = size_t(1) << 30;
  EXPECT_EQ(DeviceCacheBudget(32 * GB, 8 * GB), 4 * GB);
  EXPECT_EQ(DeviceCacheBudget(1 * GB, 8 * GB), 1 * GB);
  EXPECT_EQ(DeviceCacheBudget(1 * GB, 0), 0u);
}

// ---------------------------------------------------------------------------------------
// Inputs of a PatchMatchProblem

struct ListedProblem {
  std::vector<float> image = std::vector<float>(12 * 10, 1.f);
  std::vector<float> depth = std::vector<float>(12 * 10, 2.f);
  std::vector<float> plane = std::vector<float>(4 * 12 * 10, 0.f);
  std::vector<float> cost = std::vector<float>(12 * 10, 0.f);
  std::vector<uint8_t> label = std::vector<uint8_t>(12 * 10, 1);
  PatchMatchProblem problem;

  ListedProblem() {
    problem.ref_image_id = 0;
    problem.ref_camera.width = 12;
    problem.ref_camera.height = 10;
    problem.ref_image = ImageView{image.data(), 12, 10};
    for (uint32_t id : {1u, 2u}) {
      PatchMatchSource src;
      src.image = ImageView{image.data(), 12, 10};
      src.camera = problem.ref_camera;
      src.depth_map = depth.data();
      src.image_id = id;
      problem.sources.push_back(src);
    }
    problem.depth_maps_stage = 1;
    problem.init_plane = plane.data();
    problem.init_cost = cost.data();
    problem.prior_plane = plane.data();
    problem.prior_label = label.data();
  }
};

TEST(DeviceCachePlan, ListsInputsWithCacheKeysFromTheProblem) {
  ListedProblem lp;
  PatchMatchSchedule geometric_prior = mpmvs::test::ScheduleWithOptionDefaults();
  geometric_prior.geometric = true;
  geometric_prior.use_prior = true;
  const std::vector<DeviceInput> inputs = ListDeviceInputs(lp.problem, geometric_prior);
  using R = DeviceInputRole;
  const std::vector<R> roles = {R::kRefImage,   R::kSourceImage, R::kSourceDepth, R::kSourceImage,
                                R::kSourceDepth, R::kInitPlane,   R::kInitCost,    R::kPriorPlane,
                                R::kPriorLabel,  R::kSourceViews};
  ASSERT_EQ(inputs.size(), roles.size());
  for (size_t i = 0; i < roles.size(); ++i) EXPECT_EQ(inputs[i].role, roles[i]) << i;
  EXPECT_EQ(inputs[0].key, ImageKey(0));
  EXPECT_EQ(inputs[3].key, ImageKey(2));
  EXPECT_EQ(inputs[3].source, 1);
  EXPECT_EQ(inputs[4].key.kind, DeviceDataKind::kDepthMap);
  EXPECT_EQ(inputs[4].key.image_id, 2u);
  EXPECT_EQ(inputs[4].key.stage, 1);
  for (size_t i = 0; i < 5; ++i) EXPECT_TRUE(inputs[i].cached) << i;
  for (size_t i = 5; i < inputs.size(); ++i) EXPECT_FALSE(inputs[i].cached) << i;
  EXPECT_EQ(inputs[0].bytes, 12u * 10u * sizeof(float));
  EXPECT_EQ(inputs[5].bytes, 4u * 12u * 10u * sizeof(float));
  EXPECT_EQ(inputs[8].bytes, 12u * 10u);
  EXPECT_EQ(inputs[9].bytes, 2 * sizeof(SourceView));
  EXPECT_EQ(inputs[9].host, nullptr);
  EXPECT_EQ(inputs[2].host, lp.depth.data());

  // A photometric schedule has no depth maps and no prior.
  PatchMatchSchedule photometric = mpmvs::test::ScheduleWithOptionDefaults();
  EXPECT_EQ(ListDeviceInputs(lp.problem, photometric).size(), 6u);
  // An input without host data is refused before any plan records an entry for it.
  ListedProblem missing_depth;
  missing_depth.problem.sources[1].depth_map = nullptr;
  EXPECT_THROW(ListDeviceInputs(missing_depth.problem, geometric_prior), std::invalid_argument);
  // A reference chroma guide comes right after the reference image, for this problem only.
  ListedProblem with_chroma;
  const std::vector<float> chroma(2 * 12 * 10, 1.f);
  with_chroma.problem.ref_image.chroma = chroma.data();
  const std::vector<DeviceInput> chroma_inputs = ListDeviceInputs(with_chroma.problem, photometric);
  ASSERT_EQ(chroma_inputs.size(), 7u);
  EXPECT_EQ(chroma_inputs[1].role, R::kRefChroma);
  EXPECT_FALSE(chroma_inputs[1].cached);
  EXPECT_EQ(chroma_inputs[1].bytes, 2u * 12u * 10u * sizeof(float));
  EXPECT_EQ(chroma_inputs[1].host, chroma.data());

  // The next stage's depth maps of the same views are new entries; the images are hits.
  DeviceCachePlanner planner(100 * kImageBytes);
  const UploadPlan stage1 = planner.Plan(inputs);
  planner.Release(stage1.ticket);
  ListedProblem next_stage;
  next_stage.problem.depth_maps_stage = 2;
  const std::vector<DeviceInput> next_inputs = ListDeviceInputs(next_stage.problem, geometric_prior);
  const UploadPlan stage2 = planner.Plan(next_inputs);
  std::multiset<DeviceInputRole> uploaded;
  for (const PlannedUpload& up : stage2.uploads) {
    if (next_inputs[up.input].cached) uploaded.insert(next_inputs[up.input].role);
  }
  EXPECT_EQ(uploaded, (std::multiset<R>{R::kSourceDepth, R::kSourceDepth}));
  planner.Release(stage2.ticket);

  // No ids (or no depth stage): uploaded for the problem only, never cached.
  ListedProblem anonymous;
  anonymous.problem.ref_image_id = kNoImageId;
  for (PatchMatchSource& s : anonymous.problem.sources) s.image_id = kNoImageId;
  for (const DeviceInput& in : ListDeviceInputs(anonymous.problem, geometric_prior)) {
    EXPECT_FALSE(in.cached);
  }
  ListedProblem no_stage;
  no_stage.problem.depth_maps_stage = -1;
  for (const DeviceInput& in : ListDeviceInputs(no_stage.problem, geometric_prior)) {
    EXPECT_EQ(in.cached, in.role == R::kRefImage || in.role == R::kSourceImage);
  }
}

TEST(DeviceCachePlan, SameDeviceInputsComparesKeysSizesAndHostMemory) {
  ListedProblem lp;
  PatchMatchSchedule schedule = mpmvs::test::ScheduleWithOptionDefaults();
  const std::vector<DeviceInput> a = ListDeviceInputs(lp.problem, schedule);
  EXPECT_TRUE(SameDeviceInputs(a, ListDeviceInputs(lp.problem, schedule)));
  ListedProblem other;  // same ids and sizes, other host memory
  EXPECT_FALSE(SameDeviceInputs(a, ListDeviceInputs(other.problem, schedule)));
  PatchMatchSchedule geometric = mpmvs::test::ScheduleWithOptionDefaults();
  geometric.geometric = true;
  EXPECT_FALSE(SameDeviceInputs(a, ListDeviceInputs(lp.problem, geometric)));
}

}  // namespace
}  // namespace kernels
}  // namespace mpmvs

// What StageStore derives from a view's image once for every reference that uses it.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/plan/run_plan.h"
#include "colmap_ext/prior/image_noise.h"
#include "colmap_ext/store/result_fingerprint.h"
#include "colmap_ext/store/stage_store.h"
#include "colmap_ext/store/state_record.h"
#include "colmap_ext/util/file_util.h"
#include "kernels/patch_match.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

// The small plane scene (3 views, 96x72) with the default run plan and its reference
// problems; Store() makes a StageStore of the problems as they are then.
struct PlaneSceneRun {
  test::TempDir tmp;
  MpMvsWorkspaceIo io;
  DenseWorkspace workspace;
  const PatchMatchStereoOptions colmap_options;
  const MpMvsOptions options;
  const RunPlan plan = MakeRunPlan(colmap_options, options, false);
  std::vector<ReferenceProblem> problems;

  PlaneSceneRun() {
    test::WriteSmallPlaneScene(tmp / "ws", 96, 72, 3);
    workspace = io.Load(tmp / "ws", -1);
    problems = LoadReferenceProblems(workspace, "", colmap_options, plan.sources_per_reference).runnable;
  }
  std::unique_ptr<StageStore> Store() {
    return std::make_unique<StageStore>(workspace, &io, plan, problems,
                                        MakeResultFingerprint(colmap_options, options, workspace, problems));
  }
};

// The prior's plain-window masks and noise variances: the same as computing them afresh
// from the view's image, and computed once (the second request gets the same object).
TEST(StageStore, PlainWindowMasksAreThoseOfTheImageAndComputedOnce) {
  PlaneSceneRun run;
  ASSERT_EQ(run.problems.size(), 3u);
  const std::unique_ptr<StageStore> made = run.Store();
  StageStore& store = *made;
  const DenseWorkspace& workspace = run.workspace;

  for (int view = 0; view < 3; ++view) {
    const GrayImage image = run.io.ReadGray(workspace, view);
    const float noise = EstimateNoiseVariance(image);
    EXPECT_EQ(store.NoiseVariance(view), noise) << view;
    const kernels::ImageView grey{image.data.data(), image.width, image.height};
    for (int scale : {0, 1}) {
      const std::vector<uint8_t> expected =
          kernels::PlainWindowMaskCpu(grey, kernels::WindowForScale(scale), noise, 1);
      const std::shared_ptr<const std::vector<uint8_t>> mask = store.PlainWindows(view, scale);
      EXPECT_EQ(*mask, expected) << "view " << view << ", scale " << scale;
      EXPECT_EQ(store.PlainWindows(view, scale), mask) << "view " << view << ", scale " << scale;
    }
  }
  // The scales differ somewhere (a test of a mask that ignored the scale would pass above).
  EXPECT_NE(*store.PlainWindows(0, 0), *store.PlainWindows(0, 1));
}

// The depth check's results made with another tolerance (the sparse model's poses changed)
// are not resumed; those made with the same are, and so are every other stage's, which do not
// depend on it.
TEST(StageStore, OnlyTheDepthChecksStateDependsOnItsTolerance) {
  PlaneSceneRun run;
  ASSERT_EQ(run.plan.pipeline.stages.back().name, "depth_check");
  ASSERT_FALSE(run.problems.empty());
  const DenseWorkspace& workspace = run.workspace;
  auto set_tolerance = [&](float tolerance) {
    for (ReferenceProblem& q : run.problems) q.depth_check_tolerance = tolerance;
  };
  auto store_with = [&](float tolerance) {
    set_tolerance(tolerance);
    return run.Store();
  };
  const ReferenceProblem& p = run.problems[0];
  kernels::PatchMatchResult state;
  state.width = workspace.views[p.ref].width;
  state.height = workspace.views[p.ref].height;
  const size_t n = static_cast<size_t>(state.width) * state.height;
  const float depth = 0.5f * (p.depth_min + p.depth_max);
  for (size_t i = 0; i < n; ++i) state.plane.insert(state.plane.end(), {0.f, 0.f, -1.f, depth});
  state.cost.assign(n, 0.5f);
  state.photo_cost.assign(n, 0.5f);
  state.geo_error.assign(n, 0.f);
  state.view_mask.assign(n, 1u);
  CreateDirectories(workspace.IntermediateDir());
  for (const char* stage : {"geometric3", "depth_check"}) {
    store_with(kDepthCheckBaseTolerance)->WriteState(p.ref, stage, state);
  }
  EXPECT_TRUE(store_with(kDepthCheckBaseTolerance)->HasState(p.ref, "depth_check"));
  // Even at 1 % the depth check's record names its inputs apart from the stage before it:
  // each image's tolerance follows its agreement with its sources, so the depth checks of
  // builds from before that (whose records named the same inputs as geometric3's) are made
  // again.
  StateRecord geometric, checked;
  std::string why;
  const auto store = store_with(kDepthCheckBaseTolerance);
  ASSERT_TRUE(ReadStateRecord(store->StateRecordPath(p.ref, "geometric3"), &geometric, &why)) << why;
  ASSERT_TRUE(ReadStateRecord(store->StateRecordPath(p.ref, "depth_check"), &checked, &why)) << why;
  EXPECT_NE(checked.inputs, geometric.inputs);
  EXPECT_FALSE(store_with(0.02f)->HasState(p.ref, "depth_check"));
  EXPECT_TRUE(store_with(0.02f)->HasState(p.ref, "geometric3"));
  store_with(0.02f)->WriteState(p.ref, "depth_check", state);
  EXPECT_TRUE(store_with(0.02f)->HasState(p.ref, "depth_check"));
  EXPECT_FALSE(store_with(0.03f)->HasState(p.ref, "depth_check"));
  EXPECT_TRUE(store_with(0.03f)->HasState(p.ref, "geometric3"));
  // Runs that share the workspace at once must agree on it too (work_claims.h).
  auto tag_with = [&](float tolerance) {
    set_tolerance(tolerance);
    return MakeResultFingerprint(run.colmap_options, run.options, workspace, run.problems).RunTag();
  };
  EXPECT_NE(tag_with(0.02f), tag_with(kDepthCheckBaseTolerance));
  EXPECT_EQ(tag_with(0.02f), tag_with(0.02f));
}

}  // namespace
}  // namespace mpmvs

// The stage chain of each planar-prior mode (plan/stage_plan.h).
#include <gtest/gtest.h>

#include <cmath>

#include "colmap_ext/plan/stage_plan.h"

namespace mpmvs {
namespace {

std::string Chain(const PipelinePlan& plan) {
  std::string text;
  for (const StagePlan& st : plan.stages) {
    text += (text.empty() ? "" : " ") + st.name + "<" +
            (st.input < 0 ? std::string("-") : plan.stages[st.input].name);
  }
  return text;
}

TEST(StagePlan, EachPriorRoundBuildsOnThePreviousGeometricPass) {
  PatchMatchStereoOptions colmap;
  MpMvsOptions options;
  options.prior_rounds = 1;
  EXPECT_EQ(Chain(MakePipelinePlan(colmap, options)),
            "photometric<- geometric1<photometric prior<geometric1 geometric2<prior depth_check<geometric2");
  options.prior_rounds = 2;
  const PipelinePlan two = MakePipelinePlan(colmap, options);
  EXPECT_EQ(Chain(two), "photometric<- geometric1<photometric prior<geometric1 geometric2<prior "
                        "prior2<geometric2 geometric3<prior2 depth_check<geometric3");
  EXPECT_EQ(two.stages[two.geometric_output].name, "depth_check");
  EXPECT_EQ(two.stages[two.geometric_output].kind, StageKind::kDepthCheck);
  EXPECT_EQ(two.stages[two.geometric_output].confirming_views, 1);
  EXPECT_TRUE(two.stages[two.geometric_output].schedule.geometric);  // reads its sources' results
  EXPECT_TRUE(two.stages[two.geometric_output].schedule.iterations.empty());
  EXPECT_EQ(two.stages[two.photometric_output].name, "photometric");
  EXPECT_EQ(two.stages[4].kind, StageKind::kPlanarPrior);
  EXPECT_TRUE(two.stages[4].prior_geometric_selection);
  // The other modes have one prior at most: rounds do not apply.
  options.planar_prior = "photometric";
  EXPECT_EQ(Chain(MakePipelinePlan(colmap, options)),
            "photometric<- prior<photometric geometric1<prior geometric2<geometric1 depth_check<geometric2");
  options.planar_prior = "none";
  EXPECT_EQ(Chain(MakePipelinePlan(colmap, options)),
            "photometric<- geometric1<photometric geometric2<geometric1 depth_check<geometric2");
  // Without the check (the paper) the last geometric pass writes the maps.
  options.depth_check_views = 0;
  const PipelinePlan paper = MakePipelinePlan(colmap, options);
  EXPECT_EQ(Chain(paper), "photometric<- geometric1<photometric geometric2<geometric1");
  EXPECT_EQ(paper.stages[paper.geometric_output].name, "geometric2");
  // Without geometric stages there is nothing to check against.
  options.depth_check_views = 1;
  colmap.geom_consistency = false;
  EXPECT_EQ(Chain(MakePipelinePlan(colmap, options)), "photometric<-");
}

// The photometric schedule: iterations (scale, tau index, at half resolution) as written.
std::string PhotometricIterations(const MpMvsOptions& options) {
  const PipelinePlan plan = MakePipelinePlan(PatchMatchStereoOptions(), options);
  std::string text;
  for (const kernels::IterationSpec& it : plan.stages[0].schedule.iterations) {
    text += (text.empty() ? "" : " ") + std::to_string(it.window_scale) + std::to_string(it.tau_index) +
            (it.half_resolution ? "h" : "");
  }
  return text;
}

TEST(StagePlan, TheLargestWindowScalesRunAtHalfResolutionWithOneScaleLess) {
  MpMvsOptions options;
  options.iterations_per_scale = 2;
  options.half_resolution_scales = 0;
  EXPECT_EQ(PhotometricIterations(options), "20 21 10 11 00 01");  // the paper's mPM
  options.half_resolution_scales = 1;
  EXPECT_EQ(PhotometricIterations(options), "10h 11h 10 11 00 01");
  options.half_resolution_scales = 2;
  EXPECT_EQ(PhotometricIterations(options), "10h 11h 00h 01h 00 01");
  options.half_resolution_scales = 4;  // never the finest scale
  EXPECT_EQ(PhotometricIterations(options), "10h 11h 00h 01h 00 01");
  options.max_window_scale = 0;
  EXPECT_EQ(PhotometricIterations(options), "00 01");
  // Only the photometric stage: the later ones start from full-resolution maps.
  options.max_window_scale = 2;
  const PipelinePlan plan = MakePipelinePlan(PatchMatchStereoOptions(), options);
  for (const StagePlan& stage : plan.stages) {
    if (stage.kind == StageKind::kPhotometric) continue;
    for (const kernels::IterationSpec& it : stage.schedule.iterations) EXPECT_FALSE(it.half_resolution) << stage.name;
  }
}

TEST(StagePlan, OnlyTheFirstPriorRoundBuildsOnAnEstimateWithoutPrior) {
  MpMvsOptions options;
  const PipelinePlan plan = MakePipelinePlan(PatchMatchStereoOptions(), options);
  std::string follows;
  for (const StagePlan& st : plan.stages) follows += BuildsOnPrior(plan, st.input) ? "1" : "0";
  // photometric geometric1 prior geometric2 prior2 geometric3 depth_check
  EXPECT_EQ(follows, "0001111");
  EXPECT_FALSE(BuildsOnPrior(plan, -1));
}

TEST(StagePlan, PriorRoundsAndVertexBendAreChecked) {
  MpMvsOptions options;
  std::string error;
  options.prior_rounds = 0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("prior_rounds"), std::string::npos) << error;
  options.prior_rounds = 5;
  EXPECT_FALSE(options.Check(&error));
  options.prior_rounds = 4;
  EXPECT_TRUE(options.Check(&error)) << error;
  options.prior_vertex_bend = -0.01;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("prior_vertex_bend"), std::string::npos) << error;
  options.prior_vertex_bend = std::nan("");
  EXPECT_FALSE(options.Check(&error));
  options.prior_vertex_bend = 1.5;
  EXPECT_FALSE(options.Check(&error));
  options.prior_vertex_bend = 0;  // off: the paper
  EXPECT_TRUE(options.Check(&error)) << error;
}

TEST(StagePlan, EveryPatchMatchStageSkipsSettledPixelsAsTheOptionSays) {
  MpMvsOptions options;
  PatchMatchStereoOptions colmap_options;
  for (int skips : {0, 2}) {
    options.settled_pixel_skips = skips;
    const PipelinePlan plan = MakePipelinePlan(colmap_options, options);
    for (const StagePlan& st : plan.stages) EXPECT_EQ(st.schedule.settled_skips, skips) << st.name;
  }
  std::string error;
  options.settled_pixel_skips = -1;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("settled_pixel_skips"), std::string::npos) << error;
  options.settled_pixel_skips = 256;
  EXPECT_FALSE(options.Check(&error));
  options.settled_pixel_skips = 255;
  EXPECT_TRUE(options.Check(&error)) << error;
  EXPECT_EQ(MpMvsOptions().settled_pixel_skips, 0);  // the paper's schedule by default
}

}  // namespace
}  // namespace mpmvs

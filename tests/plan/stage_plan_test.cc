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

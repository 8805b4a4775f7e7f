// The stage chain of each planar-prior mode (pipeline/stage_plan.h).
#include <gtest/gtest.h>

#include "colmap_ext/pipeline/stage_plan.h"

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
            "photometric<- geometric1<photometric prior<geometric1 geometric2<prior");
  options.prior_rounds = 2;
  const PipelinePlan two = MakePipelinePlan(colmap, options);
  EXPECT_EQ(Chain(two), "photometric<- geometric1<photometric prior<geometric1 geometric2<prior "
                        "prior2<geometric2 geometric3<prior2");
  EXPECT_EQ(two.stages[two.geometric_output].name, "geometric3");
  EXPECT_EQ(two.stages[two.photometric_output].name, "photometric");
  EXPECT_EQ(two.stages[4].kind, StageKind::kPlanarPrior);
  EXPECT_TRUE(two.stages[4].prior_geometric_selection);
  // The other modes have one prior at most: rounds do not apply.
  options.planar_prior = "photometric";
  EXPECT_EQ(Chain(MakePipelinePlan(colmap, options)),
            "photometric<- prior<photometric geometric1<prior geometric2<geometric1");
  options.planar_prior = "none";
  EXPECT_EQ(Chain(MakePipelinePlan(colmap, options)), "photometric<- geometric1<photometric geometric2<geometric1");
}

TEST(StagePlan, PriorRoundsAreChecked) {
  MpMvsOptions options;
  std::string error;
  options.prior_rounds = 0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("prior_rounds"), std::string::npos) << error;
  options.prior_rounds = 5;
  EXPECT_FALSE(options.Check(&error));
  options.prior_rounds = 4;
  EXPECT_TRUE(options.Check(&error)) << error;
}

}  // namespace
}  // namespace mpmvs

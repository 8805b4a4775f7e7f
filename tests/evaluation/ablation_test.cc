// The ablation rows differ in what they run, not only in name: checked from each row's run
// statistics (window sides and propagation pattern per iteration, stage order).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "colmap_ext/evaluation/ablation.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

TEST(Ablation, RowsRunWhatTheirNamesSay) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp / "scene", 64, 48, 3);
  AblationOptions options;
  options.workspace_path = tmp / "scene";
  options.gt_path = tmp / "scene/gt";
  options.output_path = tmp / "rows";
  options.fuse = false;
  options.options.write_pictures = "none";
  const std::vector<AblationRowResult> rows = RunAblation(options);
  ASSERT_EQ(rows.size(), 6u);

  struct Expected {
    const char* name;
    std::vector<int> sides;
    kernels::PatternKind pattern;
    std::vector<std::string> stages;
  };
  const std::vector<int> single(3, 11);
  // The default runs the 41 and 21 px windows as the 21 and 11 px ones at half resolution.
  const std::vector<int> multi = {21, 21, 21, 11, 11, 11, 11, 11, 11};
  const std::vector<std::string> plain = {"photometric", "geometric1", "geometric2", "depth_check"};
  const std::vector<std::string> pp = {"photometric", "prior", "geometric1", "geometric2", "depth_check"};
  // Default prior_rounds 2: a second prior from geometric2, then geometric3.
  const std::vector<std::string> gp = {"photometric", "geometric1", "prior", "geometric2",
                                       "prior2",      "geometric3", "depth_check"};
  const std::vector<Expected> expected = {
      {"ACMH", single, kernels::PatternKind::kAcmh, plain},
      {"mPM+ACMH", multi, kernels::PatternKind::kAcmh, plain},
      {"mPM+rs", multi, kernels::PatternKind::kDistant, plain},
      {"mPM+ACMH+pp", multi, kernels::PatternKind::kAcmh, pp},
      {"mPM+rs+pp", multi, kernels::PatternKind::kDistant, pp},
      {"mPM+rs+gp", multi, kernels::PatternKind::kDistant, gp}};
  for (size_t r = 0; r < rows.size(); ++r) {
    SCOPED_TRACE(rows[r].name);
    EXPECT_EQ(rows[r].name, expected[r].name);
    std::vector<std::string> stages;
    for (const StageSummary& s : rows[r].summary.stages) stages.push_back(s.name);
    EXPECT_EQ(stages, expected[r].stages);
    std::vector<int> sides;
    int half = 0;
    for (const kernels::IterationStats& it : rows[r].summary.stages[0].iterations) {
      sides.push_back(it.window_side);
      half += it.half_resolution;
      EXPECT_EQ(it.pattern, expected[r].pattern);
    }
    EXPECT_EQ(sides, expected[r].sides);
    EXPECT_EQ(half, r == 0 ? 0 : 6);
    // Later stages run the 11 px window with the row's pattern.
    for (size_t s = 1; s < rows[r].summary.stages.size(); ++s) {
      for (const kernels::IterationStats& it : rows[r].summary.stages[s].iterations) {
        EXPECT_EQ(it.window_side, 11);
        EXPECT_EQ(it.pattern, expected[r].pattern);
      }
    }
    // Scored against GT.
    ASSERT_FALSE(rows[r].evaluation.depth.pooled.at.empty());
    EXPECT_GT(rows[r].evaluation.depth.pooled.at[0].f1, 0.3);
  }
  const std::string table = FormatAblationTable(rows);
  EXPECT_NE(table.find("mPM+rs+gp"), std::string::npos);
  EXPECT_NE(table.find("windows 41h/21h/11 px"), std::string::npos) << table;
  EXPECT_NE(table.find("windows 11 px"), std::string::npos) << table;
  EXPECT_NE(table.find("untextured 1%: acc comp F1"), std::string::npos);

  // ablation.json: each row with its name, the options that change its results, its run time.
  const nlohmann::json json = nlohmann::json::parse(AblationJson(rows, ReportContext{"test", "test"}));
  ASSERT_EQ(json["workspaces"].size(), 6u);
  EXPECT_EQ(json["workspaces"][0]["row"], "ACMH");
  EXPECT_EQ(json["workspaces"][0]["options"]["max_window_scale"], "0");
  EXPECT_EQ(json["workspaces"][5]["options"]["planar_prior"], "geometric");
  EXPECT_EQ(json["workspaces"][5]["seconds"], rows[5].summary.seconds);
}

}  // namespace
}  // namespace mpmvs

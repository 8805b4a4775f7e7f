// The JSON result files read back: evaluation.json / comparison.json (EvaluationJson),
// agreement.json (AgreementJson) and gt/scene_info.json keep their keys, order and values.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "colmap_ext/evaluation/evaluation_report.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

using Json = nlohmann::ordered_json;

std::vector<std::string> Keys(const Json& object) {
  std::vector<std::string> keys;
  for (const auto& item : object.items()) keys.push_back(item.key());
  return keys;
}

DepthPixelScore Score(int64_t num_gt, int64_t num_estimated, double median) {
  DepthPixelScore s;
  s.num_gt = num_gt;
  s.num_estimated = num_estimated;
  s.median_rel_error = median;
  s.at.push_back({0.01, 40, 0.4, 0.2, F1Score(0.4, 0.2)});
  s.at.push_back({0.02, 80, 0.8, 0.4, F1Score(0.8, 0.4)});
  return s;
}

TEST(JsonFiles, EvaluationReadsBack) {
  WorkspaceEvaluation e;
  e.label = "run \"a\"\n";  // quotes and control characters are escaped
  e.workspace_path = "/ws";
  e.gt_dir = "/ws/gt";
  e.depth.input_type = "geometric";
  e.depth.tolerances = {0.01, 0.02};
  e.depth.pooled = Score(200, 100, 0.005);
  e.depth.has_masks = true;
  e.depth.pooled_untextured = Score(50, 10, NAN);
  DepthImageScore image;
  image.name = "view_00.png";
  image.has_estimate = true;
  image.all = Score(200, 100, 0.005);
  e.depth.images.push_back(image);
  DepthImageScore missing;
  missing.name = "view_01.png";
  e.depth.images.push_back(missing);
  e.has_cloud = true;
  e.cloud.fused_path = "/ws/fused.ply";
  e.cloud.num_points = 1000;
  e.cloud.num_observed = 900;
  e.cloud.num_gt_points = 5000;
  e.cloud.median_gt_depth = 3.5;
  e.cloud.at.push_back({0.01, 0.035, 850, 4000, 0.85, 0.8, F1Score(0.85, 0.8)});
  e.depth.surface_names = {"far wall"};
  e.depth.pooled_surfaces.push_back(e.depth.pooled);
  e.depth.pooled_surfaces[0].num_too_near = 7;
  WorkspaceEvaluation without_cloud;
  without_cloud.label = "b";
  without_cloud.depth.input_type = "photometric";

  const std::string text = EvaluationJson({e, without_cloud}, {"colmap-mp evaluate --x 1", ""});
  ASSERT_EQ(text.back(), '\n');
  const Json j = Json::parse(text);
  EXPECT_EQ(Keys(j), (std::vector<std::string>{"command", "commit", "protocol", "workspaces"}));
  EXPECT_EQ(j["command"], "colmap-mp evaluate --x 1");
  EXPECT_EQ(j["commit"], "unknown");
  ASSERT_EQ(j["workspaces"].size(), 2u);

  const Json& w = j["workspaces"][0];
  EXPECT_EQ(Keys(w), (std::vector<std::string>{"label", "workspace_path", "gt_dir", "depth", "point_cloud"}));
  EXPECT_EQ(w["label"], "run \"a\"\n");
  EXPECT_EQ(w["gt_dir"], "/ws/gt");
  const Json& depth = w["depth"];
  EXPECT_EQ(Keys(depth), (std::vector<std::string>{"input_type", "tolerances", "pooled",
                                                   "pooled_untextured", "pooled_surfaces", "images"}));
  ASSERT_EQ(depth["pooled_surfaces"].size(), 1u);
  EXPECT_EQ(Keys(depth["pooled_surfaces"][0]), (std::vector<std::string>{"name", "all"}));
  EXPECT_EQ(depth["pooled_surfaces"][0]["name"], "far wall");
  EXPECT_EQ(depth["pooled_surfaces"][0]["all"]["num_too_near"], 7);
  EXPECT_EQ(depth["tolerances"], Json({0.01, 0.02}));
  const Json& pooled = depth["pooled"];
  EXPECT_EQ(Keys(pooled), (std::vector<std::string>{"num_gt_pixels", "num_estimated_pixels",
                                                    "median_relative_error", "num_too_near",
                                                    "num_too_far", "tolerances"}));
  EXPECT_EQ(pooled["num_gt_pixels"], 200);
  EXPECT_EQ(pooled["num_estimated_pixels"], 100);
  EXPECT_EQ(pooled["median_relative_error"], 0.005);
  ASSERT_EQ(pooled["tolerances"].size(), 2u);
  const Json& t = pooled["tolerances"][1];
  EXPECT_EQ(Keys(t), (std::vector<std::string>{"tolerance", "num_good", "accuracy", "completeness", "f1"}));
  EXPECT_EQ(t["tolerance"], 0.02);
  EXPECT_EQ(t["num_good"], 80);
  EXPECT_EQ(t["f1"], F1Score(0.8, 0.4));  // doubles round-trip exactly
  EXPECT_TRUE(depth["pooled_untextured"]["median_relative_error"].is_null());  // NaN
  ASSERT_EQ(depth["images"].size(), 2u);
  EXPECT_EQ(Keys(depth["images"][0]), (std::vector<std::string>{"name", "has_estimate", "all"}));
  EXPECT_EQ(depth["images"][0]["has_estimate"], true);
  EXPECT_EQ(depth["images"][1]["name"], "view_01.png");
  EXPECT_EQ(depth["images"][1]["has_estimate"], false);
  const Json& cloud = w["point_cloud"];
  EXPECT_EQ(Keys(cloud), (std::vector<std::string>{"fused_path", "num_points", "num_observed_points",
                                                   "num_gt_points", "median_gt_depth", "tolerances"}));
  EXPECT_EQ(cloud["num_observed_points"], 900);
  EXPECT_EQ(cloud["median_gt_depth"], 3.5);
  EXPECT_EQ(Keys(cloud["tolerances"][0]), (std::vector<std::string>{"relative_tolerance", "tolerance",
                                                                     "accuracy", "completeness", "f1"}));
  EXPECT_EQ(cloud["tolerances"][0]["tolerance"], 0.035);

  const Json& b = j["workspaces"][1];
  EXPECT_EQ(Keys(b), (std::vector<std::string>{"label", "workspace_path", "gt_dir", "depth"}));
  EXPECT_EQ(Keys(b["depth"]), (std::vector<std::string>{"input_type", "tolerances", "pooled", "images"}));
  EXPECT_TRUE(b["depth"]["tolerances"].is_array());
  EXPECT_TRUE(b["depth"]["images"].is_array());
}

TEST(JsonFiles, AgreementReadsBack) {
  PairAgreement pair;
  pair.a = 0;
  pair.b = 1;
  pair.pooled = {100, 90, 80, 70, 63};
  ImageAgreement image;
  image.name = "view_00.png";
  image.present_a = true;
  image.counts = pair.pooled;
  pair.images.push_back(image);
  const Json j = Json::parse(AgreementJson({"x", "y"}, {pair}, 0.01, "geometric", {"cmd", "abc"}));
  EXPECT_EQ(Keys(j), (std::vector<std::string>{"command", "commit", "protocol", "input_type",
                                               "tolerance", "labels", "pairs"}));
  EXPECT_EQ(j["commit"], "abc");
  EXPECT_EQ(j["tolerance"], 0.01);
  EXPECT_EQ(j["labels"], Json({"x", "y"}));
  ASSERT_EQ(j["pairs"].size(), 1u);
  const Json& p = j["pairs"][0];
  EXPECT_EQ(Keys(p), (std::vector<std::string>{"a", "b", "pooled", "images"}));
  EXPECT_EQ(p["b"], "y");
  EXPECT_EQ(Keys(p["pooled"]), (std::vector<std::string>{"num_pixels", "num_a", "num_b", "num_both",
                                                         "num_agree", "agree_share"}));
  EXPECT_EQ(p["pooled"]["num_agree"], 63);
  EXPECT_EQ(p["pooled"]["agree_share"], 0.9);
  EXPECT_EQ(Keys(p["images"][0]), (std::vector<std::string>{"name", "present_a", "present_b", "counts"}));
  EXPECT_EQ(p["images"][0]["present_b"], false);
}

TEST(JsonFiles, SceneInfoReadsBack) {
  test::TempDir dir;
  SyntheticSceneOptions o;
  o.scene = "plane";
  o.width = 64;
  o.height = 48;
  o.num_views = 2;
  o.supersampling = 1;
  const SyntheticScene scene = GenerateSyntheticScene(o, dir.path());
  const Json j = Json::parse(test::ReadTextFile(dir / "gt/scene_info.json"));
  EXPECT_EQ(Keys(j), (std::vector<std::string>{"generator", "options", "num_sparse_points",
                                               "pixel_convention", "plane_view_angles_deg", "views"}));
  EXPECT_EQ(j["generator"], "mp-mvs generate_scene");
  const Json& options = j["options"];
  EXPECT_EQ(Keys(options), (std::vector<std::string>{
                               "scene", "width", "height", "num_views", "seed", "noise_sigma",
                               "supersampling", "blur_sigma", "exposure_variation",
                               "plane_tilt_deg", "max_sparse_points", "sparse_noise_px"}));
  EXPECT_EQ(options["scene"], "plane");
  EXPECT_EQ(options["width"], 64);
  EXPECT_EQ(options["seed"], o.seed);
  EXPECT_EQ(options["noise_sigma"], o.noise_sigma);
  EXPECT_EQ(j["num_sparse_points"], scene.model.points.size());
  EXPECT_EQ(j["plane_view_angles_deg"].get<std::vector<double>>(), scene.plane_view_angles_deg);
  ASSERT_EQ(j["views"].size(), 2u);
  const Json& v = j["views"][1];
  EXPECT_EQ(Keys(v), (std::vector<std::string>{
                         "name", "K_fx_fy_cx_cy", "center", "R", "t", "gain", "offset",
                         "gt_valid_fraction", "untextured_fraction", "gt_depth_range",
                         "num_sparse_points", "sparse_depth_range", "gt_in_sparse_depth_range"}));
  const SyntheticView& sv = scene.views[1];
  const SyntheticCamera& c = sv.camera;
  EXPECT_EQ(v["name"], sv.name);
  EXPECT_EQ(v["K_fx_fy_cx_cy"].get<std::vector<double>>(), (std::vector<double>{c.fx, c.fy, c.cx, c.cy}));
  ASSERT_EQ(v["R"].size(), 9u);
  for (int k = 0; k < 9; ++k) EXPECT_EQ(v["R"][k], c.R(k / 3, k % 3)) << k;
  EXPECT_EQ(v["t"][2], c.t.z());
  EXPECT_EQ(v["center"][0], c.Center().x());
  EXPECT_EQ(v["gain"], sv.gain);
  EXPECT_EQ(v["gt_depth_range"].get<std::vector<double>>(),
            (std::vector<double>{sv.stats.gt_depth_min, sv.stats.gt_depth_max}));
  EXPECT_EQ(v["num_sparse_points"], sv.stats.num_sparse_points);
}

}  // namespace
}  // namespace mpmvs

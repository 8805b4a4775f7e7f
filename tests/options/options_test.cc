// The option declarations (colmap_ext/options): every part made from them — the state
// fingerprint, Check(), the presets, -h and docs/options.md — says what the tables say.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <set>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/cli/patch_match_flags.h"
#include "colmap_ext/options/patch_match_options.h"
#include "colmap_ext/plan/run_plan.h"
#include "colmap_ext/plan/stage_plan.h"
#include "colmap_ext/store/state_record.h"
#include "colmap_ext/util/error.h"

namespace mpmvs {
namespace {

// The fingerprint text must stay byte-identical to what builds before the declarations wrote
// (those texts, printed by the earlier StateOptionsText) for the options they ran: otherwise
// every state on disk would be recomputed. A speed option (kResultWhenSet) enters it only away
// from its paper value, whatever the default is, so that a default which now changes the maps
// recomputes them.
TEST(Options, FingerprintTextIsTheOneEarlierBuildsWrote) {
  MpMvsOptions earlier;
  earlier.half_resolution_scales = 0;  // the default before 5 Dec 2026
  EXPECT_EQ(StateOptionsText(earlier),
      "math_revision 9\n"
      "max_window_scale 2\n"
      "iterations_per_scale 3\n"
      "distant_sampling 1\n"
      "planar_prior geometric\n"
      "geom_iterations 2\n"
      "prior_iterations 3\n"
      "prior_rounds 2\n"
      "geom_weight 0.20000000000000001\n"
      "geom_max_error 2\n"
      "prior_max_photo_cost 0.20000000000000001\n"
      "prior_max_geom_error 1\n"
      "prior_max_cost_acmp 0.10000000000000001\n"
      "prior_cell_size 5\n"
      "prior_points_per_cell 3\n"
      "prior_plane_vote 1\n"
      "prior_corner_colour_match 12\n"
      "prior_source_vertices 1\n"
      "prior_vertex_bend 0.01\n"
      "prior_beta 8\n"
      "noise_floor 1\n"
      "refinement_rho 0.02\n"
      "depth_check_views 1\n"
      "chroma_weight 8\n"
      "max_source_images 20\n"
      "seed 1\n");
  // Today's default runs the larger windows at half resolution: its states are not those.
  EXPECT_EQ(StateOptionsText(MpMvsOptions{}), StateOptionsText(earlier) + "half_resolution_scales 2\n");
  MpMvsOptions b;
  b.half_resolution_scales = 0;
  b.settled_pixel_skips = 2;
  b.prior_beta = 0.18;
  b.planar_prior = "photometric";
  b.distant_sampling = false;
  b.geom_weight = 0.3;
  b.chroma_weight = 0;
  b.seed = 5;
  b.prior_vertex_bend = 0.125;
  b.overwrite = true;  // options of the run do not enter it
  b.stage = "prior";
  EXPECT_EQ(StateOptionsText(b),
      "math_revision 9\n"
      "max_window_scale 2\n"
      "iterations_per_scale 3\n"
      "distant_sampling 0\n"
      "planar_prior photometric\n"
      "geom_iterations 2\n"
      "prior_iterations 3\n"
      "prior_rounds 2\n"
      "geom_weight 0.29999999999999999\n"
      "geom_max_error 2\n"
      "prior_max_photo_cost 0.20000000000000001\n"
      "prior_max_geom_error 1\n"
      "prior_max_cost_acmp 0.10000000000000001\n"
      "prior_cell_size 5\n"
      "prior_points_per_cell 3\n"
      "prior_plane_vote 1\n"
      "prior_corner_colour_match 12\n"
      "prior_source_vertices 1\n"
      "prior_vertex_bend 0.125\n"
      "prior_beta 0.17999999999999999\n"
      "noise_floor 1\n"
      "refinement_rho 0.02\n"
      "depth_check_views 1\n"
      "chroma_weight 0\n"
      "max_source_images 20\n"
      "seed 5\n"
      "settled_pixel_skips 2\n");
}

// Parses args with the front ends' registration; returns the options.
MpMvsOptions Parse(const std::vector<std::string>& args, PatchMatchStereoOptions* colmap = nullptr) {
  PatchMatchStereoOptions c;
  MpMvsOptions m;
  OptionParser parser;
  AddPatchMatchOptions(&parser, &c, &m);
  EXPECT_TRUE(parser.Parse(args));
  if (colmap) *colmap = c;
  return m;
}

std::vector<std::string> StageNames(const PipelinePlan& plan, int* iterations) {
  std::vector<std::string> names;
  *iterations = 0;
  for (const StagePlan& stage : plan.stages) {
    names.push_back(stage.name);
    *iterations += static_cast<int>(stage.schedule.iterations.size());
  }
  return names;
}

// Whether a stage runs two iterations in a row at one window scale and resolution: only there
// does a settled pixel skip an update (kernels/DESIGN.md 27).
bool SomeStageRepeatsAWindowScale(const PipelinePlan& plan) {
  for (const StagePlan& stage : plan.stages) {
    const std::vector<kernels::IterationSpec>& it = stage.schedule.iterations;
    for (size_t i = 1; i < it.size(); ++i) {
      if (it[i].window_scale == it[i - 1].window_scale && it[i].half_resolution == it[i - 1].half_resolution) {
        return true;
      }
    }
  }
  return false;
}

TEST(Options, PaperPresetRunsThePapersPipelineAndExplicitOptionsOverrideIt) {
  PatchMatchStereoOptions colmap;
  const MpMvsOptions paper = Parse({"--MPMVS.preset", "paper"}, &colmap);
  int iterations = 0;
  EXPECT_EQ(StageNames(MakePipelinePlan(colmap, paper), &iterations),
            (std::vector<std::string>{"photometric", "geometric1", "prior", "geometric2"}));
  EXPECT_EQ(iterations, 16);
  EXPECT_EQ(paper.prior_beta, 0.18);
  EXPECT_FALSE(paper.prior_plane_vote);
  EXPECT_EQ(paper.prior_corner_colour_match, 0);
  EXPECT_EQ(paper.chroma_weight, 0);

  // The default pipeline: seven stages, 21 iterations.
  const MpMvsOptions defaults = Parse({}, &colmap);
  EXPECT_EQ(StageNames(MakePipelinePlan(colmap, defaults), &iterations),
            (std::vector<std::string>{"photometric", "geometric1", "prior", "geometric2", "prior2", "geometric3",
                                      "depth_check"}));
  EXPECT_EQ(iterations, 21);
  EXPECT_EQ(StateOptionsText(Parse({"--MPMVS.preset", "default"})), StateOptionsText(MpMvsOptions{}));

  // fast: one iteration per window scale, the two larger windows at half resolution, fewer
  // iterations per stage, one prior round, the candidates costed in three views.
  const MpMvsOptions fast = Parse({"--MPMVS.preset", "fast"}, &colmap);
  EXPECT_EQ(StageNames(MakePipelinePlan(colmap, fast), &iterations),
            (std::vector<std::string>{"photometric", "geometric1", "prior", "geometric2", "depth_check"}));
  EXPECT_EQ(iterations, 6);
  EXPECT_EQ(fast.prior_rounds, 1);
  EXPECT_EQ(fast.iterations_per_scale, 1);
  EXPECT_EQ(fast.prior_iterations, 1);
  // Settled pixels skip updates only at a window scale a stage runs twice in a row; fast runs
  // none twice, so it must not set the option (it did until 6 Dec 2026: that changed its
  // fingerprint, not its maps).
  EXPECT_FALSE(fast.settled_pixel_skips > 0 && !SomeStageRepeatsAWindowScale(MakePipelinePlan(colmap, fast)));
  EXPECT_EQ(fast.costed_views, 3);
  EXPECT_EQ(fast.max_window_scale, 2);
  EXPECT_EQ(fast.half_resolution_scales, 2);
  EXPECT_EQ(MpMvsOptions().half_resolution_scales, 2);
  EXPECT_EQ(paper.half_resolution_scales, 0);
  EXPECT_EQ(fast.chroma_weight, MpMvsOptions().chroma_weight);

  // Explicit options win over the preset, before or after it on the command line.
  for (const auto& args : {std::vector<std::string>{"--MPMVS.prior_rounds", "2", "--MPMVS.preset", "paper"},
                           std::vector<std::string>{"--MPMVS.preset", "paper", "--MPMVS.prior_rounds", "2"}}) {
    const MpMvsOptions o = Parse(args);
    EXPECT_EQ(o.prior_rounds, 2);
    EXPECT_EQ(o.depth_check_views, 0);
  }
  // Options of the run are no part of a preset.
  EXPECT_TRUE(Parse({"--MPMVS.overwrite", "1", "--MPMVS.preset", "paper"}).overwrite);

  PatchMatchStereoOptions c;
  MpMvsOptions m;
  OptionParser parser;
  AddPatchMatchOptions(&parser, &c, &m);
  try {
    parser.Parse({"--MPMVS.preset", "fastest"});
    FAIL() << "an unknown preset was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--MPMVS.preset = fastest is invalid"), std::string::npos) << e.what();
  }
}

// Every declared numeric range is enforced by Check(), with a message naming the option.
TEST(Options, CheckRefusesEveryValueOutsideItsDeclaredRange) {
  int checked = 0;
  MpMvsOptions().Visit([&](const OptionSpec& spec, const auto& value, const auto&) {
    using T = std::decay_t<decltype(value)>;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      const OptionRange& r = spec.range;
      std::vector<double> outside;
      if (r.kind == OptionRange::Kind::kClosed || r.kind == OptionRange::Kind::kClosedOpen ||
          r.kind == OptionRange::Kind::kAtLeast) {
        outside.push_back(r.lo - 1);
      }
      if (r.kind == OptionRange::Kind::kOpen || r.kind == OptionRange::Kind::kAbove) outside.push_back(r.lo);
      if (r.kind == OptionRange::Kind::kClosed) outside.push_back(r.hi + 1);
      if (r.kind == OptionRange::Kind::kOpen || r.kind == OptionRange::Kind::kClosedOpen) outside.push_back(r.hi);
      for (double v : outside) {
        // A bound at the type's limit has no value beyond it to try.
        if (v < static_cast<double>(std::numeric_limits<T>::lowest()) ||
            v > static_cast<double>(std::numeric_limits<T>::max())) {
          continue;
        }
        MpMvsOptions o;
        o.Visit([&](const OptionSpec& s, auto& field, const auto&) {
          if constexpr (std::is_same_v<std::decay_t<decltype(field)>, T>) {
            if (std::string(s.name) == spec.name) field = static_cast<T>(v);
          }
        });
        std::string error;
        EXPECT_FALSE(o.Check(&error)) << spec.name << " = " << v;
        EXPECT_NE(error.find("--MPMVS." + std::string(spec.name) + " = "), std::string::npos) << error;
        ++checked;
      }
    }
  });
  EXPECT_GE(checked, 25);
  std::string error;
  EXPECT_TRUE(MpMvsOptions().Check(&error)) << error;
  EXPECT_TRUE(PatchMatchStereoOptions().Check(&error)) << error;
  MpMvsOptions bad_prior;
  bad_prior.planar_prior = "both";
  EXPECT_FALSE(bad_prior.Check(&error));
  EXPECT_EQ(error, "--MPMVS.planar_prior = both is invalid: must be none, photometric or geometric");
  PatchMatchStereoOptions bad_colmap;
  bad_colmap.max_image_size = 0;
  EXPECT_FALSE(bad_colmap.Check(&error));
  EXPECT_EQ(error, "--PatchMatchStereo.max_image_size = 0 is invalid: must be -1 or > 0");
}

// Issue 35, defect 7: absurd but finite values are refused by Check(), naming the option,
// instead of ruining the maps (depths beyond float precision or FLT_MAX, a geometric weight
// of 1e39) or exhausting memory (2^31 - 1 iterations).
TEST(Options, CheckRefusesAbsurdFiniteValuesNamingTheOption) {
  auto colmap_error = [](double depth_min, double depth_max) {
    PatchMatchStereoOptions c;
    c.depth_min = depth_min;
    c.depth_max = depth_max;
    std::string error;
    EXPECT_FALSE(c.Check(&error)) << depth_min << " " << depth_max;
    return error;
  };
  EXPECT_NE(colmap_error(1, 1e15).find("--PatchMatchStereo.depth_max"), std::string::npos);
  EXPECT_NE(colmap_error(1, 1e39).find("--PatchMatchStereo.depth_max"), std::string::npos);
  EXPECT_NE(colmap_error(1e-30, 10).find("--PatchMatchStereo.depth_min"), std::string::npos);
  auto method_error = [](const std::function<void(MpMvsOptions*)>& set) {
    MpMvsOptions o;
    set(&o);
    std::string error;
    EXPECT_FALSE(o.Check(&error));
    return error;
  };
  const int max_int = std::numeric_limits<int>::max();
  EXPECT_NE(method_error([](MpMvsOptions* o) { o->geom_weight = 1e39; }).find("--MPMVS.geom_weight"),
            std::string::npos);
  EXPECT_NE(method_error([&](MpMvsOptions* o) { o->iterations_per_scale = max_int; }).find("--MPMVS.iterations_per_scale"),
            std::string::npos);
  EXPECT_NE(method_error([&](MpMvsOptions* o) { o->geom_iterations = max_int; }).find("--MPMVS.geom_iterations"),
            std::string::npos);
  EXPECT_NE(method_error([&](MpMvsOptions* o) { o->prior_iterations = max_int; }).find("--MPMVS.prior_iterations"),
            std::string::npos);
  EXPECT_NE(method_error([](MpMvsOptions* o) { o->prior_max_photo_cost = std::nan(""); })
                .find("--MPMVS.prior_max_photo_cost"),
            std::string::npos);
  EXPECT_NE(method_error([&](MpMvsOptions* o) { o->claim_lease = max_int; }).find("--MPMVS.claim_lease"),
            std::string::npos);
}

// Every numeric option has a range bounded on both sides, but the resource options, which
// are clamped with a warning instead, and max_image_size (a bound above the image's size
// means full size).
TEST(Options, EveryNumericOptionHasABoundedRange) {
  const std::set<std::string> unbounded = {"num_threads", "cache_size", "max_image_size"};
  auto bounded = [](const OptionRange& r) {
    return r.kind == OptionRange::Kind::kClosed || r.kind == OptionRange::Kind::kOpen ||
           r.kind == OptionRange::Kind::kClosedOpen || r.kind == OptionRange::Kind::kOpenClosed;
  };
  auto check = [&](const OptionSpec& spec, const auto& value) {
    using T = std::decay_t<decltype(value)>;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      if (!unbounded.count(spec.name)) EXPECT_TRUE(bounded(spec.range)) << spec.name << ": " << spec.range.Text();
    }
  };
  PatchMatchStereoOptions().Visit([&](const OptionSpec& spec, const auto& value) { check(spec, value); });
  MpMvsOptions().Visit([&](const OptionSpec& spec, const auto& value, const auto&) { check(spec, value); });
}

// Resource options stay accepted and are clamped with a warning.
TEST(Options, HugeCacheSizeIsClampedWithAWarning) {
  PatchMatchStereoOptions c;
  c.cache_size = 1e30;
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  const RunPlan plan = MakeRunPlan(c, MpMvsOptions{}, false);
  const std::string log = testing::internal::GetCapturedStdout() + testing::internal::GetCapturedStderr();
  EXPECT_NE(log.find("--PatchMatchStereo.cache_size"), std::string::npos) << log;
  EXPECT_GT(plan.cache_bytes, size_t(1) << 20);
  EXPECT_LT(plan.cache_bytes, size_t(1) << 50);
}

// -h shows every declared option with its range, and the stage option names every stage a
// run can log.
TEST(Options, HelpShowsEveryOptionAndEveryStage) {
  PatchMatchStereoOptions c;
  MpMvsOptions m;
  OptionParser parser;
  AddPatchMatchOptions(&parser, &c, &m);
  const std::string help = parser.Help();
  m.Visit([&](const OptionSpec& spec, const auto&, const auto&) {
    EXPECT_NE(help.find("--MPMVS." + std::string(spec.name) + " "), std::string::npos) << spec.name;
  });
  std::string words;  // the help with its line wrapping undone
  std::istringstream in(help);
  for (std::string word; in >> word;) words += word + " ";
  EXPECT_NE(words.find("--MPMVS.max_window_scale int (=2) mPM: windows"), std::string::npos) << words;
  EXPECT_NE(words.find("0 = single 11 px window [in [0, 4]]"), std::string::npos) << words;
  MpMvsOptions most;
  most.prior_rounds = 4;
  std::string stage_help;
  m.Visit([&](const OptionSpec& spec, const auto&, const auto&) {
    if (std::string(spec.name) == "stage") stage_help = spec.help;
  });
  for (const StagePlan& stage : MakePipelinePlan(PatchMatchStereoOptions(), most).stages) {
    const std::string name = stage.name;
    const bool named = stage_help.find(name) != std::string::npos ||
                       (name.rfind("prior", 0) == 0 && stage_help.find("prior3") != std::string::npos) ||
                       (name.rfind("geometric", 0) == 0 && stage_help.find("geometric4") != std::string::npos);
    EXPECT_TRUE(named) << name << " is not named in the help of --MPMVS.stage: " << stage_help;
  }
  EXPECT_NE(stage_help.find("depth_check"), std::string::npos);
}

// docs/options.md is generated from the declarations; MPMVS_UPDATE_DOCS=1 rewrites it.
TEST(OptionDocs, OptionsMdMatchesTheDeclarations) {
  const std::string path = std::string(MPMVS_SOURCE_DIR) + "/docs/options.md";
  const std::string generated = OptionsMarkdown();
  if (std::getenv("MPMVS_UPDATE_DOCS")) {
    std::ofstream(path) << generated;
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), generated) << path << " differs from the option declarations; rewrite it with "
                                   << "MPMVS_UPDATE_DOCS=1 build/mpmvs_tests --gtest_filter='OptionDocs.*'";
}

}  // namespace
}  // namespace mpmvs

#include "colmap_ext/plan/stage_plan.h"

#include <algorithm>

namespace mpmvs {

bool BuildsOnPrior(const PipelinePlan& pipeline, int k) {
  for (; k >= 0; k = pipeline.stages[k].input) {
    if (pipeline.stages[k].kind == StageKind::kPlanarPrior) return true;
  }
  return false;
}

std::string StageKindName(StageKind kind) {
  switch (kind) {
    case StageKind::kPhotometric: return "photometric";
    case StageKind::kGeometric: return "geometric";
    case StageKind::kPlanarPrior: return "planar prior";
    case StageKind::kDepthCheck: return "depth check";
  }
  return "?";
}

PipelinePlan MakePipelinePlan(const PatchMatchStereoOptions& colmap_options,
                              const MpMvsOptions& options) {
  kernels::PatchMatchSchedule base;
  base.pattern = options.distant_sampling ? kernels::PatternKind::kDistant : kernels::PatternKind::kAcmh;
  base.geom_lambda = static_cast<float>(options.geom_weight);
  base.geom_error_clamp = static_cast<float>(options.geom_max_error);
  base.refinement_rho = static_cast<float>(options.refinement_rho);
  base.settled_skips = options.settled_pixel_skips;
  base.costed_views = options.costed_views;
  base.seed = static_cast<uint64_t>(options.seed);
  base.num_threads = colmap_options.num_threads;
  base.prior_beta = static_cast<float>(options.prior_beta);

  auto single_scale = [&](int iterations) {
    kernels::PatchMatchSchedule s = base;
    for (int t = 0; t < iterations; ++t) s.iterations.push_back({0, t});
    return s;
  };

  PipelinePlan plan;
  StagePlan photometric;
  photometric.name = "photometric";
  photometric.kind = StageKind::kPhotometric;
  photometric.schedule = base;
  // mPM: largest window first, tau restarting at every scale. The largest
  // half_resolution_scales scales (at most all but the finest) run at half resolution with
  // the window of one scale less, which covers the same part of the scene.
  const int half_scales = std::min(options.half_resolution_scales, options.max_window_scale);
  for (int s = options.max_window_scale; s >= 0; --s) {
    const bool half = s > options.max_window_scale - half_scales;
    for (int t = 0; t < options.iterations_per_scale; ++t) {
      photometric.schedule.iterations.push_back({half ? s - 1 : s, t, half});
    }
  }
  plan.stages.push_back(photometric);

  auto add_prior = [&](bool geometric_selection, const std::string& name) {
    StagePlan prior;
    prior.name = name;
    prior.kind = StageKind::kPlanarPrior;
    prior.input = static_cast<int>(plan.stages.size()) - 1;
    prior.prior_geometric_selection = geometric_selection;
    prior.schedule = single_scale(options.prior_iterations);
    prior.schedule.use_prior = true;
    prior.schedule.noise_floor = options.noise_floor;
    // After a geometric pass (gp) the prior run keeps the geometric term: the paper does not
    // say, the reference code drops it, and keeping it scores better (colmap_ext/DESIGN.md).
    prior.schedule.geometric = geometric_selection;
    plan.stages.push_back(prior);
  };
  auto add_geometric = [&](const std::string& name) {
    StagePlan geo;
    geo.name = name;
    geo.kind = StageKind::kGeometric;
    geo.input = static_cast<int>(plan.stages.size()) - 1;
    geo.schedule = single_scale(options.geom_iterations);
    geo.schedule.geometric = true;
    geo.schedule.noise_floor = options.noise_floor;
    plan.stages.push_back(geo);
  };

  const PlanarPriorMode prior = options.PriorMode();
  if (prior == PlanarPriorMode::kPhotometric) add_prior(false, "prior");
  plan.photometric_output = static_cast<int>(plan.stages.size()) - 1;
  if (colmap_options.geom_consistency) {
    add_geometric("geometric1");
    if (prior == PlanarPriorMode::kGeometric) {
      // Each round builds its prior from the previous geometric pass: prior, geometric2,
      // then prior2, geometric3, ...
      for (int round = 1; round <= options.prior_rounds; ++round) {
        add_prior(true, round == 1 ? "prior" : "prior" + std::to_string(round));
        add_geometric("geometric" + std::to_string(round + 1));
      }
    } else {
      add_geometric("geometric2");
    }
    if (options.depth_check_views > 0) {
      // No PatchMatch iterations: the last geometric pass's results, checked against its
      // sources' results of the same pass (kernels/DESIGN.md 22).
      StagePlan check;
      check.name = "depth_check";
      check.kind = StageKind::kDepthCheck;
      check.input = static_cast<int>(plan.stages.size()) - 1;
      check.confirming_views = options.depth_check_views;
      check.schedule = base;
      check.schedule.geometric = true;  // reads the sources' results of its input stage
      plan.stages.push_back(check);
    }
    plan.geometric_output = static_cast<int>(plan.stages.size()) - 1;
  }
  for (size_t i = 0; i < plan.stages.size(); ++i) {
    plan.stages[i].schedule.stage_id = static_cast<uint32_t>(i);
  }
  return plan;
}

}  // namespace mpmvs

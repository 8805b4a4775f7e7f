#include "kernels/patch_match.h"

#include <stdexcept>

#include "kernels/half_resolution.h"

namespace mpmvs {
namespace kernels {

void PatchMatchSchedule::Check() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (iterations.empty()) fail("a PatchMatch schedule needs at least one iteration");
  for (const IterationSpec& it : iterations) {
    if (it.window_scale < 0 || it.window_scale > 4) fail("window scale must be in [0, 4]");
    if (it.tau_index < 0) fail("tau index must be >= 0");
  }
  for (size_t i = 1; i < iterations.size(); ++i) {
    if (iterations[i].half_resolution && !iterations[i - 1].half_resolution) {
      fail("half-resolution iterations must come first");
    }
  }
  if (iterations.front().half_resolution) {
    if (geometric || use_prior) fail("half-resolution iterations are photometric only");
    if (iterations.back().half_resolution) fail("half-resolution iterations need full-resolution ones after them");
  }
  if (geom_lambda < 0.f) fail("geometric weight must be >= 0");
  if (geometric && geom_error_clamp <= 0.f) fail("geometric clamp must be > 0");
  if (settled_skips < 0 || settled_skips > 255) fail("settled pixel skips must be in [0, 255]");
  if (costed_views < 0 || costed_views > kMaxSourceViews) fail("costed views must be in [0, 32]");
  if (refinement_rho <= 0.f || refinement_rho >= 1.f) fail("refinement rho must be in (0, 1)");
  if (tau0 <= 0.f || tau_alpha <= 0.f) fail("tau0 and alpha must be > 0");
  if (use_prior && (prior_beta <= 0.f || prior_sigma_normal_deg <= 0.f)) fail("prior sigmas must be > 0");
}

std::vector<SourceView> MakeSourceViews(const PatchMatchProblem& problem) {
  std::vector<SourceView> views(problem.sources.size());
  for (size_t s = 0; s < problem.sources.size(); ++s) {
    views[s].image = problem.sources[s].image;
    views[s].camera = problem.sources[s].camera;
    views[s].rel = ComputeRelativePose(problem.ref_camera, problem.sources[s].camera);
    views[s].depth = problem.sources[s].depth_map;
  }
  return views;
}

PassParams MakePassParams(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                          const SourceView* sources) {
  if (problem.sources.empty() || problem.sources.size() > static_cast<size_t>(kMaxSourceViews)) {
    throw std::invalid_argument("a problem needs 1.." + std::to_string(kMaxSourceViews) +
                                " source views");
  }
  if (!(problem.depth_min > 0.f && problem.depth_max > problem.depth_min)) {
    throw std::invalid_argument("invalid depth range");
  }
  if (schedule.geometric) {
    for (const PatchMatchSource& s : problem.sources) {
      if (!s.depth_map) throw std::invalid_argument("geometric schedule without source depth maps");
    }
  }
  if (HasHalfResolutionIterations(schedule)) {
    throw std::invalid_argument("a schedule with half-resolution iterations runs through RunWithHalfResolutionStart");
  }
  if (schedule.use_prior && (!problem.prior_plane || !problem.prior_label)) {
    throw std::invalid_argument("prior schedule without a planar prior");
  }
  PassParams p;
  p.ref_camera = problem.ref_camera;
  p.ref_image = problem.ref_image;
  p.sources = sources;
  p.num_sources = static_cast<int>(problem.sources.size());
  p.pattern = MakePropagationPattern(schedule.pattern);
  p.refinement.rho = schedule.refinement_rho;
  p.depth_min = problem.depth_min;
  p.depth_max = problem.depth_max;
  p.geometric = schedule.geometric;
  p.geom_lambda = schedule.geometric ? schedule.geom_lambda : 0.f;
  p.geom_max_error = schedule.geom_error_clamp;
  p.noise_variance = schedule.noise_floor ? problem.ref_noise_variance : 0.f;
  p.use_prior = schedule.use_prior;
  p.settled_skips = schedule.settled_skips;
  p.costed_views = schedule.costed_views;
  p.prior.plane = problem.prior_plane;
  p.prior.label = problem.prior_label;
  p.prior.gamma = schedule.prior_gamma;
  p.prior.beta = schedule.prior_beta;
  p.prior.sigma_depth = (problem.depth_max - problem.depth_min) / 64.f;
  p.prior.sigma_normal = schedule.prior_sigma_normal_deg * kPi / 180.f;
  p.seed = schedule.seed;
  p.image_id = problem.image_id;
  return p;
}

namespace {
// Random streams: stage id in the high 16 bits, pass number in the low bits (0 = init).
uint32_t PassStream(const PatchMatchSchedule& schedule, uint32_t pass) {
  return (schedule.stage_id << 16) + pass;
}
}  // namespace

void SetInitPass(const PatchMatchSchedule& schedule, PassParams* params) {
  params->window = WindowForScale(schedule.iterations.front().window_scale);
  params->color = 0;
  params->rng_iteration = PassStream(schedule, 0);
}

void SetCheckerboardPass(const PatchMatchSchedule& schedule, int iteration, int color,
                         PassParams* params) {
  const IterationSpec& spec = schedule.iterations[iteration];
  params->window = WindowForScale(spec.window_scale);
  params->view_selection.good_threshold =
      GoodMatchThreshold(spec.tau_index, schedule.tau0, schedule.tau_alpha);
  params->new_window_scale =
      iteration > 0 && schedule.iterations[iteration - 1].window_scale != spec.window_scale;
  params->color = color;
  params->iteration = static_cast<uint32_t>(iteration);
  params->rng_iteration = PassStream(schedule, static_cast<uint32_t>(1 + 2 * iteration + color));
}

IterationStats MakeIterationStats(const PatchMatchSchedule& schedule, int iteration,
                                  uint64_t ncc_evaluations, double seconds) {
  const IterationSpec& spec = schedule.iterations[iteration];
  IterationStats stats;
  stats.window_scale = spec.window_scale;
  stats.window_side = WindowSide(WindowForScale(spec.window_scale));
  stats.pattern = schedule.pattern;
  stats.tau = GoodMatchThreshold(spec.tau_index, schedule.tau0, schedule.tau_alpha);
  stats.ncc_evaluations = ncc_evaluations;
  stats.seconds = seconds;
  return stats;
}

void ResetResult(int width, int height, PatchMatchResult* result) {
  const StateLayout layout = MakeStateLayout(width, height);
  result->width = width;
  result->height = height;
  result->plane.assign(layout.plane_floats, 0.f);
  result->cost.assign(layout.cost_floats, kInvalidCost);
  result->photo_cost.assign(layout.cost_floats, kInvalidCost);
  result->geo_error.assign(layout.cost_floats, 0.f);
  result->view_mask.assign(layout.mask_words, 0u);
  result->init_ncc_evaluations = 0;
  result->iterations.clear();
}

size_t InvalidateGeometricallyInconsistent(float geom_max_error, PatchMatchResult* result) {
  size_t count = 0;
  for (size_t i = 0; i < result->geo_error.size(); ++i) {
    if (result->geo_error[i] >= geom_max_error * (1.f - 1e-4f) && result->photo_cost[i] < kInvalidCost) {
      result->photo_cost[i] = kInvalidCost;
      ++count;
    }
  }
  return count;
}

void ExtractDepthNormalMaps(const PatchMatchProblem& problem, const PatchMatchResult& result,
                            std::vector<float>* depth, std::vector<float>* normal) {
  const int W = result.width, H = result.height;
  const size_t n = static_cast<size_t>(W) * H;
  depth->assign(n, 0.f);
  normal->assign(3 * n, 0.f);
  PixelState state;
  state.plane = const_cast<float*>(result.plane.data());
  state.photo_cost = const_cast<float*>(result.photo_cost.data());
  PassParams params;
  params.ref_camera = problem.ref_camera;
  params.depth_min = problem.depth_min;
  params.depth_max = problem.depth_max;
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      Vec3 nrm;
      const size_t i = static_cast<size_t>(v) * W + u;
      ExtractDepthNormal(params, state, u, v, &(*depth)[i], &nrm);
      (*normal)[i] = nrm.x;
      (*normal)[n + i] = nrm.y;
      (*normal)[2 * n + i] = nrm.z;
    }
  }
}

}  // namespace kernels
}  // namespace mpmvs

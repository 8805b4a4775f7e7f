#include "kernels/patch_match.h"

#include <stdexcept>

namespace mpmvs {
namespace kernels {

void PatchMatchSchedule::Check() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (iterations.empty()) fail("a PatchMatch schedule needs at least one iteration");
  for (const IterationSpec& it : iterations) {
    if (it.window_scale < 0 || it.window_scale > 4) fail("window scale must be in [0, 4]");
    if (it.tau_index < 0) fail("tau index must be >= 0");
  }
  if (geom_lambda < 0.f) fail("geometric weight must be >= 0");
  if (geom_max_error <= 0.f) fail("geometric clamp must be > 0");
  if (refinement_rho <= 0.f || refinement_rho >= 1.f) fail("refinement rho must be in (0, 1)");
  if (tau0 <= 0.f || tau_alpha <= 0.f) fail("tau0 and alpha must be > 0");
  if (prior_beta <= 0.f || prior_sigma_normal_deg <= 0.f) fail("prior sigmas must be > 0");
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
  p.geom_max_error = schedule.geom_max_error;
  p.use_prior = schedule.use_prior;
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

#if !defined(MPMVS_WITH_CUDA)
bool CudaDeviceAvailable(int, std::string* why) {
  if (why) *why = "this build of mp-mvs has no CUDA backend (nvcc was not found at build time)";
  return false;
}

void RunPatchMatchCuda(const PatchMatchProblem&, const PatchMatchSchedule&, int,
                       PatchMatchResult*, const ProgressCallback&) {
  throw std::runtime_error("this build of mp-mvs has no CUDA backend");
}
#endif

}  // namespace kernels
}  // namespace mpmvs

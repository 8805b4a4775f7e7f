#pragma once
// Kernel schedules for tests that build them by hand: the kernels keep no option defaults
// (they come from the run's plan), so these take the declared ones.
#include "colmap_ext/options/patch_match_options.h"
#include "kernels/patch_match.h"

namespace mpmvs {
namespace test {

// The declared --MPMVS defaults of the schedule's option values, but prior_beta at ACMP's
// 0.18 (the kernel-level tests of the prior are ACMP's); no iterations.
inline kernels::PatchMatchSchedule ScheduleWithOptionDefaults() {
  const MpMvsOptions options;
  kernels::PatchMatchSchedule schedule;
  schedule.geom_lambda = static_cast<float>(options.geom_weight);
  schedule.geom_error_clamp = static_cast<float>(options.geom_max_error);
  schedule.refinement_rho = static_cast<float>(options.refinement_rho);
  schedule.prior_beta = kernels::kAcmpBeta;
  return schedule;
}

}  // namespace test
}  // namespace mpmvs

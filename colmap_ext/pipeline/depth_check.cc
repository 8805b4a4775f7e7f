#include "colmap_ext/pipeline/depth_check.h"

#include <vector>

#include "kernels/depth_segments.h"

namespace mpmvs {

DepthCheckCounts RunDepthCheck(const kernels::PatchMatchProblem& problem, float geom_error_clamp, int min_views,
                               float model_tolerance, int num_threads, kernels::PatchMatchResult* result) {
  kernels::InvalidateGeometricallyInconsistent(geom_error_clamp, result);
  const std::vector<float> differences = kernels::ConfirmingDifferencesCpu(problem, min_views, num_threads, *result);
  DepthCheckCounts counts;
  counts.agreement = ImageAgreementOf(differences, model_tolerance);
  counts.unconfirmed = kernels::InvalidateUnconfirmedDepths(differences, counts.agreement.tolerance, result);
  counts.speckles = kernels::InvalidateSmallDepthSegments(problem, kDepthCheckMinSegmentPixels,
                                                          kDepthSegmentMaxRelativeStep, result);
  return counts;
}

void MarkConfirmingViews(const kernels::PatchMatchProblem& problem, float tolerance, int num_threads,
                         kernels::PatchMatchResult* result) {
  kernels::MarkConfirmingViewsCpu(problem, tolerance, num_threads, result);
}

}  // namespace mpmvs

#include "colmap_ext/pipeline/depth_check.h"

#include "kernels/depth_segments.h"

namespace mpmvs {

DepthCheckCounts RunDepthCheck(const kernels::PatchMatchProblem& problem, float geom_error_clamp, int min_views,
                               float tolerance, int num_threads, kernels::PatchMatchResult* result) {
  kernels::InvalidateGeometricallyInconsistent(geom_error_clamp, result);
  DepthCheckCounts counts;
  counts.unconfirmed = kernels::InvalidateUnconfirmedDepthsCpu(problem, min_views, tolerance,
                                                               num_threads, result);
  counts.speckles = kernels::InvalidateSmallDepthSegments(problem, kDepthCheckMinSegmentPixels,
                                                          kDepthSegmentMaxRelativeStep, result);
  return counts;
}

void MarkConfirmingViews(const kernels::PatchMatchProblem& problem, float tolerance, int num_threads,
                         kernels::PatchMatchResult* result) {
  kernels::MarkConfirmingViewsCpu(problem, tolerance, num_threads, result);
}

}  // namespace mpmvs

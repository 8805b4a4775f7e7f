#include "colmap_ext/pipeline/depth_check.h"

#include "kernels/depth_segments.h"

namespace mpmvs {

DepthCheckCounts RunDepthCheck(const kernels::PatchMatchProblem& problem, float geom_error_clamp, int min_views,
                               int num_threads, kernels::PatchMatchResult* result) {
  kernels::InvalidateGeometricallyInconsistent(geom_error_clamp, result);
  DepthCheckCounts counts;
  counts.unconfirmed = kernels::InvalidateUnconfirmedDepthsCpu(problem, min_views, kDepthCheckMaxRelativeError,
                                                               num_threads, result);
  counts.speckles = kernels::InvalidateSmallDepthSegments(problem, kDepthCheckMinSegmentPixels,
                                                          kDepthCheckMaxRelativeError, result);
  return counts;
}

void MarkConfirmingViews(const kernels::PatchMatchProblem& problem, int num_threads,
                         kernels::PatchMatchResult* result) {
  kernels::MarkConfirmingViewsCpu(problem, kDepthCheckMaxRelativeError, num_threads, result);
}

}  // namespace mpmvs

#include "colmap_ext/pipeline/depth_check.h"

#include "kernels/depth_segments.h"

namespace mpmvs {

DepthCheckCounts RunDepthCheck(const kernels::PatchMatchProblem& problem, float geom_max_error, int min_views,
                               int num_threads, kernels::PatchMatchResult* result) {
  kernels::InvalidateGeometricallyInconsistent(geom_max_error, result);
  DepthCheckCounts counts;
  counts.unconfirmed = kernels::InvalidateUnconfirmedDepthsCpu(problem, min_views, kDepthCheckMaxRelativeError,
                                                               num_threads, result);
  counts.speckles = kernels::InvalidateSmallDepthSegments(problem, kDepthCheckMinSegmentPixels,
                                                          kDepthCheckMaxRelativeError, result);
  return counts;
}

}  // namespace mpmvs

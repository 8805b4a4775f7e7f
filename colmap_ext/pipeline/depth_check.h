#pragma once
// The depth_check stage (kernels/DESIGN.md items 22, 23): no PatchMatch iterations, only
// the pixels of the last geometric pass that the written map should keep.
#include <cstddef>

#include "colmap_ext/plan/depth_check_tolerance.h"
#include "kernels/patch_match.h"

namespace mpmvs {

// Neighbours within this relative depth difference join one depth segment (1 %, the
// check's tolerance for exactly posed models; depth_check_tolerance.h).
constexpr float kDepthSegmentMaxRelativeStep = kDepthCheckBaseTolerance;
// Depth segments smaller than this go: isolated speckles, mostly wrong.
constexpr int kDepthCheckMinSegmentPixels = 100;

struct DepthCheckCounts {
  ImageAgreement agreement;  // the tolerance the check used, and why
  size_t unconfirmed = 0;    // fewer than min_views sources confirm the depth
  size_t speckles = 0;       // in a depth segment under kDepthCheckMinSegmentPixels
};

// Invalidates, in order, the pixels whose geometric term is saturated (which the written map
// leaves out anyway, so they split no segment), those that fewer than min_views sources'
// results confirm within the image's tolerance (relative to depth: model_tolerance, widened
// by ImageAgreementOf), and those in small depth segments. problem's sources carry their
// results of the same pass as *result.
DepthCheckCounts RunDepthCheck(const kernels::PatchMatchProblem& problem, float geom_error_clamp, int min_views,
                               float model_tolerance, int num_threads, kernels::PatchMatchResult* result);

// The geometric consistency graph of the check's maps (write_consistency_graph): sets
// result->view_mask to the sources whose results confirm each remaining pixel's depth within
// tolerance.
void MarkConfirmingViews(const kernels::PatchMatchProblem& problem, float tolerance, int num_threads,
                         kernels::PatchMatchResult* result);

}  // namespace mpmvs

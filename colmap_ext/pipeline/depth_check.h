#pragma once
// The depth_check stage (kernels/DESIGN.md items 22, 23): no PatchMatch iterations, only
// the pixels of the last geometric pass that the written map should keep.
#include <cstddef>

#include "kernels/patch_match.h"

namespace mpmvs {

// The check's tolerance, relative to depth: COLMAP stereo_fusion's max_depth_error. It is
// also the step that joins neighbours into one depth segment.
constexpr float kDepthCheckMaxRelativeError = 0.01f;
// Depth segments smaller than this go: isolated speckles, mostly wrong.
constexpr int kDepthCheckMinSegmentPixels = 100;

struct DepthCheckCounts {
  size_t unconfirmed = 0;  // fewer than min_views sources confirm the depth
  size_t speckles = 0;     // in a depth segment under kDepthCheckMinSegmentPixels
};

// Invalidates, in order, the pixels whose geometric term is saturated (which the written map
// leaves out anyway, so they split no segment), those that fewer than min_views sources'
// results confirm, and those in small depth segments. problem's sources carry their results
// of the same pass as *result.
DepthCheckCounts RunDepthCheck(const kernels::PatchMatchProblem& problem, float geom_error_clamp, int min_views,
                               int num_threads, kernels::PatchMatchResult* result);

// The geometric consistency graph of the check's maps (write_consistency_graph): sets
// result->view_mask to the sources whose results confirm each remaining pixel's depth.
void MarkConfirmingViews(const kernels::PatchMatchProblem& problem, int num_threads,
                         kernels::PatchMatchResult* result);

}  // namespace mpmvs

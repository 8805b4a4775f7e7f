#pragma once
// Removal of small depth segments (speckles) from a finished result (host, one thread).
#include <cstddef>

#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {

// Splits the pixels with a depth into segments of 4-neighbours whose depths differ by less
// than max_relative_step (relative to the smaller) and invalidates (photometric cost 2)
// every pixel of a segment with fewer than min_pixels pixels; returns how many.
size_t InvalidateSmallDepthSegments(const PatchMatchProblem& problem, int min_pixels, float max_relative_step,
                                    PatchMatchResult* result);

}  // namespace kernels
}  // namespace mpmvs

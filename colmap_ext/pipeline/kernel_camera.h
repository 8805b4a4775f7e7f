#pragma once
// The kernels' float camera of a workspace view, and the host-side check of (reference,
// source) pairs the kernels can get nothing from.
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "kernels/camera.h"

namespace mpmvs {

// Same size, K, R and t as the view, in float.
kernels::Camera ToKernelCamera(const DenseView& view);

// Why source `src` can contribute nothing, or nearly nothing, to reference `ref` over
// depths [depth_min, depth_max], or "" when it can: intrinsics far beyond any lens, the
// reference's view entirely behind it, or reference rays running in its image plane (their
// points project arbitrarily far out). The kernels cope with all of these; this names them.
std::string DegenerateSourceReason(const DenseView& ref, const DenseView& src, double depth_min,
                                   double depth_max);

}  // namespace mpmvs

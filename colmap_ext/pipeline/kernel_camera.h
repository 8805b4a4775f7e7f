#pragma once
// The kernels' float camera of a workspace view.
#include "colmap_ext/io/dense_workspace.h"
#include "kernels/camera.h"

namespace mpmvs {

// Same size, K, R and t as the view, in float.
kernels::Camera ToKernelCamera(const DenseView& view);

}  // namespace mpmvs

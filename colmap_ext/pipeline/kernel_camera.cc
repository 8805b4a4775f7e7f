#include "colmap_ext/pipeline/kernel_camera.h"

namespace mpmvs {

kernels::Camera ToKernelCamera(const DenseView& view) {
  kernels::Camera c;
  c.width = view.width;
  c.height = view.height;
  c.fx = static_cast<float>(view.K[0]);
  c.fy = static_cast<float>(view.K[4]);
  c.cx = static_cast<float>(view.K[2]);
  c.cy = static_cast<float>(view.K[5]);
  for (int i = 0; i < 9; ++i) c.R[i] = static_cast<float>(view.R[i]);
  for (int i = 0; i < 3; ++i) c.t[i] = static_cast<float>(view.T[i]);
  return c;
}

}  // namespace mpmvs

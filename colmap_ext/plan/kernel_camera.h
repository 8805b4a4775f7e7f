#pragma once
// The kernels' float cameras of workspace views, in a frame chosen per reference image, and
// the host-side check of (reference, source) pairs the kernels can get nothing from.
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "kernels/camera.h"

namespace mpmvs {

// Where the kernels' cameras of one reference problem are expressed. The kernels form
// relative poses in float from float absolute poses: exact enough near the world origin,
// but a world origin millions of metres away (geo-referenced models: UTM, ECEF) leaves
// metres of error in every relative translation. Such problems get their cameras
// re-centred on the reference camera, computed in double; the others keep the world frame
// and with it their float rounding, i.e. their maps. Depths, normals and planes are in the
// reference camera frame either way.
struct KernelFrame {
  bool recentred = false;
  double origin[3] = {0, 0, 0};  // the world point that becomes the origin
};

// Largest error, in source pixels at depth_min, that the world frame may cost a relative
// pose before a problem is re-centred.
constexpr double kMaxWorldFrameErrorPx = 0.01;

// The frame of reference view `ref` with source views `src` (workspace view indices).
KernelFrame ChooseKernelFrame(const DenseWorkspace& workspace, int ref, const std::vector<int>& src,
                              double depth_min);

// The view's camera in `frame`: same size, K and R; t of the frame's origin; in float.
kernels::Camera ToKernelCamera(const DenseView& view, const KernelFrame& frame = KernelFrame());

// Why source `src` can contribute nothing, or nearly nothing, to reference `ref` over
// depths [depth_min, depth_max], or "" when it can: intrinsics far beyond any lens, the
// reference's view entirely behind it, or reference rays running in its image plane (their
// points project arbitrarily far out). The kernels cope with all of these; this names them.
std::string DegenerateSourceReason(const DenseView& ref, const DenseView& src, double depth_min,
                                   double depth_max);

}  // namespace mpmvs

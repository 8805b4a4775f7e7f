#pragma once
// The depth check's tolerance (kernels/DESIGN.md 22): COLMAP stereo_fusion's max_depth_error,
// 1 % of the depth, widened where the sparse model says that the poses are less exact. There
// the views' maps disagree by more, and a 1 % check empties pixels that are right within a few
// percent (docs/results.md, "Pose error and the depth check").
#include "colmap_ext/io/dense_workspace.h"

namespace mpmvs {

constexpr float kDepthCheckBaseTolerance = 0.01f;
// Tolerance per radian of the sparse points' mean reprojection error: 1 % at 2 mrad, which
// every exactly posed scene measured stays below (at most 1.3 mrad).
constexpr double kDepthCheckTolerancePerRadian = 5.0;

struct DepthCheckTolerance {
  float relative = kDepthCheckBaseTolerance;
  double mean_error_px = 0;   // the sparse points' mean reprojection error (model pixels)
  double mean_error_rad = 0;  // the same over the images' mean focal length
};

// max(1 %, kDepthCheckTolerancePerRadian x the points' mean reprojection error over the mean
// focal length of the workspace's images), at most 100 %. Points without a finite error of
// at least 0 (COLMAP writes -1 for none) are left out; without any, or without images, 1 %.
DepthCheckTolerance DepthCheckToleranceOf(const DenseWorkspace& workspace);

}  // namespace mpmvs

#pragma once
// The depth check's tolerance (kernels/DESIGN.md 22): COLMAP stereo_fusion's max_depth_error,
// 1 % of the depth, widened where the sparse model says that the poses are less exact, and
// for an image whose sources' maps hold its depths only roughly. There the views' maps
// disagree by more, and a 1 % check empties pixels that are right within a few percent
// (docs/results.md, "Pose error and the depth check", "The depth check follows the views'
// agreement").
#include <vector>

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

// An image's agreement with its sources: the median, over its pixels, of the difference
// within which its sources' maps confirm its depth (the one the check tests), leaving out
// differences above kAgreementMaxDifference (other surfaces or wrong depths). It is
// 0.016-0.10 % on the sharp scenes measured, up to 0.13 % on views along a corridor (depth
// resolution), and 0.12-0.34 % on blurred real frames.
constexpr float kAgreementMaxDifference = 0.05f;
constexpr float kDepthCheckTolerancePerMedianDifference = 15.f;

// Revision of the check's rule, which its results' records name (StageStore::InputsHash): a
// change bumps it, so that the depth checks of earlier builds are made again while the stages
// before them resume. 1: each image's tolerance follows its agreement (7 Dec 2026).
constexpr int kDepthCheckRevision = 1;

struct ImageAgreement {
  float median_difference = 0;  // over the pixels with a difference under kAgreementMaxDifference
  float tolerance = 0;          // the check's tolerance for the image
};

// The image's tolerance: max(model_tolerance, min(kAgreementMaxDifference,
// kDepthCheckTolerancePerMedianDifference x the median of its pixels' confirming differences
// under kAgreementMaxDifference)); model_tolerance where no pixel has one.
ImageAgreement ImageAgreementOf(const std::vector<float>& confirming_differences, float model_tolerance);

// max(1 %, kDepthCheckTolerancePerRadian x the points' mean reprojection error over the mean
// focal length of the workspace's images), at most 100 %. Points without a finite error of
// at least 0 (COLMAP writes -1 for none) are left out; without any, or without images, 1 %.
DepthCheckTolerance DepthCheckToleranceOf(const DenseWorkspace& workspace);

}  // namespace mpmvs

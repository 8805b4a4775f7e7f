#include "colmap_ext/plan/depth_check_tolerance.h"

#include <algorithm>
#include <cmath>

namespace mpmvs {

DepthCheckTolerance DepthCheckToleranceOf(const DenseWorkspace& workspace) {
  DepthCheckTolerance tolerance;
  // The errors are in the model's pixels: the focal lengths before max_image_size scaling.
  double focal_sum = 0;
  int focal_count = 0;
  for (const DenseView& view : workspace.views) {
    if (view.width <= 0 || view.height <= 0) continue;
    const double focal = 0.5 * (view.K[0] * view.original_width / view.width +
                                view.K[4] * view.original_height / view.height);
    if (!(focal > 0) || !std::isfinite(focal)) continue;
    focal_sum += focal;
    ++focal_count;
  }
  double error_sum = 0;
  size_t error_count = 0;
  for (const SparsePoint3D& point : workspace.model.points) {
    if (!std::isfinite(point.error) || point.error < 0) continue;
    error_sum += point.error;
    ++error_count;
  }
  if (focal_count == 0 || error_count == 0 || !std::isfinite(error_sum)) return tolerance;
  tolerance.mean_error_px = error_sum / error_count;
  tolerance.mean_error_rad = tolerance.mean_error_px / (focal_sum / focal_count);
  tolerance.relative = static_cast<float>(std::clamp(kDepthCheckTolerancePerRadian * tolerance.mean_error_rad,
                                                     static_cast<double>(kDepthCheckBaseTolerance), 1.0));
  return tolerance;
}

ImageAgreement ImageAgreementOf(const std::vector<float>& confirming_differences, float model_tolerance) {
  std::vector<float> agreeing;
  for (float d : confirming_differences) {
    if (d < kAgreementMaxDifference) agreeing.push_back(d);
  }
  ImageAgreement agreement;
  agreement.tolerance = model_tolerance;
  if (agreeing.empty()) return agreement;
  const auto middle = agreeing.begin() + agreeing.size() / 2;
  std::nth_element(agreeing.begin(), middle, agreeing.end());
  agreement.median_difference = *middle;
  agreement.tolerance = std::max(model_tolerance, std::min(kAgreementMaxDifference,
                                                           kDepthCheckTolerancePerMedianDifference * *middle));
  return agreement;
}

}  // namespace mpmvs

#include "colmap_ext/plan/depth_check_tolerance.h"

#include <algorithm>
#include <cmath>

namespace mpmvs {

DepthCheckTolerance DepthCheckToleranceOf(const SparseModel& model) {
  DepthCheckTolerance tolerance;
  double focal_sum = 0;
  int focal_count = 0;
  for (const SparseImage& image : model.images) {
    const int c = model.FindCamera(image.camera_id);
    if (c < 0 || model.cameras[c].params.empty()) continue;
    const std::vector<double>& params = model.cameras[c].params;
    // SIMPLE_PINHOLE: f, cx, cy; PINHOLE: fx, fy, cx, cy (undistorted workspaces have no other).
    const double focal = model.cameras[c].model_id == kPinholeModelId && params.size() >= 2
                             ? 0.5 * (params[0] + params[1])
                             : params[0];
    if (!(focal > 0)) continue;
    focal_sum += focal;
    ++focal_count;
  }
  double error_sum = 0;
  for (const SparsePoint3D& point : model.points) error_sum += point.error;
  if (focal_count == 0 || model.points.empty() || !std::isfinite(error_sum) || error_sum < 0) return tolerance;
  tolerance.mean_error_px = error_sum / model.points.size();
  tolerance.mean_error_rad = tolerance.mean_error_px / (focal_sum / focal_count);
  tolerance.relative = static_cast<float>(
      std::max<double>(kDepthCheckBaseTolerance, kDepthCheckTolerancePerRadian * tolerance.mean_error_rad));
  return tolerance;
}

}  // namespace mpmvs

#pragma once
// A sparse model as SfM would leave it for a synthetic scene: features only where a
// detector fires (corner-like image structure on TEXTURED materials), tracks only in views
// where the surface point is unoccluded, 2-D observations with sub-pixel noise, 3-D points
// triangulated from those noisy observations.
#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/synthetic/scene_renderer.h"

namespace mpmvs {

struct SparseSimulationOptions {
  int max_points = 2000;
  double observation_noise_px = 0.5;  // std. dev. of each 2-D coordinate
  int cell_size = 8;                  // at most one feature per cell x cell block per view
  // Shi-Tomasi score (smaller structure-tensor eigenvalue per pixel, in (grey levels/px)^2)
  // a feature needs; plain surfaces with sensor noise stay far below.
  double min_corner_score = 12.0;
  double max_view_angle_deg = 75.0;  // surfaces seen more obliquely yield no feature
  uint64_t seed = 1;

  void Check() const;  // throws Error
};

// names[i] is the image name of cameras[i] / views[i]. Image ids are 1..n in this order;
// cameras with identical intrinsics share one PINHOLE camera. Observations use COLMAP's
// SfM convention (pixel centre at +0.5): x = x_mvs + 0.5.
SparseModel SimulateSparseModel(const std::vector<SyntheticCamera>& cameras,
                                const std::vector<std::string>& names,
                                const std::vector<RenderedView>& views,
                                const SparseSimulationOptions& options);

// Where a model's points lie according to the GT. In each view of its track a point is
// projected (MVS convention) to its nearest pixel; it agrees there when its depth is within
// depth_tolerance (relative) of the GT depth. A point is on a surface when it agrees in at
// least half of the views it projects into, and on an untextured surface when most of those
// agreeing pixels are marked untextured.
struct SparsePointLabels {
  int on_textured = 0;
  int on_untextured = 0;
  int off_surface = 0;  // depth disagrees with the GT: a wrong match or a poor triangulation
};
// cameras/views in the model's image order.
SparsePointLabels LabelSparsePoints(const SparseModel& model,
                                    const std::vector<SyntheticCamera>& cameras,
                                    const std::vector<RenderedView>& views,
                                    double depth_tolerance = 0.03);

// COLMAP's patch-match depth range for image `image_index` of the model: sorted z of its
// observed points, 0.75 * z[floor(0.01 n)], 1.25 * z[floor(0.99 n)]; false without points.
bool SparseDepthRange(const SparseModel& model, int image_index, double* depth_min,
                      double* depth_max);

}  // namespace mpmvs

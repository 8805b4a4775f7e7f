#include "colmap_ext/plan/kernel_camera.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mpmvs {
namespace {

// Relative translation of src w.r.t. ref in double: t_s - R_s R_r^T t_r.
void ExactRelativeTranslation(const DenseView& ref, const DenseView& src, double t[3]) {
  double c[3];  // R_r^T t_r = -C_r
  for (int j = 0; j < 3; ++j) c[j] = ref.R[j] * ref.T[0] + ref.R[3 + j] * ref.T[1] + ref.R[6 + j] * ref.T[2];
  for (int i = 0; i < 3; ++i) {
    t[i] = src.T[i] - (src.R[3 * i] * c[0] + src.R[3 * i + 1] * c[1] + src.R[3 * i + 2] * c[2]);
  }
}

// A point of the reference camera frame in the source camera frame, in double.
void RefToSource(const DenseView& ref, const DenseView& src, const double X[3], double Xs[3]) {
  double W[3];  // world point: R_r^T (X - t_r)
  for (int j = 0; j < 3; ++j) {
    W[j] = ref.R[j] * (X[0] - ref.T[0]) + ref.R[3 + j] * (X[1] - ref.T[1]) + ref.R[6 + j] * (X[2] - ref.T[2]);
  }
  for (int i = 0; i < 3; ++i) {
    Xs[i] = src.R[3 * i] * W[0] + src.R[3 * i + 1] * W[1] + src.R[3 * i + 2] * W[2] + src.T[i];
  }
}

}  // namespace

KernelFrame ChooseKernelFrame(const DenseWorkspace& workspace, int ref, const std::vector<int>& src,
                              double depth_min) {
  const DenseView& r = workspace.views[ref];
  const kernels::Camera ref_world = ToKernelCamera(r);
  double worst_px = 0;
  for (int s : src) {
    const DenseView& v = workspace.views[s];
    // The relative translation the kernels would form in the world frame, against the exact one.
    const kernels::RelativePose rel = kernels::ComputeRelativePose(ref_world, ToKernelCamera(v));
    double exact[3];
    ExactRelativeTranslation(r, v, exact);
    double error = 0;
    for (int i = 0; i < 3; ++i) error = std::max(error, std::abs(static_cast<double>(rel.t[i]) - exact[i]));
    const double px = std::max(std::abs(v.K[0]), std::abs(v.K[4])) * error / std::max(depth_min, 1e-12);
    worst_px = std::max(worst_px, std::isfinite(px) ? px : HUGE_VAL);
  }
  KernelFrame frame;
  if (worst_px > kMaxWorldFrameErrorPx) {
    frame.recentred = true;
    for (int j = 0; j < 3; ++j) {  // C_r = -R_r^T t_r
      frame.origin[j] = -(r.R[j] * r.T[0] + r.R[3 + j] * r.T[1] + r.R[6 + j] * r.T[2]);
    }
  }
  return frame;
}

kernels::Camera ToKernelCamera(const DenseView& view, const KernelFrame& frame) {
  kernels::Camera c;
  c.width = view.width;
  c.height = view.height;
  c.fx = static_cast<float>(view.K[0]);
  c.fy = static_cast<float>(view.K[4]);
  c.cx = static_cast<float>(view.K[2]);
  c.cy = static_cast<float>(view.K[5]);
  for (int i = 0; i < 9; ++i) c.R[i] = static_cast<float>(view.R[i]);
  for (int i = 0; i < 3; ++i) {
    // X_cam = R (X' + origin) + t for X' = X - origin.
    const double t = frame.recentred ? view.T[i] + view.R[3 * i] * frame.origin[0] +
                                           view.R[3 * i + 1] * frame.origin[1] +
                                           view.R[3 * i + 2] * frame.origin[2]
                                     : view.T[i];
    c.t[i] = static_cast<float>(t);
  }
  return c;
}

std::string DegenerateSourceReason(const DenseView& ref, const DenseView& src, double depth_min,
                                   double depth_max) {
  // Intrinsics: a field of view below ~0.06 degrees or above ~179.9 degrees, or a principal
  // point more than ten image sizes away from the image.
  const double size = std::max(src.width, src.height);
  const double fx = src.K[0], fy = src.K[4], cx = src.K[2], cy = src.K[5];
  const auto extreme_focal = [&](double f) { return !(f > 1e-3 * size && f < 1e3 * size); };
  if (extreme_focal(fx) || extreme_focal(fy) || !(std::abs(cx - 0.5 * src.width) < 10 * size) ||
      !(std::abs(cy - 0.5 * src.height) < 10 * size)) {
    std::ostringstream why;
    why << "its intrinsics are extreme (fx " << fx << ", fy " << fy << ", cx " << cx << ", cy " << cy
        << " for " << src.width << "x" << src.height << " px)";
    return why.str();
  }
  // The reference's rays through its image corners, at depth_min and depth_max, in the
  // source frame. The view is the convex hull of these 8 points.
  const double corners[4][2] = {{0, 0}, {ref.width - 1.0, 0}, {0, ref.height - 1.0}, {ref.width - 1.0, ref.height - 1.0}};
  bool any_in_front = false;
  double min_slope = HUGE_VAL, max_slope = -HUGE_VAL;  // source z per unit length along each ray
  for (const auto& corner : corners) {
    const double ray[3] = {(corner[0] - ref.K[2]) / ref.K[0], (corner[1] - ref.K[5]) / ref.K[4], 1.0};
    double Xs[2][3];
    for (int k = 0; k < 2; ++k) {
      const double depth = k == 0 ? depth_min : depth_max;
      const double X[3] = {depth * ray[0], depth * ray[1], depth};
      RefToSource(ref, src, X, Xs[k]);
      if (Xs[k][2] > 0) any_in_front = true;
    }
    double d[3], length = 0;
    for (int i = 0; i < 3; ++i) {
      d[i] = Xs[1][i] - Xs[0][i];
      length += d[i] * d[i];
    }
    length = std::sqrt(length);
    if (length > 0) {
      min_slope = std::min(min_slope, d[2] / length);
      max_slope = std::max(max_slope, d[2] / length);
    }
  }
  if (!any_in_front) return "the reference's whole view (within its depth range) is behind it";
  // Reference rays run in the source's image plane when the reference centre lies within
  // sin(1 deg) * depth_min of that plane and some reference ray is parallel to it (the
  // source z per unit length changes sign over the image corners).
  double t[3];
  ExactRelativeTranslation(ref, src, t);  // t[2]: the reference centre's source z
  const double s = std::sin(M_PI / 180.0);
  if (std::abs(t[2]) <= s * depth_min && min_slope <= s && max_slope >= -s) {
    return "the reference camera lies in its image plane and reference rays run along that plane "
           "(their points project arbitrarily far out of it)";
  }
  return "";
}

}  // namespace mpmvs

#include "colmap_ext/synthetic/synthetic_sparse.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Dense>

#include "colmap_ext/synthetic/synthetic_random.h"
#include "colmap_ext/util/error.h"

namespace mpmvs {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

struct Candidate {
  Eigen::Vector3d X;
  int view = 0;
  int col = 0, row = 0;
  std::vector<int> visible;  // views where the point is observed (source included)
};

std::vector<float> GreyOf(const RgbImage& image) {
  std::vector<float> grey(static_cast<size_t>(image.width) * image.height);
  for (size_t i = 0; i < grey.size(); ++i) {
    grey[i] = 0.299f * image.data[3 * i] + 0.587f * image.data[3 * i + 1] +
              0.114f * image.data[3 * i + 2];
  }
  return grey;
}

// Per-pixel Shi-Tomasi score: smaller eigenvalue of the structure tensor summed over a
// 5x5 window, divided by the window size. 0 near the border.
std::vector<float> CornerScores(const std::vector<float>& grey, int w, int h) {
  std::vector<float> ixx(grey.size(), 0), ixy(grey.size(), 0), iyy(grey.size(), 0);
  for (int r = 1; r < h - 1; ++r) {
    for (int c = 1; c < w - 1; ++c) {
      const size_t i = static_cast<size_t>(r) * w + c;
      const float gx = 0.5f * (grey[i + 1] - grey[i - 1]);
      const float gy = 0.5f * (grey[i + w] - grey[i - w]);
      ixx[i] = gx * gx;
      ixy[i] = gx * gy;
      iyy[i] = gy * gy;
    }
  }
  std::vector<float> score(grey.size(), 0);
  constexpr int kRadius = 2;
  for (int r = kRadius + 1; r < h - kRadius - 1; ++r) {
    for (int c = kRadius + 1; c < w - kRadius - 1; ++c) {
      double a = 0, b = 0, d = 0;
      for (int dr = -kRadius; dr <= kRadius; ++dr) {
        for (int dc = -kRadius; dc <= kRadius; ++dc) {
          const size_t j = static_cast<size_t>(r + dr) * w + (c + dc);
          a += ixx[j];
          b += ixy[j];
          d += iyy[j];
        }
      }
      const double n = (2 * kRadius + 1) * (2 * kRadius + 1);
      a /= n, b /= n, d /= n;
      const double half_trace = 0.5 * (a + d);
      const double disc = std::sqrt(0.25 * (a - d) * (a - d) + b * b);
      score[static_cast<size_t>(r) * w + c] = static_cast<float>(half_trace - disc);
    }
  }
  return score;
}

// Whether world point X (seen at depth z in view v) is an unoccluded, textured, not too
// oblique surface point of view v; returns the image coordinate.
bool VisibleIn(const SyntheticCamera& cam, const RenderedView& view, const Eigen::Vector3d& X,
               double max_angle_cos, double* x, double* y) {
  double z;
  if (!cam.Project(X, x, y, &z)) return false;
  const int col = static_cast<int>(std::lround(*x)), row = static_cast<int>(std::lround(*y));
  constexpr int kMargin = 3;
  if (col < kMargin || row < kMargin || col >= cam.width - kMargin || row >= cam.height - kMargin) {
    return false;
  }
  const float gt = view.depth.At(row, col);
  if (gt <= 0 || std::abs(z - gt) > 0.01 * gt) return false;  // occluded or off-surface
  if (view.untextured[static_cast<size_t>(row) * cam.width + col]) return false;
  const Eigen::Vector3d n(view.normal.At(row, col, 0), view.normal.At(row, col, 1),
                          view.normal.At(row, col, 2));
  const Eigen::Vector3d ray = (cam.R * X + cam.t).normalized();
  return -n.dot(ray) >= max_angle_cos;
}

// Least-squares point closest to all rays (camera centre + direction).
Eigen::Vector3d TriangulateRays(const std::vector<Eigen::Vector3d>& centers,
                                const std::vector<Eigen::Vector3d>& directions) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < centers.size(); ++i) {
    const Eigen::Vector3d d = directions[i].normalized();
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - d * d.transpose();
    A += P;
    b += P * centers[i];
  }
  return A.ldlt().solve(b);
}

int64_t VoxelKeyPart(double v, double size) { return static_cast<int64_t>(std::floor(v / size)); }

uint64_t VoxelKey(int64_t x, int64_t y, int64_t z) {
  return SynthHash(static_cast<uint64_t>(x), static_cast<uint64_t>(y), static_cast<uint64_t>(z));
}

}  // namespace

void SparseSimulationOptions::Check() const {
  if (max_points < 1) throw Error("sparse simulation: max_points must be >= 1");
  if (observation_noise_px < 0) throw Error("sparse simulation: observation noise must be >= 0");
  if (cell_size < 2) throw Error("sparse simulation: cell_size must be >= 2");
  if (max_view_angle_deg <= 0 || max_view_angle_deg > 90) {
    throw Error("sparse simulation: max_view_angle_deg must be in (0, 90]");
  }
}

SparseModel SimulateSparseModel(const std::vector<SyntheticCamera>& cameras,
                                const std::vector<std::string>& names,
                                const std::vector<RenderedView>& views,
                                const SparseSimulationOptions& options) {
  options.Check();
  const int n = static_cast<int>(cameras.size());
  if (static_cast<int>(names.size()) != n || static_cast<int>(views.size()) != n) {
    throw Error("SimulateSparseModel: cameras, names and views differ in number");
  }
  const double max_angle_cos = std::cos(options.max_view_angle_deg * kDegToRad);

  // 1. Detect: the strongest corner per grid cell on textured, visible surfaces.
  std::vector<Candidate> candidates;
  for (int v = 0; v < n; ++v) {
    const SyntheticCamera& cam = cameras[v];
    const RenderedView& view = views[v];
    const std::vector<float> score = CornerScores(GreyOf(view.image), cam.width, cam.height);
    const int cs = options.cell_size;
    for (int r0 = 0; r0 < cam.height; r0 += cs) {
      for (int c0 = 0; c0 < cam.width; c0 += cs) {
        int best_col = -1, best_row = -1;
        float best = static_cast<float>(options.min_corner_score);
        for (int r = r0; r < std::min(cam.height, r0 + cs); ++r) {
          for (int c = c0; c < std::min(cam.width, c0 + cs); ++c) {
            const size_t i = static_cast<size_t>(r) * cam.width + c;
            if (score[i] > best && !view.untextured[i] && view.depth.At(r, c) > 0) {
              best = score[i];
              best_col = c;
              best_row = r;
            }
          }
        }
        if (best_col < 0) continue;
        Candidate cand;
        const double z = view.depth.At(best_row, best_col);
        const Eigen::Vector3d Xc(z * (best_col - cam.cx) / cam.fx, z * (best_row - cam.cy) / cam.fy, z);
        cand.X = cam.R.transpose() * (Xc - cam.t);
        cand.view = v;
        cand.col = best_col;
        cand.row = best_row;
        for (int j = 0; j < n; ++j) {
          double x, y;
          if (VisibleIn(cameras[j], views[j], cand.X, max_angle_cos, &x, &y)) {
            cand.visible.push_back(j);
          }
        }
        if (cand.visible.size() >= 2) candidates.push_back(std::move(cand));
      }
    }
  }

  // 2. Merge re-detections of the same surface spot from different views (SfM would
  // have matched them into one track): drop candidates within 3 pixel footprints of an
  // already accepted one.
  std::vector<double> footprint(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) {
    const SyntheticCamera& cam = cameras[candidates[i].view];
    footprint[i] = 3.0 * (cam.R * candidates[i].X + cam.t).z() / cam.fx;
  }
  std::vector<Candidate> unique;
  if (!candidates.empty()) {
    std::vector<double> sorted = footprint;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double voxel = std::max(1e-6, sorted[sorted.size() / 2]);
    std::unordered_map<uint64_t, std::vector<int>> grid;
    for (size_t i = 0; i < candidates.size(); ++i) {
      const Eigen::Vector3d& X = candidates[i].X;
      const int64_t kx = VoxelKeyPart(X.x(), voxel), ky = VoxelKeyPart(X.y(), voxel),
                    kz = VoxelKeyPart(X.z(), voxel);
      const int64_t reach = static_cast<int64_t>(std::ceil(footprint[i] / voxel));
      bool duplicate = false;
      for (int64_t dx = -reach; dx <= reach && !duplicate; ++dx) {
        for (int64_t dy = -reach; dy <= reach && !duplicate; ++dy) {
          for (int64_t dz = -reach; dz <= reach && !duplicate; ++dz) {
            auto it = grid.find(VoxelKey(kx + dx, ky + dy, kz + dz));
            if (it == grid.end()) continue;
            for (int k : it->second) {
              if ((unique[k].X - X).norm() < footprint[i]) {
                duplicate = true;
                break;
              }
            }
          }
        }
      }
      if (duplicate) continue;
      grid[VoxelKey(kx, ky, kz)].push_back(static_cast<int>(unique.size()));
      unique.push_back(candidates[i]);
    }
  }

  // 3. Keep at most max_points, chosen by a seeded hash so the choice is reproducible.
  if (static_cast<int>(unique.size()) > options.max_points) {
    std::vector<std::pair<uint64_t, int>> keys(unique.size());
    for (size_t i = 0; i < unique.size(); ++i) keys[i] = {SynthHash(options.seed, 0x5e1ec7, i), static_cast<int>(i)};
    std::sort(keys.begin(), keys.end());
    keys.resize(options.max_points);
    std::vector<int> keep;
    for (const auto& k : keys) keep.push_back(k.second);
    std::sort(keep.begin(), keep.end());
    std::vector<Candidate> kept;
    for (int i : keep) kept.push_back(std::move(unique[i]));
    unique = std::move(kept);
  }

  // 4. The model: cameras, images, points with noisy observations and triangulated xyz.
  SparseModel model;
  std::vector<uint32_t> camera_of_view(n);
  for (int v = 0; v < n; ++v) {
    const SyntheticCamera& c = cameras[v];
    const std::vector<double> params = {c.fx, c.fy, c.cx, c.cy};
    uint32_t id = 0;
    for (const SparseCamera& existing : model.cameras) {
      if (existing.params == params && existing.width == static_cast<uint64_t>(c.width) &&
          existing.height == static_cast<uint64_t>(c.height)) {
        id = existing.camera_id;
      }
    }
    if (id == 0) {
      SparseCamera sc;
      sc.camera_id = static_cast<uint32_t>(model.cameras.size() + 1);
      sc.model_id = kPinholeModelId;
      sc.width = c.width;
      sc.height = c.height;
      sc.params = params;
      model.cameras.push_back(sc);
      id = sc.camera_id;
    }
    camera_of_view[v] = id;
    SparseImage image;
    image.image_id = static_cast<uint32_t>(v + 1);
    double R[9];
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) R[3 * r + k] = c.R(r, k);
    }
    RotationMatrixToQuaternion(R, image.qvec);
    for (int k = 0; k < 3; ++k) image.tvec[k] = c.t[k];
    image.camera_id = id;
    image.name = names[v];
    model.images.push_back(image);
  }

  for (size_t k = 0; k < unique.size(); ++k) {
    const Candidate& cand = unique[k];
    SparsePoint3D point;
    point.point3D_id = k + 1;
    std::vector<Eigen::Vector3d> centers, directions;
    std::vector<Eigen::Vector2d> observations;
    for (int j : cand.visible) {
      const SyntheticCamera& cam = cameras[j];
      double x, y, z;
      cam.Project(cand.X, &x, &y, &z);
      const double sigma = options.observation_noise_px;
      x += sigma * SynthNormal(SynthHash(options.seed, k, j, 0));
      y += sigma * SynthNormal(SynthHash(options.seed, k, j, 1));
      observations.emplace_back(x, y);
      centers.push_back(cam.Center());
      directions.push_back(cam.RayThrough(x, y).direction);
    }
    const Eigen::Vector3d X = TriangulateRays(centers, directions);
    double error_sum = 0;
    for (size_t e = 0; e < cand.visible.size(); ++e) {
      const int j = cand.visible[e];
      double x, y, z;
      if (cameras[j].Project(X, &x, &y, &z)) {
        error_sum += (Eigen::Vector2d(x, y) - observations[e]).norm();
      }
      SparseImage& image = model.images[j];
      SparsePoint2D p2d;
      p2d.x = observations[e].x() + 0.5;  // SfM pixel-centre convention
      p2d.y = observations[e].y() + 0.5;
      p2d.point3D_id = point.point3D_id;
      point.track.push_back({image.image_id, static_cast<uint32_t>(image.points2D.size())});
      image.points2D.push_back(p2d);
    }
    for (int a = 0; a < 3; ++a) point.xyz[a] = X[a];
    const RgbImage& img = views[cand.view].image;
    const size_t pix = static_cast<size_t>(cand.row) * img.width + cand.col;
    for (int a = 0; a < 3; ++a) point.rgb[a] = img.data[3 * pix + a];
    point.error = error_sum / cand.visible.size();
    model.points.push_back(std::move(point));
  }
  return model;
}

SparsePointLabels LabelSparsePoints(const SparseModel& model,
                                    const std::vector<SyntheticCamera>& cameras,
                                    const std::vector<RenderedView>& views,
                                    double depth_tolerance) {
  SparsePointLabels labels;
  for (const SparsePoint3D& point : model.points) {
    const Eigen::Vector3d X(point.xyz[0], point.xyz[1], point.xyz[2]);
    int seen = 0, agree = 0, untextured = 0;
    for (const SparseTrackElement& t : point.track) {
      const int v = model.FindImageById(t.image_id);
      if (v < 0 || v >= static_cast<int>(cameras.size())) continue;
      const SyntheticCamera& cam = cameras[v];
      double x, y, z;
      if (!cam.Project(X, &x, &y, &z)) continue;
      const int col = static_cast<int>(std::lround(x)), row = static_cast<int>(std::lround(y));
      if (col < 0 || row < 0 || col >= cam.width || row >= cam.height) continue;
      ++seen;
      const float gt = views[v].depth.At(row, col);
      if (!(gt > 0) || std::abs(z - gt) > depth_tolerance * gt) continue;
      ++agree;
      untextured += views[v].untextured[static_cast<size_t>(row) * cam.width + col] != 0;
    }
    if (seen == 0 || 2 * agree < seen) {
      ++labels.off_surface;
    } else if (2 * untextured > agree) {
      ++labels.on_untextured;
    } else {
      ++labels.on_textured;
    }
  }
  return labels;
}

bool SparseDepthRange(const SparseModel& model, int image_index, double* depth_min,
                      double* depth_max) {
  const SparseImage& image = model.images.at(image_index);
  double R[9];
  QuaternionToRotationMatrix(image.qvec, R);
  std::unordered_map<uint64_t, int> index_of;
  for (size_t i = 0; i < model.points.size(); ++i) index_of[model.points[i].point3D_id] = static_cast<int>(i);
  std::vector<double> depths;
  for (const SparsePoint2D& p : image.points2D) {
    if (p.point3D_id == UINT64_MAX) continue;
    auto it = index_of.find(p.point3D_id);
    if (it == index_of.end()) continue;
    const double* X = model.points[it->second].xyz;
    const double z = R[6] * X[0] + R[7] * X[1] + R[8] * X[2] + image.tvec[2];
    if (z > 0) depths.push_back(z);
  }
  if (depths.empty()) return false;
  std::sort(depths.begin(), depths.end());
  const size_t n = depths.size();
  *depth_min = 0.75 * depths[static_cast<size_t>(std::floor(0.01 * n))];
  *depth_max = 1.25 * depths[std::min(n - 1, static_cast<size_t>(std::floor(0.99 * n)))];
  return true;
}

}  // namespace mpmvs

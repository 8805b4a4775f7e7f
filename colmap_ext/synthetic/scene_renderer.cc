#include "colmap_ext/synthetic/scene_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "colmap_ext/synthetic/synthetic_random.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/thread_range.h"

namespace mpmvs {
namespace {

constexpr double kShadowEps = 1e-4;
constexpr double kGamma = 1.0 / 2.2;

double PointIrradiance(const SceneGeometry& geometry, const ScenePointLight& light,
                       const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                       const Eigen::Vector3d& shadow_origin) {
  if (light.power <= 0) return 0;
  const Eigen::Vector3d to_light = light.position - p;
  const double dist2 = to_light.squaredNorm();
  const double ndl = n.dot(to_light) / std::sqrt(dist2);
  if (ndl <= 0) return 0;
  SceneRay shadow{shadow_origin, to_light};
  if (geometry.Occluded(shadow, 0, 1.0 - 1e-6)) return 0;
  return light.power * ndl / (dist2 + light.softness * light.softness);
}

Eigen::Vector3d Shade(const SyntheticWorld& world, const SceneRay& ray, const SceneHit& hit,
                      Eigen::Vector3d* oriented_normal) {
  const Eigen::Vector3d p = ray.origin + hit.t * ray.direction;
  Eigen::Vector3d n = hit.normal;
  if (n.dot(ray.direction) > 0) n = -n;  // two-sided surfaces: shade the visible side
  *oriented_normal = n;
  const SceneLighting& light = world.lighting;
  const Eigen::Vector3d shadow_origin = p + kShadowEps * n;
  double irradiance = light.ambient;
  if (light.sun_intensity > 0) {
    const Eigen::Vector3d l = -light.sun_direction.normalized();
    const double ndl = n.dot(l);
    if (ndl > 0) {
      SceneRay shadow{shadow_origin, l};
      if (!world.geometry.Occluded(shadow, 0, std::numeric_limits<double>::infinity())) {
        irradiance += light.sun_intensity * ndl;
      }
    }
  }
  if (light.has_point_light && light.point_power > 0) {
    const Eigen::Vector3d to_light = light.point_position - p;
    const double dist2 = to_light.squaredNorm();
    const double ndl = n.dot(to_light) / std::sqrt(dist2);
    if (ndl > 0) {
      SceneRay shadow{shadow_origin, to_light};
      if (!world.geometry.Occluded(shadow, 0, 1.0 - 1e-6)) {
        irradiance += light.point_power * ndl / (dist2 + light.point_softness * light.point_softness);
      }
    }
  }
  for (const ScenePointLight& extra : light.extra_point_lights) {
    irradiance += PointIrradiance(world.geometry, extra, p, n, shadow_origin);
  }
  const SurfaceMaterial& material = world.materials[hit.material];
  if (material.Emissive()) return irradiance * MaterialAlbedo(material, p) + material.emission;
  return irradiance * MaterialAlbedo(material, p);
}

Eigen::Vector3d Background(const SceneBackground& bg, const Eigen::Vector3d& direction) {
  if (!bg.sky) return bg.color;
  const double e = std::max(0.0, direction.normalized().dot(bg.up.normalized()));
  const double w = std::sqrt(e);
  return (1 - w) * bg.color + w * bg.zenith;
}

// 1 - strength * r^2, r the distance from the image centre relative to the corner's.
double Vignette(const SyntheticCamera& camera, int col, int row, double strength) {
  const double hx = 0.5 * (camera.width - 1), hy = 0.5 * (camera.height - 1);
  const double dx = col - hx, dy = row - hy;
  return 1.0 - strength * (dx * dx + dy * dy) / (hx * hx + hy * hy);
}

double ToneCurve(double radiance, double exposure) {
  const double v = std::min(1.0, std::max(0.0, radiance * exposure));
  return 255.0 * std::pow(v, kGamma);
}

// Separable Gaussian blur of a planar 3-channel float image, edges clamped.
void BlurPlanar(std::vector<float>* planes, int width, int height, double sigma) {
  const int radius = std::max(1, static_cast<int>(std::ceil(3 * sigma)));
  std::vector<double> kernel(2 * radius + 1);
  double sum = 0;
  for (int i = -radius; i <= radius; ++i) {
    kernel[i + radius] = std::exp(-0.5 * i * i / (sigma * sigma));
    sum += kernel[i + radius];
  }
  for (double& k : kernel) k /= sum;
  const size_t plane = static_cast<size_t>(width) * height;
  std::vector<float> tmp(plane);
  for (int c = 0; c < 3; ++c) {
    float* img = planes->data() + c * plane;
    for (int r = 0; r < height; ++r) {
      for (int x = 0; x < width; ++x) {
        double acc = 0;
        for (int k = -radius; k <= radius; ++k) {
          const int xx = std::min(width - 1, std::max(0, x + k));
          acc += kernel[k + radius] * img[static_cast<size_t>(r) * width + xx];
        }
        tmp[static_cast<size_t>(r) * width + x] = static_cast<float>(acc);
      }
    }
    for (int r = 0; r < height; ++r) {
      for (int x = 0; x < width; ++x) {
        double acc = 0;
        for (int k = -radius; k <= radius; ++k) {
          const int rr = std::min(height - 1, std::max(0, r + k));
          acc += kernel[k + radius] * tmp[static_cast<size_t>(rr) * width + x];
        }
        img[static_cast<size_t>(r) * width + x] = static_cast<float>(acc);
      }
    }
  }
}

}  // namespace

SceneRay SyntheticCamera::RayThrough(double x, double y) const {
  const Eigen::Vector3d d_cam((x - cx) / fx, (y - cy) / fy, 1.0);
  return SceneRay{Center(), R.transpose() * d_cam};
}

bool SyntheticCamera::Project(const Eigen::Vector3d& X, double* x, double* y, double* z) const {
  const Eigen::Vector3d Xc = R * X + t;
  if (Xc.z() <= 0) return false;
  *x = fx * Xc.x() / Xc.z() + cx;
  *y = fy * Xc.y() / Xc.z() + cy;
  *z = Xc.z();
  return true;
}

SyntheticCamera LookAtCamera(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
                             const Eigen::Vector3d& up, double roll, int width, int height,
                             double fx, double fy, double cx, double cy) {
  const Eigen::Vector3d forward = (target - center).normalized();
  Eigen::Vector3d right = forward.cross(up).normalized();
  Eigen::Vector3d down = forward.cross(right);
  const double c = std::cos(roll), s = std::sin(roll);
  const Eigen::Vector3d right_rolled = c * right + s * down;
  const Eigen::Vector3d down_rolled = -s * right + c * down;
  SyntheticCamera cam;
  cam.width = width;
  cam.height = height;
  cam.fx = fx;
  cam.fy = fy;
  cam.cx = cx;
  cam.cy = cy;
  cam.R.row(0) = right_rolled.transpose();
  cam.R.row(1) = down_rolled.transpose();
  cam.R.row(2) = forward.transpose();
  cam.t = -cam.R * center;
  return cam;
}

std::vector<std::string> SurfaceNames(const SyntheticWorld& world) {
  std::vector<std::string> names;
  for (const SurfaceMaterial& m : world.materials) {
    if (!m.surface.empty() && std::find(names.begin(), names.end(), m.surface) == names.end()) {
      names.push_back(m.surface);
    }
  }
  if (names.size() > 255) throw Error("more than 255 named surfaces");
  return names;
}

RenderedView RenderView(const SyntheticWorld& world, const SyntheticCamera& camera,
                        const RenderOptions& options) {
  const int w = camera.width, h = camera.height;
  const int s = std::max(1, options.supersampling);
  const size_t plane = static_cast<size_t>(w) * h;
  RenderedView view;
  view.depth = FloatMap(w, h, 1);
  view.normal = FloatMap(w, h, 3);
  view.untextured.assign(plane, 0);
  view.surface.assign(plane, 0);
  const std::vector<std::string> surface_names = SurfaceNames(world);
  std::vector<uint8_t> material_surface(world.materials.size(), 0);
  for (size_t m = 0; m < world.materials.size(); ++m) {
    const auto it = std::find(surface_names.begin(), surface_names.end(), world.materials[m].surface);
    if (it != surface_names.end()) material_surface[m] = static_cast<uint8_t>(it - surface_names.begin() + 1);
  }
  std::vector<float> linear(3 * plane);  // planar r, g, b after the tone curve
  const double exposure = world.lighting.exposure;

  RunRangeInThreads(h, options.num_threads, [&](int row_begin, int row_end) {
    SceneHit hit;
    Eigen::Vector3d normal;
    for (int row = row_begin; row < row_end; ++row) {
      for (int col = 0; col < w; ++col) {
        // Ground truth from the ray through the pixel centre.
        const SceneRay centre_ray = camera.RayThrough(col, row);
        if (world.geometry.Intersect(centre_ray, 1e-6, std::numeric_limits<double>::infinity(),
                                     &hit)) {
          Eigen::Vector3d n = hit.normal;
          if (n.dot(centre_ray.direction) > 0) n = -n;
          const Eigen::Vector3d n_cam = camera.R * n;
          view.depth.At(row, col) = static_cast<float>(hit.t);
          for (int c = 0; c < 3; ++c) view.normal.At(row, col, c) = static_cast<float>(n_cam[c]);
          if (!world.materials[hit.material].Textured()) {
            view.untextured[static_cast<size_t>(row) * w + col] = 255;
          }
          view.surface[static_cast<size_t>(row) * w + col] = material_surface[hit.material];
        }
        // Colour: average of s x s samples spread over the pixel around its centre.
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (int sy = 0; sy < s; ++sy) {
          for (int sx = 0; sx < s; ++sx) {
            const double x = col + (sx + 0.5) / s - 0.5;
            const double y = row + (sy + 0.5) / s - 0.5;
            const SceneRay ray = camera.RayThrough(x, y);
            if (world.geometry.Intersect(ray, 1e-6, std::numeric_limits<double>::infinity(),
                                         &hit)) {
              sum += Shade(world, ray, hit, &normal);
            } else {
              sum += Background(world.background, ray.direction);
            }
          }
        }
        sum /= static_cast<double>(s * s);
        if (options.vignetting > 0) sum *= Vignette(camera, col, row, options.vignetting);
        for (int c = 0; c < 3; ++c) {
          const double v = ToneCurve(sum[c], exposure);
          linear[c * plane + static_cast<size_t>(row) * w + col] =
              static_cast<float>(options.gain * v + options.offset);
        }
      }
    }
  });

  if (options.blur_sigma > 0) BlurPlanar(&linear, w, h, options.blur_sigma);

  view.image.width = w;
  view.image.height = h;
  view.image.data.resize(3 * plane);
  for (size_t i = 0; i < plane; ++i) {
    for (int c = 0; c < 3; ++c) {
      double v = linear[c * plane + i];
      if (options.shot_noise > 0) {
        const double sigma =
            std::sqrt(options.noise_sigma * options.noise_sigma + options.shot_noise * std::max(0.0, v));
        v += sigma * SynthNormal(SynthHash(options.noise_seed, i, c));
      } else if (options.noise_sigma > 0) {
        v += options.noise_sigma * SynthNormal(SynthHash(options.noise_seed, i, c));
      }
      view.image.data[3 * i + c] =
          static_cast<uint8_t>(std::lround(std::min(255.0, std::max(0.0, v))));
    }
  }
  return view;
}

}  // namespace mpmvs

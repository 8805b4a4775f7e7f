#pragma once
// CPU ray-casting renderer of synthetic scenes: supersampled Lambertian shading with
// shadows, per-view exposure, optional blur and Gaussian sensor noise, plus exact ground
// truth (z-depth, camera-frame normals, untextured-material mask) per pixel.
//
// Pixel convention (COLMAP MVS): pixel (col,row) is centred at image coordinate (col,row),
// i.e. it sees the ray K^-1 (col, row, 1). Images and GT use the same centre, so GT depth
// back-projected as X_cam = z ((col-cx)/fx, (row-cy)/fy, 1) lands exactly on the surface
// that colours the pixel.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/synthetic/procedural_texture.h"
#include "colmap_ext/synthetic/scene_geometry.h"

namespace mpmvs {

struct SyntheticCamera {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // COLMAP PINHOLE parameters
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // X_cam = R X_world + t
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d Center() const { return -R.transpose() * t; }
  // World-frame ray through image coordinate (x, y); its camera-frame z component is 1,
  // so the hit parameter equals the z-depth.
  SceneRay RayThrough(double x, double y) const;
  // Image coordinate of a world point (MVS convention); false when behind the camera.
  bool Project(const Eigen::Vector3d& X, double* x, double* y, double* z) const;
};

// Camera at `center` looking at `target`; `up` fixes the horizon, roll (radians) turns
// the camera about its optical axis. Camera frame: x right, y down, z forward.
SyntheticCamera LookAtCamera(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
                             const Eigen::Vector3d& up, double roll, int width, int height,
                             double fx, double fy, double cx, double cy);

struct ScenePointLight {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double power = 0;     // irradiance = power * cos / (d^2 + softness^2)
  double softness = 0;  // metres
};

struct SceneLighting {
  double ambient = 0.3;
  Eigen::Vector3d sun_direction{0, 0, -1};  // direction the light travels
  double sun_intensity = 0.7;
  bool has_point_light = false;
  Eigen::Vector3d point_position = Eigen::Vector3d::Zero();
  double point_power = 0;  // irradiance = power * cos / (d^2 + softness^2)
  double point_softness = 0;  // metres; > 0 keeps nearby surfaces from saturating
  double exposure = 1.0;   // scales radiance before the tone curve
  // Further point lights (e.g. a row of ceiling lamps), added after the one above.
  std::vector<ScenePointLight> extra_point_lights;
};

struct SceneBackground {
  bool sky = false;  // false: constant colour; true: gradient from horizon to zenith
  Eigen::Vector3d color{0.25, 0.25, 0.25};  // constant colour or horizon colour
  Eigen::Vector3d zenith{0.35, 0.5, 0.8};
  Eigen::Vector3d up{0, 0, 1};
};

// Everything needed to render: geometry (built), materials, lights, background.
struct SyntheticWorld {
  SceneGeometry geometry;
  std::vector<SurfaceMaterial> materials;
  SceneLighting lighting;
  SceneBackground background;
};

struct RenderOptions {
  int supersampling = 3;     // s x s samples per pixel
  double noise_sigma = 2.0;  // Gaussian sensor noise, 8-bit levels
  double blur_sigma = 0.0;   // Gaussian optical blur in pixels, 0 = off
  double gain = 1.0;         // per-view exposure: I = gain * I + offset
  double offset = 0.0;       // 8-bit levels
  uint64_t noise_seed = 0;
  int num_threads = -1;      // -1 = all hardware threads
  // Darkening of the image corners (radiance falls off as 1 - vignetting * r^2, r = 1 at
  // the corner), 0 = off.
  double vignetting = 0.0;
  // Signal-dependent (shot) noise: the noise variance is noise_sigma^2 + shot_noise * I
  // for 8-bit intensity I. 0 = constant Gaussian noise only.
  double shot_noise = 0.0;
};

struct RenderedView {
  RgbImage image;
  FloatMap depth;   // 1 channel z-depth (m), 0 where the ray hits no surface
  FloatMap normal;  // 3 channels, camera frame, facing the camera, 0 where no surface
  std::vector<uint8_t> untextured;  // 255 where the surface at the pixel centre is plain
  // Where the surface at the pixel centre is a named one (SurfaceMaterial::surface): its
  // position in SurfaceNames(world) plus 1; 0 elsewhere.
  std::vector<uint8_t> surface;
};

// The distinct SurfaceMaterial::surface names of the world's materials, in material order
// (at most 255).
std::vector<std::string> SurfaceNames(const SyntheticWorld& world);

RenderedView RenderView(const SyntheticWorld& world, const SyntheticCamera& camera,
                        const RenderOptions& options);

}  // namespace mpmvs

#pragma once
// Surface materials of synthetic scenes: a base colour and an optional procedural pattern
// evaluated as a solid texture at the 3-D surface point (no surface parametrisation is
// needed, and every view sees the same albedo at the same point).
#include <cstdint>
#include <string>

#include <Eigen/Core>

namespace mpmvs {

enum class TexturePattern {
  kPlain,    // untextured: only shading and sensor noise (the case MP-MVS targets)
  kNoise,    // fractal value noise, several octaves starting at `scale`
  kChecker,  // checker cells of size `scale`, lightly perturbed by noise
  kStripes,  // wavy stripes of period `scale` along stripe_direction
  kMixed,    // noise + checker + fine noise at three scales
};

struct SurfaceMaterial {
  Eigen::Vector3d color_a{0.7, 0.7, 0.7};  // linear albedo in [0, 1]
  Eigen::Vector3d color_b{0.3, 0.3, 0.3};  // second colour of the pattern
  TexturePattern pattern = TexturePattern::kPlain;
  double scale = 0.1;  // metres
  Eigen::Vector3d stripe_direction{1, 0, 0};
  uint64_t seed = 0;
  // Light the surface gives off by itself (linear radiance added to the shaded albedo), e.g.
  // a bright window or a lamp panel. Not a light source for other surfaces.
  Eigen::Vector3d emission{0, 0, 0};
  // The part of the scene this material makes, scored on its own by `evaluate` (e.g. "side
  // walls", gt/surface_<stem>.png); empty: none.
  std::string surface;

  bool Textured() const { return pattern != TexturePattern::kPlain; }
  bool Emissive() const { return emission.x() > 0 || emission.y() > 0 || emission.z() > 0; }
};

// Albedo of the material at world point p.
Eigen::Vector3d MaterialAlbedo(const SurfaceMaterial& material, const Eigen::Vector3d& p);

// Smooth value noise on the integer lattice, in [0, 1].
double ValueNoise3(const Eigen::Vector3d& p, uint64_t seed);
// Sum of `octaves` value-noise octaves (each twice the frequency, half the weight), in [0, 1].
double FractalNoise3(const Eigen::Vector3d& p, uint64_t seed, int octaves);

}  // namespace mpmvs

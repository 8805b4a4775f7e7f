#pragma once
// Helpers shared by the synthetic scene layouts: a world builder that gives materials
// seeds derived from the scene seed, a few primitives, and camera spreading.
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "colmap_ext/synthetic/scene_renderer.h"
#include "colmap_ext/synthetic/synthetic_random.h"

namespace mpmvs {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// Collects materials and primitives; material seeds derive from the scene seed.
class WorldBuilder {
 public:
  explicit WorldBuilder(uint64_t seed) : seed_(seed) {}

  int Plain(const Eigen::Vector3d& color) {
    SurfaceMaterial m;
    m.color_a = color;
    return AddMaterial(m);
  }
  int Pattern(TexturePattern pattern, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
              double scale, const Eigen::Vector3d& stripe_direction = Eigen::Vector3d::UnitX()) {
    SurfaceMaterial m;
    m.pattern = pattern;
    m.color_a = a;
    m.color_b = b;
    m.scale = scale;
    m.stripe_direction = stripe_direction;
    return AddMaterial(m);
  }
  // Names the part of the scene a material makes (SurfaceMaterial::surface).
  void NameSurface(int material, const std::string& surface) { world_.materials[material].surface = surface; }
  int AddMaterial(SurfaceMaterial m) {
    m.seed = SynthHash(seed_, 0x5eed0000ULL + world_.materials.size());
    world_.materials.push_back(m);
    return static_cast<int>(world_.materials.size()) - 1;
  }
  void Add(ScenePrimitive p, bool casts_shadow = true) {
    p.casts_shadow = casts_shadow;
    world_.geometry.Add(p);
  }
  SyntheticWorld& world() { return world_; }

 private:
  uint64_t seed_;
  SyntheticWorld world_;
};

// Box with explicit orthonormal axes (columns).
inline ScenePrimitive OrientedBox(const Eigen::Vector3d& center, const Eigen::Matrix3d& axes,
                                  const Eigen::Vector3d& half, int material) {
  ScenePrimitive p;
  p.type = PrimitiveType::kBox;
  p.material = material;
  p.center = center;
  p.axes = axes;
  p.half_size = half;
  return p;
}

// Position in [-0.5, 0.5] of camera i among n.
inline double Spread(int i, int n) {
  return n <= 1 ? 0.0 : static_cast<double>(i) / (n - 1) - 0.5;
}

}  // namespace mpmvs

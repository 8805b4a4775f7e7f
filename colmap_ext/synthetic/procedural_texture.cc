#include "colmap_ext/synthetic/procedural_texture.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/synthetic/synthetic_random.h"

namespace mpmvs {
namespace {

double Fade(double t) { return t * t * (3.0 - 2.0 * t); }

double LatticeValue(int64_t x, int64_t y, int64_t z, uint64_t seed) {
  return SynthUnit(SynthHash(seed, static_cast<uint64_t>(x), static_cast<uint64_t>(y),
                             static_cast<uint64_t>(z)));
}

double Clamp01(double v) { return std::min(1.0, std::max(0.0, v)); }

// Pushes noise (which clusters around 0.5) towards both colours for visible contrast.
double Stretch(double w, double gain) { return Clamp01(0.5 + (w - 0.5) * gain); }

}  // namespace

double ValueNoise3(const Eigen::Vector3d& p, uint64_t seed) {
  const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
  const int64_t ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy),
                iz = static_cast<int64_t>(fz);
  const double tx = Fade(p.x() - fx), ty = Fade(p.y() - fy), tz = Fade(p.z() - fz);
  double c[2][2][2];
  for (int dz = 0; dz < 2; ++dz) {
    for (int dy = 0; dy < 2; ++dy) {
      for (int dx = 0; dx < 2; ++dx) c[dz][dy][dx] = LatticeValue(ix + dx, iy + dy, iz + dz, seed);
    }
  }
  auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  const double y0 = lerp(lerp(c[0][0][0], c[0][0][1], tx), lerp(c[0][1][0], c[0][1][1], tx), ty);
  const double y1 = lerp(lerp(c[1][0][0], c[1][0][1], tx), lerp(c[1][1][0], c[1][1][1], tx), ty);
  return lerp(y0, y1, tz);
}

double FractalNoise3(const Eigen::Vector3d& p, uint64_t seed, int octaves) {
  double sum = 0, weight = 1, total = 0, freq = 1;
  for (int o = 0; o < octaves; ++o) {
    // Offsetting each octave avoids lattice points of all octaves coinciding at the origin.
    sum += weight * ValueNoise3(p * freq + Eigen::Vector3d(17.3 * o, 5.1 * o, 31.7 * o),
                                SynthHash(seed, o));
    total += weight;
    weight *= 0.5;
    freq *= 2.0;
  }
  return sum / total;
}

Eigen::Vector3d MaterialAlbedo(const SurfaceMaterial& m, const Eigen::Vector3d& p) {
  double w = 0;
  const Eigen::Vector3d q = p / m.scale;
  switch (m.pattern) {
    case TexturePattern::kPlain:
      return m.color_a;
    case TexturePattern::kNoise:
      w = Stretch(FractalNoise3(q, m.seed, 4), 2.4);
      break;
    case TexturePattern::kChecker: {
      const int64_t parity = static_cast<int64_t>(std::floor(q.x())) +
                             static_cast<int64_t>(std::floor(q.y())) +
                             static_cast<int64_t>(std::floor(q.z()));
      const double checker = (parity & 1) ? 1.0 : 0.0;
      w = 0.75 * checker + 0.25 * Stretch(FractalNoise3(q * 2.0, m.seed, 3), 2.0);
      break;
    }
    case TexturePattern::kStripes: {
      const double phase = p.dot(m.stripe_direction.normalized()) / m.scale +
                           0.8 * FractalNoise3(q * 0.5, m.seed, 2);
      const double s = 0.5 + 0.5 * std::sin(6.283185307179586 * phase);
      w = 0.8 * Stretch(s, 1.6) + 0.2 * FractalNoise3(q * 4.0, SynthHash(m.seed, 7), 2);
      break;
    }
    case TexturePattern::kMixed: {
      const Eigen::Vector3d c = (q * 0.5).array().floor();
      const int64_t parity = static_cast<int64_t>(c.x() + c.y() + c.z());
      const double checker = (parity & 1) ? 1.0 : 0.0;
      // Noise dominates so that the checker never makes the pattern repetitive.
      w = 0.55 * Stretch(FractalNoise3(q, m.seed, 3), 2.4) + 0.2 * checker +
          0.25 * Stretch(ValueNoise3(q * 4.0, SynthHash(m.seed, 3)), 2.0);
      break;
    }
  }
  w = Clamp01(w);
  return (1.0 - w) * m.color_a + w * m.color_b;
}

}  // namespace mpmvs

#pragma once
// Checkerboard propagation patterns as data (docs/algorithm.md §5): 8 regions of pixel offsets,
// each of odd parity (du+dv odd) so that every sample has the other checkerboard colour.
// Per region the neighbour with the lowest stored cost is taken as candidate.
#include "kernels/common.h"

namespace mpmvs {
namespace kernels {

constexpr int kNumRegions = 8;
constexpr int kMaxRegionSamples = 12;

enum class PatternKind : int {
  kAcmh = 0,     // ACMH: 4 near V-shapes (5 px) + 4 far lines (3..23 px)
  kDistant = 1,  // MP-MVS "rs": 4 distant V-shapes (12 samples) + 4 lines (5..23 px, 10 samples)
};

struct PropagationPattern {
  PatternKind kind = PatternKind::kDistant;
  int num_samples[kNumRegions] = {0};
  int du[kNumRegions][kMaxRegionSamples] = {{0}};
  int dv[kNumRegions][kMaxRegionSamples] = {{0}};
  int reach = 0;  // largest |du| or |dv|: pixels this far inside the image need no bounds checks
};

// Region order: 0 up-V, 1 down-V, 2 left-V, 3 right-V, 4 up line, 5 down line, 6 left line,
// 7 right line. The V-shapes point at the pixel along an axis; their arms run diagonally.
MPMVS_HD inline PropagationPattern MakePropagationPattern(PatternKind kind) {
  PropagationPattern p;
  p.kind = kind;
  // Direction (ax, ay) of each axis: up, down, left, right.
  const int ax[4] = {0, 0, -1, 1};
  const int ay[4] = {-1, 1, 0, 0};
  for (int r = 0; r < 4; ++r) {
    int n = 0;
    if (kind == PatternKind::kDistant) {
      // (±k, -(k+1)) for k = 5..10 for "up", rotated for the other axes.
      for (int k = 5; k <= 10; ++k) {
        for (int s = -1; s <= 1; s += 2) {
          const int lateral = s * k, along = k + 1;
          p.du[r][n] = ax[r] != 0 ? ax[r] * along : lateral;
          p.dv[r][n] = ay[r] != 0 ? ay[r] * along : lateral;
          ++n;
        }
      }
    } else {
      // ACMH near V (the paper's shape, parity-correct): (0,-1), (±1,-2), (±2,-3).
      p.du[r][n] = ax[r];
      p.dv[r][n] = ay[r];
      ++n;
      for (int k = 1; k <= 2; ++k) {
        for (int s = -1; s <= 1; s += 2) {
          const int lateral = s * k, along = k + 1;
          p.du[r][n] = ax[r] != 0 ? ax[r] * along : lateral;
          p.dv[r][n] = ay[r] != 0 ? ay[r] * along : lateral;
          ++n;
        }
      }
    }
    p.num_samples[r] = n;
    // Lines: distant 5,7,..,23 (10 samples); ACMH 3,5,..,23 (11 samples).
    n = 0;
    for (int k = (kind == PatternKind::kDistant ? 5 : 3); k <= 23; k += 2) {
      p.du[4 + r][n] = ax[r] * k;
      p.dv[4 + r][n] = ay[r] * k;
      ++n;
    }
    p.num_samples[4 + r] = n;
  }
  for (int r = 0; r < kNumRegions; ++r) {
    for (int i = 0; i < p.num_samples[r]; ++i) {
      p.reach = MaxI(p.reach, MaxI(p.du[r][i] < 0 ? -p.du[r][i] : p.du[r][i], p.dv[r][i] < 0 ? -p.dv[r][i] : p.dv[r][i]));
    }
  }
  return p;
}

}  // namespace kernels
}  // namespace mpmvs

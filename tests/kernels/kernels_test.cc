// Unit tests of the shared per-pixel math (kernels/*.h) as the CPU backend runs it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <iostream>
#include <random>
#include <set>
#include <vector>

#include "tests/kernel_schedule_util.h"
#include "kernels/ncc_simd.h"
#include "kernels/depth_segments.h"
#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {
namespace {

Camera MakeCamera(int w, int h, float f, const float R[9], const float t[3]) {
  Camera c;
  c.width = w;
  c.height = h;
  c.fx = c.fy = f;
  c.cx = w / 2.f;
  c.cy = h / 2.f;
  for (int i = 0; i < 9; ++i) c.R[i] = R[i];
  for (int i = 0; i < 3; ++i) c.t[i] = t[i];
  return c;
}

// Rotation about axis (normalised) by angle, row-major.
void AxisAngle(float ax, float ay, float az, float angle, float R[9]) {
  const float n = std::sqrt(ax * ax + ay * ay + az * az);
  ax /= n, ay /= n, az /= n;
  const float c = std::cos(angle), s = std::sin(angle), C = 1 - c;
  const float M[9] = {c + ax * ax * C,      ax * ay * C - az * s, ax * az * C + ay * s,
                      ay * ax * C + az * s, c + ay * ay * C,      ay * az * C - ax * s,
                      az * ax * C - ay * s, az * ay * C + ax * s, c + az * az * C};
  for (int i = 0; i < 9; ++i) R[i] = M[i];
}

TEST(KernelCamera, HomographyMatchesDirectReprojection) {
  float Rr[9], Rs[9];
  AxisAngle(0.3f, 1.f, 0.2f, 0.2f, Rr);
  AxisAngle(-0.5f, 0.4f, 1.f, 0.35f, Rs);
  const float tr[3] = {0.1f, -0.2f, 0.3f}, ts[3] = {-0.4f, 0.1f, 0.2f};
  Camera ref = MakeCamera(200, 150, 180.f, Rr, tr);
  Camera src = MakeCamera(220, 160, 200.f, Rs, ts);
  src.cx = 105.f;
  const RelativePose rel = ComputeRelativePose(ref, src);
  const Vec3 n = Normalize(Vec3{0.2f, -0.3f, -1.f});
  for (int trial = 0; trial < 20; ++trial) {
    const float u = 10.f + 9.f * trial, v = 5.f + 7.f * trial;
    const Vec3 ray = PixelRay(ref, u, v);
    const float depth = 3.f + 0.1f * trial;
    const Plane plane = PlaneFromDepthNormal(ray, depth, n);
    EXPECT_NEAR(PlaneDepth(plane, ray), depth, 1e-4f);
    float H[9];
    PlaneHomography(rel, HomographyPlaneVector(ref, plane), H);
    // Direct: back-project, to world, to source.
    const Vec3 Xr = depth * ray;
    const Vec3 Xw = MatTVec(ref.R, Xr - Vec3{tr[0], tr[1], tr[2]});
    const Vec3 Xs = MatVec(src.R, Xw) + Vec3{ts[0], ts[1], ts[2]};
    float us, vs;
    ASSERT_TRUE(ProjectCameraPoint(src, Xs, &us, &vs));
    const float hz = H[6] * u + H[7] * v + H[8];
    EXPECT_NEAR((H[0] * u + H[1] * v + H[2]) / hz, us, 2e-3f);
    EXPECT_NEAR((H[3] * u + H[4] * v + H[5]) / hz, vs, 2e-3f);
  }
}

std::vector<float> RandomImage(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(20.f, 230.f);
  std::vector<float> img(static_cast<size_t>(w) * h);
  for (float& x : img) x = dist(rng);
  return img;
}

// A reference camera at the origin and one source per offset (no rotation), all seeing img,
// with depths in [1, 10].
PatchMatchProblem ShiftedSourcesProblem(const std::vector<float>& img, int w, int h, float f,
                                        const std::vector<std::array<float, 3>>& offsets) {
  const float I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const float t0[3] = {0.f, 0.f, 0.f};
  PatchMatchProblem problem;
  problem.ref_camera = MakeCamera(w, h, f, I, t0);
  problem.ref_image = ImageView{img.data(), w, h};
  for (const std::array<float, 3>& t : offsets) {
    PatchMatchSource source;
    source.camera = MakeCamera(w, h, f, I, t.data());
    source.image = problem.ref_image;
    problem.sources.push_back(source);
  }
  problem.depth_min = 1.f;
  problem.depth_max = 10.f;
  return problem;
}

// A random texture left of x = W / 2 and, right of it, wall(x, y) plus Gaussian noise of
// sigma 1.5 grey levels.
template <class Wall>
std::vector<float> TextureThenWall(int w, int h, unsigned seed, const Wall& wall) {
  std::vector<float> img = RandomImage(w, h, seed);
  std::mt19937 rng(seed + 1);
  std::normal_distribution<float> noise(0.f, 1.5f);
  for (int y = 0; y < h; ++y) {
    for (int x = w / 2; x < w; ++x) img[y * w + x] = wall(x, y) + noise(rng);
  }
  return img;
}

TEST(KernelNcc, InvariantToGainAndOffset) {
  const int W = 64, H = 64;
  std::vector<float> ref = RandomImage(W, H, 1);
  std::vector<float> src(ref.size());
  for (size_t i = 0; i < ref.size(); ++i) src[i] = 0.6f * ref[i] + 17.f;
  const ImageView rv{ref.data(), W, H}, sv{src.data(), W, H};
  const float identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int scale = 0; scale <= 1; ++scale) {
    const WindowSpec win = WindowForScale(scale);
    RefPatch patch;
    ComputeRefPatch(rv, 32, 30, win, &patch);
    EXPECT_NEAR(ComputeNccCost(patch, sv, identity, 32, 30, win), 0.f, 1e-3f);
    // A shifted source does not match.
    const float shift[9] = {1, 0, 3, 0, 1, 0, 0, 0, 1};
    EXPECT_GT(ComputeNccCost(patch, sv, shift, 32, 30, win), 0.5f);
    // Inverted contrast gives the maximum cost.
    std::vector<float> inv(ref.size());
    for (size_t i = 0; i < ref.size(); ++i) inv[i] = 255.f - ref[i];
    EXPECT_NEAR(ComputeNccCost(patch, ImageView{inv.data(), W, H}, identity, 32, 30, win), 2.f,
                1e-3f);
  }
}

// The chroma guide cuts the window at a colour edge that grey cannot see; a zero guide
// changes nothing.
TEST(KernelNcc, ChromaGuideLowersWeightsAcrossColourEdges) {
  const int W = 40, H = 40, u = 20, v = 20;
  std::vector<float> grey(W * H, 100.f);  // equal brightness everywhere
  std::vector<float> flat(2 * W * H, 0.f), edge(2 * W * H, 0.f);
  for (int y = 0; y < H; ++y) {
    for (int x = 24; x < W; ++x) edge[2 * (y * W + x)] = 200.f;  // x >= 24: another colour
  }
  const WindowSpec win = WindowForScale(0);
  RefPatch plain, zero_guide, guided;
  ImageView view{grey.data(), W, H};
  ComputeRefPatch(view, u, v, win, &plain);
  view.chroma = flat.data();
  ComputeRefPatch(view, u, v, win, &zero_guide);
  view.chroma = edge.data();
  ComputeRefPatch(view, u, v, win, &guided);
  for (int k = 0; k < kWindowSamplesPadded; ++k) EXPECT_EQ(plain.weight[k], zero_guide.weight[k]) << k;
  float across_plain = 0, across_guided = 0;
  for (int k = 0; k < kWindowSamples; ++k) {
    const bool across = u + plain.offset_x[k] >= 24;
    if (across) {
      across_plain += plain.weight[k];
      across_guided += guided.weight[k];
    }
  }
  // Offsets -5, -3, ..., 5 from u = 20: the column at x = 25 is across the edge.
  EXPECT_GT(across_plain, 0.1f);
  EXPECT_LT(across_guided, 1e-4f * across_plain);
  float sum = 0;
  for (int k = 0; k < kWindowSamples; ++k) sum += guided.weight[k];
  EXPECT_NEAR(sum, 1.f, 1e-5f);
}

// A window that crosses the image border (the per-sample bounds test) weighs the samples
// it keeps as the same window does where all of it lies inside (the direct row gather):
// the same relative weights, zero on the samples outside; with a chroma guide too.
TEST(KernelNcc, BorderWindowKeepsTheInsideSamplesWeights) {
  const int W = 48, H = 40, crop_x = 8, crop_y = 6;
  const std::vector<float> big = RandomImage(W, H, 7);
  std::vector<float> big_chroma(2 * W * H);
  for (size_t i = 0; i < big_chroma.size(); ++i) big_chroma[i] = static_cast<float>((i * 37) % 11);
  // The crop starts crop_x, crop_y pixels in: windows near its top-left corner cross its border.
  const int w = W - crop_x, h = H - crop_y;
  std::vector<float> crop(w * h), crop_chroma(2 * w * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int i = (y + crop_y) * W + x + crop_x;
      crop[y * w + x] = big[i];
      crop_chroma[2 * (y * w + x)] = big_chroma[2 * i];
      crop_chroma[2 * (y * w + x) + 1] = big_chroma[2 * i + 1];
    }
  }
  for (const bool chroma : {false, true}) {
    ImageView whole{big.data(), W, H}, part{crop.data(), w, h};
    if (chroma) {
      whole.chroma = big_chroma.data();
      part.chroma = crop_chroma.data();
    }
    const WindowSpec win = WindowForScale(0);
    int crossing = 0;
    for (int v = 0; v < 8; ++v) {
      for (int u = 0; u < 8; ++u) {
        RefPatch inside, border;
        ComputeRefPatch(whole, u + crop_x, v + crop_y, win, &inside);  // all of it inside
        ComputeRefPatch(part, u, v, win, &border);
        bool in_crop[kWindowSamples];
        float kept = 0.f;  // the inside window's weight on the samples the crop keeps
        for (int k = 0; k < kWindowSamples; ++k) {
          in_crop[k] = u + border.offset_x[k] >= 0 && v + border.offset_y[k] >= 0;
          if (in_crop[k]) kept += inside.weight[k];
        }
        crossing += kept < 1.f;
        for (int k = 0; k < kWindowSamples; ++k) {
          const float expected = in_crop[k] ? inside.weight[k] / kept : 0.f;
          EXPECT_NEAR(border.weight[k], expected, 1e-5f) << "chroma " << chroma << " pixel " << u << "," << v << " sample " << k;
        }
      }
    }
    EXPECT_GT(crossing, 40);  // most of these windows do cross the border
  }
}

TEST(KernelNcc, InvalidCases) {
  const int W = 32, H = 32;
  std::vector<float> ref = RandomImage(W, H, 2);
  std::vector<float> flat(ref.size(), 100.f);
  const ImageView rv{ref.data(), W, H};
  const float identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  RefPatch patch;
  ComputeRefPatch(rv, 16, 16, WindowForScale(0), &patch);
  // Flat source.
  EXPECT_EQ(ComputeNccCost(patch, ImageView{flat.data(), W, H}, identity, 16, 16, WindowForScale(0)),
            kInvalidCost);
  // Centre outside the source.
  const float away[9] = {1, 0, 100, 0, 1, 0, 0, 0, 1};
  EXPECT_EQ(ComputeNccCost(patch, rv, away, 16, 16, WindowForScale(0)), kInvalidCost);
  // Behind the camera.
  const float behind[9] = {1, 0, 0, 0, 1, 0, 0, 0, -1};
  EXPECT_EQ(ComputeNccCost(patch, rv, behind, 16, 16, WindowForScale(0)), kInvalidCost);
  // Flat reference.
  RefPatch flat_patch;
  ComputeRefPatch(ImageView{flat.data(), W, H}, 16, 16, WindowForScale(0), &flat_patch);
  EXPECT_EQ(ComputeNccCost(flat_patch, rv, identity, 16, 16, WindowForScale(0)), kInvalidCost);
}

TEST(KernelWindow, SizesAndOffsetsPerScale) {
  const int sides[3] = {11, 21, 41};
  for (int s = 0; s <= 2; ++s) {
    const WindowSpec w = WindowForScale(s);
    EXPECT_EQ(WindowSide(w), (1 << s) * 10 + 1);
    EXPECT_EQ(WindowSide(w), sides[s]);
    EXPECT_EQ(WindowOffset(w, 0), -w.radius);
    EXPECT_EQ(WindowOffset(w, kWindowSamplesPerAxis - 1), w.radius);
    EXPECT_EQ(WindowOffset(w, 1) - WindowOffset(w, 0), 2 << s);
  }
  // S = 1 samples are at ±2, ±6, ±10.
  const WindowSpec w1 = WindowForScale(1);
  std::set<int> offs;
  for (int k = 0; k < 6; ++k) offs.insert(WindowOffset(w1, k));
  EXPECT_EQ(offs, (std::set<int>{-10, -6, -2, 2, 6, 10}));
}

TEST(KernelViewSelection, GoodThresholdSchedule) {
  EXPECT_FLOAT_EQ(GoodMatchThreshold(0), 0.8f);
  EXPECT_NEAR(GoodMatchThreshold(1), 0.8f * std::exp(-1.f / 90.f), 1e-6f);
  EXPECT_NEAR(GoodMatchThreshold(2), 0.8f * std::exp(-4.f / 90.f), 1e-6f);
  EXPECT_GT(GoodMatchThreshold(0), GoodMatchThreshold(2));
}

TEST(KernelPropagation, DistantPatternLayout) {
  const PropagationPattern p = MakePropagationPattern(PatternKind::kDistant);
  for (int r = 0; r < 4; ++r) EXPECT_EQ(p.num_samples[r], 12);
  for (int r = 4; r < 8; ++r) EXPECT_EQ(p.num_samples[r], 10);
  std::set<std::pair<int, int>> all;
  for (int r = 0; r < kNumRegions; ++r) {
    for (int i = 0; i < p.num_samples[r]; ++i) {
      const int du = p.du[r][i], dv = p.dv[r][i];
      EXPECT_EQ(std::abs(du + dv) % 2, 1) << "region " << r << " sample " << i;
      EXPECT_GE(std::sqrt(float(du * du + dv * dv)), 5.f);  // nothing near the pixel
      EXPECT_TRUE(all.insert({du, dv}).second) << "duplicate sample";
    }
  }
  // Up-V: (±k, -(k+1)), k = 5..10; up line: (0, -k), k = 5..23 odd.
  std::set<std::pair<int, int>> up_v, up_line;
  for (int i = 0; i < 12; ++i) up_v.insert({p.du[0][i], p.dv[0][i]});
  for (int k = 5; k <= 10; ++k) {
    EXPECT_TRUE(up_v.count({k, -(k + 1)}));
    EXPECT_TRUE(up_v.count({-k, -(k + 1)}));
  }
  for (int i = 0; i < 10; ++i) up_line.insert({p.du[4][i], p.dv[4][i]});
  for (int k = 5; k <= 23; k += 2) EXPECT_TRUE(up_line.count({0, -k}));
  // Right line goes right.
  for (int i = 0; i < 10; ++i) EXPECT_GT(p.du[7][i], 0);
}

TEST(KernelPropagation, AcmhPatternLayout) {
  const PropagationPattern p = MakePropagationPattern(PatternKind::kAcmh);
  for (int r = 0; r < 4; ++r) EXPECT_EQ(p.num_samples[r], 5);
  for (int r = 4; r < 8; ++r) EXPECT_EQ(p.num_samples[r], 11);
  bool has_adjacent = false;
  for (int r = 0; r < kNumRegions; ++r) {
    for (int i = 0; i < p.num_samples[r]; ++i) {
      EXPECT_EQ(std::abs(p.du[r][i] + p.dv[r][i]) % 2, 1);
      if (std::abs(p.du[r][i]) + std::abs(p.dv[r][i]) == 1) has_adjacent = true;
    }
  }
  EXPECT_TRUE(has_adjacent);
}

TEST(KernelViewSelection, WeightsFollowCosts) {
  // 3 views: view 0 good for all candidates, view 1 bad for all, view 2 mixed.
  const int N = 3;
  float costs[kNumRegions * N];
  bool valid[kNumRegions];
  for (int k = 0; k < kNumRegions; ++k) {
    valid[k] = true;
    costs[k * N + 0] = 0.1f;
    costs[k * N + 1] = 1.8f;
    costs[k * N + 2] = k < 4 ? 0.3f : 1.5f;
  }
  float prior[N] = {1.f, 1.f, 1.f};
  ViewSelectionParams params;
  RandomStream rng(1, 2, 3, 4);
  float weights[N];
  const uint32_t mask = SelectViews(costs, valid, N, prior, params, &rng, weights);
  EXPECT_EQ(weights[0] + weights[1] + weights[2], 15.f);
  EXPECT_EQ(weights[1], 0.f);  // n_bad >= 3 -> probability 0
  EXPECT_EQ(weights[2], 0.f);  // 4 bad candidates -> probability 0
  EXPECT_EQ(weights[0], 15.f);
  EXPECT_EQ(mask, 1u);
  // Invalid candidates are left out of the statistics: with only 2 valid candidates no view
  // has more than 2 good matches, so all fall back to exp(-tau^2/0.32).
  for (int k = 2; k < kNumRegions; ++k) valid[k] = false;
  const uint32_t mask2 = SelectViews(costs, valid, N, prior, params, &rng, weights);
  EXPECT_EQ(weights[0] + weights[1] + weights[2], 15.f);
  EXPECT_NE(mask2, 0u);
}

TEST(KernelViewSelection, OneLikelyViewTakesAllDrawsAndAdvancesTheStreamAsTheDrawsWould) {
  // Only view 1 has any probability (views 0 and 2 have 3 or more bad candidates): it gets
  // every draw without drawing, and the stream continues exactly as after the 15 draws, so
  // refinement's random planes do not change. Also with a single source view.
  for (int N : {3, 1}) {
    float costs[kNumRegions * 3];
    bool valid[kNumRegions];
    for (int k = 0; k < kNumRegions; ++k) {
      valid[k] = true;
      for (int s = 0; s < N; ++s) costs[k * N + s] = (N == 1 || s == 1) ? 0.2f + 0.01f * k : 1.9f;
    }
    float prior[3] = {1.f, 1.f, 1.f};
    ViewSelectionParams params;
    RandomStream a(5, 6, 7, 8), b(5, 6, 7, 8);
    float weights[3] = {-1.f, -1.f, -1.f};
    const uint32_t mask = SelectViews(costs, valid, N, prior, params, &a, weights);
    const int good = N == 1 ? 0 : 1;
    EXPECT_EQ(mask, 1u << good);
    for (int s = 0; s < N; ++s) EXPECT_EQ(weights[s], s == good ? 15.f : 0.f);
    for (int i = 0; i < params.num_samples; ++i) b.Uniform();
    for (int i = 0; i < 4; ++i) EXPECT_EQ(a.Uniform(), b.Uniform());
  }
}

TEST(KernelViewSelection, NeighbourPrior) {
  const uint32_t masks[4] = {0b01, 0b01, 0b11, 0b00};
  float prior[2];
  NeighbourViewPrior(masks, 4, 2, ViewSelectionParams{}, prior);
  EXPECT_FLOAT_EQ(prior[0], 0.9f * 3 + 0.1f);
  EXPECT_FLOAT_EQ(prior[1], 0.9f + 0.1f * 3);
}

TEST(KernelRandom, SkipEqualsDrawing) {
  RandomStream a(1, 2, 3, 4), b(1, 2, 3, 4);
  a.Skip(15);
  for (int i = 0; i < 15; ++i) b.Uniform();
  EXPECT_EQ(a.Uniform(), b.Uniform());
  EXPECT_EQ(a.Uniform(0.f, 2.f), b.Uniform(0.f, 2.f));
}

TEST(KernelRandom, DeterministicAndUniform) {
  RandomStream a(7, 1, 100, 3), b(7, 1, 100, 3), c(7, 1, 101, 3);
  double sum = 0;
  int differ = 0;
  for (int i = 0; i < 10000; ++i) {
    const float x = a.Uniform();
    EXPECT_EQ(x, b.Uniform());
    if (x != c.Uniform()) ++differ;
    EXPECT_GE(x, 0.f);
    EXPECT_LT(x, 1.f);
    sum += x;
  }
  EXPECT_NEAR(sum / 10000, 0.5, 0.02);
  EXPECT_GT(differ, 9900);
}

TEST(KernelHypotheses, RandomNormalsFaceTheCamera) {
  RandomStream rng(3, 0, 0, 0);
  const Vec3 ray{0.2f, -0.1f, 1.f};
  for (int i = 0; i < 1000; ++i) {
    const Vec3 n = RandomNormal(&rng, ray);
    EXPECT_LT(Dot(n, ray), 0.f);
    EXPECT_NEAR(Norm(n), 1.f, 1e-5f);
  }
}

TEST(KernelPrior, ScoreFavoursThePriorPlane) {
  PlanarPrior prior;
  prior.sigma_depth = 0.05f;
  const Vec3 ray{0.f, 0.f, 1.f};
  const Plane prior_plane = PlaneFromDepthNormal(ray, 2.f, Vec3{0.f, 0.f, -1.f});
  const Plane near_plane = PlaneFromDepthNormal(ray, 2.01f, Vec3{0.f, 0.f, -1.f});
  const Plane far_plane = PlaneFromDepthNormal(ray, 2.5f, Normalize(Vec3{0.3f, 0.f, -1.f}));
  // Same photometric cost: the plane agreeing with the prior wins.
  EXPECT_GT(PriorScore(prior, prior.beta, 0.5f, near_plane, prior_plane, ray),
            PriorScore(prior, prior.beta, 0.5f, far_plane, prior_plane, ray));
  // Far from the prior only gamma remains; a much better photometric cost still wins.
  EXPECT_NEAR(PriorScore(prior, prior.beta, 0.f, far_plane, prior_plane, ray), prior.gamma, 1e-4f);
  EXPECT_GT(PriorScore(prior, prior.beta, 0.05f, far_plane, prior_plane, ray),
            PriorScore(prior, prior.beta, 1.2f, near_plane, prior_plane, ray));
}

// With the texture-adaptive prior (noise floor on, beta above ACMP's) the prior acts on
// plain windows only and leaves textured ones to their views; where it acts it takes the
// geometric term's place. With ACMP's beta or without the noise floor it acts on every
// labelled pixel, as in the paper.
TEST(KernelPrior, ActsOnPlainWindowsOnlyAndThereReplacesTheGeometricTerm) {
  const int W = 48, H = 32;
  const std::vector<float> img = TextureThenWall(W, H, 5, [](int, int) { return 120.f; });  // wall from x = 24
  std::vector<uint8_t> label(W * H, 1);
  const ImageView view{img.data(), W, H};
  const WindowSpec win = WindowForScale(0);
  RefPatch textured, plain;
  const int textured_idx = 16 * W + 10, plain_idx = 16 * W + 36;
  ComputeRefPatch(view, 10, 16, win, &textured, true);
  ComputeRefPatch(view, 36, 16, win, &plain, true);

  PassParams params;
  params.use_prior = true;
  params.geometric = true;
  params.prior.label = label.data();
  params.prior.beta = 8.f;
  params.noise_variance = 1.5f * 1.5f;
  EXPECT_FALSE(PixelPriorActive(params, textured, textured_idx));
  EXPECT_TRUE(PixelPriorActive(params, plain, plain_idx));
  EXPECT_TRUE(PixelGeometric(params, PixelPriorActive(params, textured, textured_idx)));
  EXPECT_FALSE(PixelGeometric(params, PixelPriorActive(params, plain, plain_idx)));
  EXPECT_NEAR(PixelPriorBeta(params, plain), 8.f, 4.f);  // near prior.beta on the wall

  label[plain_idx] = 0;  // unlabelled: no prior, the geometric term stays
  EXPECT_FALSE(PixelPriorActive(params, plain, plain_idx));
  EXPECT_TRUE(PixelGeometric(params, PixelPriorActive(params, plain, plain_idx)));

  params.prior.beta = 0.18f;  // ACMP's beta: the paper's prior on every labelled pixel
  EXPECT_TRUE(PixelPriorActive(params, textured, textured_idx));
  params.prior.beta = 8.f;
  params.noise_variance = 0.f;  // no noise floor: likewise
  EXPECT_TRUE(PixelPriorActive(params, textured, textured_idx));
  params.geometric = false;  // photometric passes never have the term
  EXPECT_FALSE(PixelGeometric(params, false));
}

// A saturated block (an over-exposed window pane) gives no view any cost: without a prior
// its pixels have no estimate; a prior pass gives them the prior plane, and a later pass
// started from that result keeps it.
TEST(KernelPrior, FlatPixelsTakeThePriorPlaneAndKeepIt) {
  const int W = 64, H = 48;
  std::vector<float> img = RandomImage(W, H, 5);
  for (int y = 12; y < 36; ++y) {
    for (int x = 20; x < 44; ++x) img[y * W + x] = 255.f;
  }
  PatchMatchProblem problem = ShiftedSourcesProblem(img, W, H, 60.f, {{0.2f, 0.f, 0.f}});
  PatchMatchSchedule schedule = mpmvs::test::ScheduleWithOptionDefaults();
  schedule.iterations.push_back({0, 0});
  schedule.num_threads = 1;
  const int centre = 24 * W + 32;  // its window lies inside the block at every scale used
  const Vec3 ray = PixelRay(problem.ref_camera, 32.f, 24.f);
  auto depth_at = [&](const PatchMatchResult& r, int i) {
    return PlaneDepth(Plane{{r.plane[4 * i], r.plane[4 * i + 1], r.plane[4 * i + 2]}, r.plane[4 * i + 3]}, ray);
  };

  PatchMatchResult none;
  RunPatchMatchCpu(problem, schedule, &none);
  EXPECT_GE(none.photo_cost[centre], kInvalidCost);

  std::vector<float> prior_plane(4 * W * H);
  for (int i = 0; i < W * H; ++i) {
    prior_plane[4 * i + 2] = -1.f;  // fronto-parallel at depth 4
    prior_plane[4 * i + 3] = 4.f;
  }
  const std::vector<uint8_t> label(W * H, 1);
  problem.prior_plane = prior_plane.data();
  problem.prior_label = label.data();
  schedule.use_prior = true;
  PatchMatchResult prior;
  RunPatchMatchCpu(problem, schedule, &prior);
  EXPECT_EQ(prior.photo_cost[centre], kFlatPriorCost);
  EXPECT_FLOAT_EQ(depth_at(prior, centre), 4.f);

  // A pass without the prior, started from the prior pass's result, keeps the plane; started
  // from scratch, it has none.
  problem.prior_plane = nullptr;
  problem.prior_label = nullptr;
  schedule.use_prior = false;
  problem.init_plane = prior.plane.data();
  problem.init_cost = prior.cost.data();
  PatchMatchResult kept;
  RunPatchMatchCpu(problem, schedule, &kept);
  EXPECT_EQ(kept.photo_cost[centre], kFlatPriorCost);
  EXPECT_FLOAT_EQ(depth_at(kept, centre), 4.f);
}

// The depth check of the written maps (kernels/DESIGN.md 22): a depth stays only where
// enough sources' depth maps hold the same point within 1 %.
TEST(KernelDepthCheck, KeepsTheDepthsThatEnoughSourcesConfirm) {
  const int W = 40, H = 30;
  const std::vector<float> img = RandomImage(W, H, 7);
  PatchMatchProblem problem = ShiftedSourcesProblem(img, W, H, 50.f, {{0.2f, 0.f, 0.f}, {0.3f, 0.f, 0.f}});
  // Source 0 sees the plane at depth 4 on its left half and 10 % too far on its right half;
  // source 1 sees it at 4 everywhere. The sources shift the image by 2.5 and 3.75 px.
  std::vector<float> half(static_cast<size_t>(W) * H), whole(half.size(), 4.f);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) half[v * W + u] = u < W / 2 ? 4.f : 4.4f;
  }
  problem.sources[0].depth_map = half.data();
  problem.sources[1].depth_map = whole.data();
  auto fronto_parallel = [&] {
    PatchMatchResult result;
    result.width = W;
    result.height = H;
    for (int i = 0; i < W * H; ++i) result.plane.insert(result.plane.end(), {0.f, 0.f, -1.f, 4.f});
    result.photo_cost.assign(static_cast<size_t>(W) * H, 0.1f);
    result.photo_cost[0] = kInvalidCost;  // no estimate: stays without one, not counted
    return result;
  };
  auto kept = [&](const PatchMatchResult& r, int u, int v) { return r.photo_cost[v * W + u] < kInvalidCost; };
  auto check = [&](int min_views, float tolerance, PatchMatchResult* r) {
    return InvalidateUnconfirmedDepths(ConfirmingDifferencesCpu(problem, min_views, 2, *r), tolerance, r);
  };

  // One confirming view: source 1 confirms every pixel it sees (the last 4 columns it does not).
  PatchMatchResult one = fronto_parallel();
  const size_t removed_one = check(1, 0.01f, &one);
  for (int v = 0; v < H; ++v) {
    for (int u = 1; u < W - 5; ++u) EXPECT_TRUE(kept(one, u, v)) << u << "," << v;
    for (int u = W - 3; u < W; ++u) EXPECT_FALSE(kept(one, u, v)) << u << "," << v;
  }
  EXPECT_FALSE(kept(one, 0, 0));
  EXPECT_EQ(removed_one, static_cast<size_t>(std::count(one.photo_cost.begin(), one.photo_cost.end(), kInvalidCost)) - 1);

  // Two: only where source 0's depth is right too.
  PatchMatchResult two = fronto_parallel();
  check(2, 0.01f, &two);
  for (int v = 0; v < H; ++v) {
    for (int u = 1; u < W / 2 - 4; ++u) EXPECT_TRUE(kept(two, u, v)) << u << "," << v;
    for (int u = W / 2; u < W; ++u) EXPECT_FALSE(kept(two, u, v)) << u << "," << v;
  }
  // The difference within which the views confirm a depth: the second smallest for two.
  const std::vector<float> first = ConfirmingDifferencesCpu(problem, 1, 2, fronto_parallel());
  const std::vector<float> second = ConfirmingDifferencesCpu(problem, 2, 2, fronto_parallel());
  EXPECT_NEAR(first[H / 2 * W + W / 2 + 4], 0.f, 1e-5f);
  EXPECT_NEAR(second[H / 2 * W + W / 2 + 4], 0.1f, 1e-5f);
  EXPECT_NEAR(second[H / 2 * W + 4], 0.f, 1e-5f);
  EXPECT_EQ(second[0], kNoDepthDifference);  // no estimate
  EXPECT_EQ(first[H / 2 * W + W - 1], kNoDepthDifference);  // neither source sees it
  // A wider tolerance accepts source 0's 10 % error.
  PatchMatchResult loose = fronto_parallel();
  check(2, 0.15f, &loose);
  for (int u = 1; u < W - 5; ++u) EXPECT_TRUE(kept(loose, u, H / 2)) << u;
}

// The difference within which min_views sources confirm a depth is the min_views-th smallest
// over all sources, in whatever order they come.
TEST(KernelDepthCheck, ConfirmingDifferenceIsTheNthSmallestOverTheSources) {
  const int W = 40, H = 30;
  const std::vector<float> img = RandomImage(W, H, 7);
  PatchMatchProblem problem =
      ShiftedSourcesProblem(img, W, H, 50.f, {{0.2f, 0.f, 0.f}, {0.25f, 0.f, 0.f}, {0.3f, 0.f, 0.f}});
  // The sources hold the plane at depth 4 10 %, 5 % and 0 % too far.
  const std::vector<float> far10(static_cast<size_t>(W) * H, 4.4f), far5(far10.size(), 4.2f),
      exact(far10.size(), 4.f);
  problem.sources[0].depth_map = far10.data();
  problem.sources[1].depth_map = far5.data();
  problem.sources[2].depth_map = exact.data();
  PatchMatchResult result;
  result.width = W;
  result.height = H;
  for (int i = 0; i < W * H; ++i) result.plane.insert(result.plane.end(), {0.f, 0.f, -1.f, 4.f});
  result.photo_cost.assign(static_cast<size_t>(W) * H, 0.1f);
  const int centre = H / 2 * W + W / 2;
  EXPECT_NEAR(ConfirmingDifferencesCpu(problem, 1, 2, result)[centre], 0.f, 1e-5f);
  EXPECT_NEAR(ConfirmingDifferencesCpu(problem, 2, 2, result)[centre], 0.05f, 1e-5f);
  EXPECT_NEAR(ConfirmingDifferencesCpu(problem, 3, 2, result)[centre], 0.1f, 1e-5f);
  EXPECT_EQ(ConfirmingDifferencesCpu(problem, 4, 2, result)[centre], kNoDepthDifference);  // only 3 sources
}

// The depth check also drops depth segments under a size (kernels/DESIGN.md 23): a speckle
// goes, a patch of its own depth as large as the limit stays, and so does a slanted surface
// whose neighbouring depths differ by less than the step.
TEST(KernelDepthCheck, RemovesSmallDepthSegmentsOnly) {
  const int W = 40, H = 30;
  const std::vector<float> img = RandomImage(W, H, 7);
  const PatchMatchProblem problem = ShiftedSourcesProblem(img, W, H, 50.f, {{0.2f, 0.f, 0.f}});
  const Camera& cam = problem.ref_camera;
  PatchMatchResult result;
  result.width = W;
  result.height = H;
  result.photo_cost.assign(static_cast<size_t>(W) * H, 0.1f);
  auto in_box = [](int u, int v, int u0, int v0, int size) {
    return u >= u0 && u < u0 + size && v >= v0 && v < v0 + size;
  };
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      // Left: a ramp, 0.5 % deeper per column; right of column 20: depth 4, with a 3x3 speckle
      // at depth 5 and a 10x10 patch (100 pixels) at depth 3.
      float depth = u < 20 ? 4.f * std::pow(1.005f, static_cast<float>(u)) : 4.f;
      if (in_box(u, v, 24, 3, 3)) depth = 5.f;
      if (in_box(u, v, 25, 15, 10)) depth = 3.f;
      const Plane plane = PlaneFromDepthNormal(PixelRay(cam, static_cast<float>(u), static_cast<float>(v)), depth,
                                               Vec3{0.f, 0.f, -1.f});
      result.plane.insert(result.plane.end(), {plane.n.x, plane.n.y, plane.n.z, plane.d});
    }
  }
  result.photo_cost[(H - 1) * W + 21] = kInvalidCost;  // no estimate: not counted
  const size_t removed = InvalidateSmallDepthSegments(problem, 100, 0.01f, &result);
  EXPECT_EQ(removed, 9u);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const bool expect_kept = !in_box(u, v, 24, 3, 3) && !(v == H - 1 && u == 21);
      EXPECT_EQ(result.photo_cost[v * W + u] < kInvalidCost, expect_kept) << u << "," << v;
    }
  }
  // With a limit of 101 pixels the 10x10 patch goes too; with a step below the ramp's 0.5 %
  // every column of the ramp is a segment of its own (30 pixels) and goes.
  PatchMatchResult stricter = result;
  EXPECT_EQ(InvalidateSmallDepthSegments(problem, 101, 0.01f, &stricter), 100u);
  PatchMatchResult finer = result;
  EXPECT_EQ(InvalidateSmallDepthSegments(problem, 100, 0.004f, &finer), 20u * H);
}

// Plain windows (no vertices of the planar prior, prior acts) are those whose texture after
// removing a shading ramp is within the noise: a steep lit wall is plain, texture is not.
TEST(KernelPrior, PlainWindowMaskMarksShadedWallsNotTexture) {
  const int W = 64, H = 40;
  const std::vector<float> img =  // a steeply lit wall from x = 32
      TextureThenWall(W, H, 7, [](int x, int y) { return 60.f + 3.f * x + 1.5f * y; });
  const std::vector<uint8_t> plain =
      PlainWindowMaskCpu(ImageView{img.data(), W, H}, WindowForScale(0), 1.5f * 1.5f, 2);
  ASSERT_EQ(plain.size(), static_cast<size_t>(W * H));
  int textured_plain = 0, wall_plain = 0, wall = 0;
  for (int y = 5; y < H - 5; ++y) {
    for (int x = 5; x < W - 5; ++x) {
      if (x < 27) textured_plain += plain[y * W + x];
      if (x >= 37) {
        ++wall;
        wall_plain += plain[y * W + x];
      }
    }
  }
  EXPECT_EQ(textured_plain, 0);
  EXPECT_GT(wall_plain, 0.9 * wall);
}

// Refinement stops costing a plane once the views costed so far already put it at or above
// the plane to beat: it is rejected exactly when its full cost would not have won, and a
// plane that is costed in full gets the cost it always had.
TEST(KernelRefinement, RejectedPlanesCouldNotHaveWon) {
  const int W = 80, H = 60;
  const std::vector<float> img = RandomImage(W, H, 21);
  const PatchMatchProblem problem =
      ShiftedSourcesProblem(img, W, H, 70.f, {{0.1f, 0.f, 0.f}, {0.2f, 0.03f, 0.f}, {0.3f, 0.06f, 0.f}});
  PatchMatchSchedule schedule = mpmvs::test::ScheduleWithOptionDefaults();
  schedule.iterations.push_back({0, 0});
  const std::vector<SourceView> sources = MakeSourceViews(problem);
  const PassParams params = MakePassParams(problem, schedule, sources.data());
  const float weights[3] = {5.f, 0.f, 10.f};
  RefPatch patch;
  const int u = 40, v = 30;
  ComputeRefPatch(problem.ref_image, u, v, params.window, &patch);
  const Vec3 ray = PixelRay(problem.ref_camera, float(u), float(v));
  const Plane plane = PlaneFromDepthNormal(ray, 4.f, Normalize(Vec3{0.1f, 0.2f, -1.f}));
  uint32_t n_full = 0;
  const WeightedCost full = EvaluatePlane<ScalarNcc>(params, false, patch, weights, u, v, ray, plane, &n_full);
  ASSERT_EQ(n_full, 2u);
  ASSERT_GT(full.total, 0.f);
  for (const float reject_at : {full.total + 1e-4f, INFINITY}) {
    bool rejected = false;
    uint32_t n = 0;
    const WeightedCost c =
        EvaluatePlane<ScalarNcc>(params, false, patch, weights, u, v, ray, plane, &n, reject_at, &rejected);
    EXPECT_FALSE(rejected);
    EXPECT_EQ(c.total, full.total);
    EXPECT_EQ(n, n_full);
  }
  bool rejected = false;
  uint32_t n = 0;
  EvaluatePlane<ScalarNcc>(params, false, patch, weights, u, v, ray, plane, &n, full.total, &rejected);
  EXPECT_TRUE(rejected);  // equal cost does not replace
  rejected = false;
  n = 0;
  EvaluatePlane<ScalarNcc>(params, false, patch, weights, u, v, ray, plane, &n, 1e-6f, &rejected);
  EXPECT_TRUE(rejected);
  EXPECT_EQ(n, 1u);  // the second selected view was never sampled

  // On prior pixels: no cost at or above PriorRejectCost scores above the score to beat.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (int trial = 0; trial < 20000; ++trial) {
    const float beta = 0.18f + 8.f * unit(rng), compat = 0.5f + unit(rng), score = 1.5f * unit(rng) + 1e-6f;
    const float reject = PriorRejectCost(beta, compat, score);
    const float cost = reject + 0.01f * unit(rng);
    EXPECT_LE(expf(-cost * cost / beta) * compat, score) << beta << " " << compat << " " << score;
  }
}

// The CPU backend's NCC (vectorised where its build allows; the test binary itself is
// compiled without -march=native, so it goes through the backend's own entry point).
TEST(KernelNcc, CpuBackendNccEqualsSharedScalar) {
  std::cout << "CPU backend NCC: " << CpuBackendNccName() << std::endl;
  const int W = 96, H = 80;
  std::vector<float> ref = RandomImage(W, H, 11), src = RandomImage(W, H, 12);
  for (size_t i = 0; i < src.size(); ++i) src[i] = 0.5f * src[i] + 0.5f * ref[i];
  const ImageView rv{ref.data(), W, H}, sv{src.data(), W, H};
  // The packed 8-bit layout the CPU backend builds needs integer grey values.
  for (float& value : src) value = std::round(value);
  std::vector<uint32_t> quads;
  ASSERT_TRUE(MakeQuadImage(sv, &quads));
  ImageView sv_quads = sv;
  sv_quads.quads = quads.data();
  std::vector<float> fractional = src;
  fractional[W + 1] += 0.5f;
  std::vector<uint32_t> refused;
  EXPECT_FALSE(MakeQuadImage(ImageView{fractional.data(), W, H}, &refused));
  EXPECT_TRUE(refused.empty());
  // Past 2^24 pixels float indices are no longer exact: the float path takes over.
  const std::vector<float> huge(static_cast<size_t>(4097) * 4096, 7.f);
  EXPECT_FALSE(MakeQuadImage(ImageView{huge.data(), 4097, 4096}, &refused));
  EXPECT_TRUE(refused.empty());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
  int compared = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const int u = 5 + trial % 85, v = 3 + (trial * 7) % 74;
    const float H9[9] = {1.f + 0.1f * jitter(rng), 0.1f * jitter(rng), 3.f * jitter(rng),
                         0.1f * jitter(rng), 1.f + 0.1f * jitter(rng), 3.f * jitter(rng),
                         1e-3f * jitter(rng), 1e-3f * jitter(rng), 1.f};
    for (int scale = 0; scale <= 2; ++scale) {
      RefPatch patch;
      ComputeRefPatch(rv, u, v, WindowForScale(scale), &patch);
      const float a = ComputeNccCost(patch, sv, H9, u, v, WindowForScale(scale));
      const float b = CpuBackendNccCost(patch, sv, H9, u, v, WindowForScale(scale));
      EXPECT_NEAR(a, b, 2e-4f) << "u=" << u << " v=" << v << " scale=" << scale;
      // The packed 8-bit layout the CPU backend builds gives the same costs.
      const float c = CpuBackendNccCost(patch, sv_quads, H9, u, v, WindowForScale(scale));
      EXPECT_NEAR(a, c, 2e-4f) << "quads u=" << u << " v=" << v << " scale=" << scale;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 1500);
}

TEST(KernelNcc, ExpNegMatchesExpf) {
  double worst = 0;
  for (float x = 0.f; x < 40.f; x += 0.0137f) {
    const double exact = std::exp(-static_cast<double>(x));
    worst = std::max(worst, std::abs(ExpNeg(x) - exact) / exact);
  }
  EXPECT_LT(worst, 1e-5);
  EXPECT_EQ(ExpNeg(0.f), 1.f);
  // The clamp of the exponent to [0, 125] (on the bit pattern): below 0 is e^0, above
  // 125 ln 2 and NaN of either sign are e^-125 ln 2, never an overflowing int conversion.
  const float floor = ExpNeg(100.f);
  EXPECT_GT(floor, 0.f);
  EXPECT_LT(floor, 1e-37f);
  EXPECT_EQ(ExpNeg(-0.f), 1.f);
  EXPECT_EQ(ExpNeg(-3.f), 1.f);
  EXPECT_EQ(ExpNeg(-std::numeric_limits<float>::infinity()), 1.f);
  EXPECT_EQ(ExpNeg(1e30f), floor);
  EXPECT_EQ(ExpNeg(std::numeric_limits<float>::infinity()), floor);
  EXPECT_EQ(ExpNeg(std::numeric_limits<float>::quiet_NaN()), floor);
  EXPECT_EQ(ExpNeg(-std::numeric_limits<float>::quiet_NaN()), floor);
}

}  // namespace
}  // namespace kernels
}  // namespace mpmvs

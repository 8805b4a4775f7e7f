// The depth_check stage (colmap_ext/pipeline/depth_check.h): its tolerance follows how
// closely the sources' maps hold the image's depths.
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

#include "colmap_ext/pipeline/depth_check.h"
#include "tests/plane_scene_util.h"

namespace mpmvs {
namespace {

using kernels::kInvalidCost;

// A reference at the origin and a source 0.2 to its right, both looking down +z at a
// fronto-parallel wall at depth 4 (shifted by 3 px in the source). The reference's
// result holds the wall's depth everywhere; the source's map holds it with a relative error
// of `off` on every fifth column and `rough` elsewhere.
struct WallCheck {
  static constexpr int W = 60, H = 40;
  std::vector<float> image = std::vector<float>(W * H, 100.f);
  std::vector<float> source_depth;
  kernels::PatchMatchProblem problem;
  kernels::PatchMatchResult result;

  WallCheck(float rough, float off) {
    problem.ref_camera = kernels::test::LookAtCamera(W, H, 1.f, {0, 0, 0}, {0, 0, 1}, {0, -1, 0});
    problem.ref_image = kernels::ImageView{image.data(), W, H};
    problem.depth_min = 1.f;
    problem.depth_max = 10.f;
    kernels::PatchMatchSource source;
    source.camera = kernels::test::LookAtCamera(W, H, 1.f, {0.2f, 0, 0}, {0.2f, 0, 1}, {0, -1, 0});
    source.image = problem.ref_image;
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u < W; ++u) source_depth.push_back(4.f * (1.f + (u % 5 == 0 ? off : rough)));
    }
    source.depth_map = source_depth.data();
    problem.sources.push_back(source);
    result.width = W;
    result.height = H;
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u < W; ++u) {
        const kernels::Vec3 ray = kernels::PixelRay(problem.ref_camera, static_cast<float>(u), static_cast<float>(v));
        const kernels::Plane plane = kernels::PlaneFromDepthNormal(ray, 4.f, kernels::Vec3{0.f, 0.f, -1.f});
        result.plane.insert(result.plane.end(), {plane.n.x, plane.n.y, plane.n.z, plane.d});
      }
    }
    result.photo_cost.assign(W * H, 0.1f);
    result.geo_error.assign(W * H, 0.f);
  }
  // Pixels kept away from the reference's left and right 6 columns (the source sees the wall
  // 3 px to the left of where the reference does: the reference's first columns it does not).
  size_t KeptInView() const {
    size_t kept = 0;
    for (int v = 0; v < H; ++v) {
      for (int u = 6; u < W - 6; ++u) kept += result.photo_cost[v * W + u] < kInvalidCost;
    }
    return kept;
  }
};

TEST(DepthCheck, ToleranceWidensWhereTheSourcesHoldTheDepthsOnlyRoughly) {
  // Sharp: the source holds most depths within 0.02 %; 1.5 % is a different depth there.
  WallCheck sharp(0.0002f, 0.015f);
  const DepthCheckCounts sharp_counts =
      RunDepthCheck(sharp.problem, 2.f, 1, kDepthCheckBaseTolerance, 2, &sharp.result);
  EXPECT_FLOAT_EQ(sharp_counts.agreement.tolerance, kDepthCheckBaseTolerance);
  EXPECT_NEAR(sharp_counts.agreement.median_difference, 0.0002f, 2e-5f);
  const size_t in_view = static_cast<size_t>(WallCheck::H) * (WallCheck::W - 12);
  EXPECT_NEAR(static_cast<double>(sharp.KeptInView()), 0.8 * in_view, 0.03 * in_view);

  // Rough (blur): the source holds the depths only within 0.15 %, and 1.5 % is within what
  // the views can tell apart: 15 x 0.15 % = 2.25 %.
  WallCheck rough(0.0015f, 0.015f);
  const DepthCheckCounts rough_counts =
      RunDepthCheck(rough.problem, 2.f, 1, kDepthCheckBaseTolerance, 2, &rough.result);
  EXPECT_NEAR(rough_counts.agreement.tolerance, kDepthCheckTolerancePerMedianDifference * 0.0015f, 1e-4f);
  EXPECT_EQ(rough.KeptInView(), in_view);
  EXPECT_LE(rough_counts.unconfirmed, static_cast<size_t>(12 * WallCheck::H));  // the borders only
}

}  // namespace
}  // namespace mpmvs

// Planar prior construction: vertex selection rules, Delaunay triangles, and the planes
// rasterised per pixel against known planes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "colmap_ext/prior/planar_prior.h"
#include "kernels/ncc.h"

namespace mpmvs {
namespace {

kernels::Camera MakeCamera(int w, int h) {
  kernels::Camera c;
  c.width = w;
  c.height = h;
  c.fx = c.fy = 100.f;
  c.cx = w / 2.f;
  c.cy = h / 2.f;
  return c;
}

// Depth of a known plane n.X + d = 0 at every pixel.
std::vector<float> PlaneDepths(const kernels::Camera& cam, const kernels::Plane& plane) {
  std::vector<float> depth(static_cast<size_t>(cam.width) * cam.height);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      depth[v * cam.width + u] = kernels::PlaneDepth(plane, kernels::PixelRay(cam, float(u), float(v)));
    }
  }
  return depth;
}

// Of the pixels in [u0, u1) x [v0, v1) that a prior triangle covers, those whose prior depth
// lies within relative tolerance tol of depth z.
struct PixelCount {
  int labelled = 0, near = 0;
};
PixelCount PriorDepthsNear(const PlanarPriorModel& model, const kernels::Camera& cam, int u0, int u1, int v0, int v1,
                           float z, float tol) {
  PixelCount count;
  for (int v = v0; v < v1; ++v) {
    for (int u = u0; u < u1; ++u) {
      const size_t i = static_cast<size_t>(v) * cam.width + u;
      if (!model.label[i]) continue;
      ++count.labelled;
      const kernels::Plane plane{{model.plane[4 * i], model.plane[4 * i + 1], model.plane[4 * i + 2]},
                                 model.plane[4 * i + 3]};
      count.near += std::abs(kernels::PlaneDepth(plane, kernels::PixelRay(cam, float(u), float(v))) - z) < tol * z;
    }
  }
  return count;
}

TEST(PlanarPrior, TrianglePlanesMatchAKnownPlane) {
  const kernels::Camera cam = MakeCamera(80, 60);
  const kernels::Vec3 n = kernels::Normalize(kernels::Vec3{0.3f, -0.2f, -1.f});
  const kernels::Plane plane = kernels::PlaneFromDepthNormal(kernels::PixelRay(cam, 40, 30), 5.f, n);
  const std::vector<float> depth = PlaneDepths(cam, plane);
  const size_t num = depth.size();
  std::vector<float> photo(num, 1.f), geo(num, 0.f);
  // Sparse reliable pixels on a coarse grid (every other 5x5 cell), like a textured subset.
  for (int v = 2; v < cam.height; v += 10) {
    for (int u = 2; u < cam.width; u += 10) photo[v * cam.width + u] = 0.05f;
  }
  PlanarPriorOptions options;
  const PlanarPriorModel model = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 20.f, options);
  ASSERT_EQ(model.vertices.size(), 48u);  // 8 x 6 reliable pixels
  EXPECT_GT(model.triangles.size() / 3, 60u);
  int labelled = 0;
  for (size_t i = 0; i < num; ++i) {
    if (!model.label[i]) continue;
    ++labelled;
    const kernels::Vec3 pn{model.plane[4 * i], model.plane[4 * i + 1], model.plane[4 * i + 2]};
    EXPECT_GT(kernels::Dot(pn, n), 0.99999f);  // same plane, facing the camera
    EXPECT_NEAR(model.plane[4 * i + 3], plane.d, 1e-3f * std::abs(plane.d));
  }
  // Everything inside the convex hull of the vertices (u, v in [2, 72] x [2, 52]).
  EXPECT_GE(labelled, 71 * 51);
}

TEST(PlanarPrior, VertexSelectionFollowsThePaper) {
  const int W = 10, H = 5;
  std::vector<float> depth(W * H, 2.f), photo(W * H, 0.5f), geo(W * H, 0.f);
  // Cell 0 (u 0..4): four pixels pass m_p < 0.2 and m_g < 1, one fails m_g.
  photo[0] = 0.10f;
  photo[1] = 0.05f;
  photo[2] = 0.15f;
  photo[3] = 0.19f;
  photo[4] = 0.01f;
  geo[4] = 1.5f;
  // Cell 1 (u 5..9): one pixel below 0.2 but without depth.
  photo[7] = 0.01f;
  depth[7] = 0.f;
  PlanarPriorOptions options;
  std::vector<PlanarPriorVertex> v = SelectPriorVertices(W, H, depth, photo, geo, options);
  ASSERT_EQ(v.size(), 3u);  // at most 3 per cell, lowest combined cost first
  EXPECT_EQ(v[0].u, 1);
  EXPECT_EQ(v[1].u, 0);
  EXPECT_EQ(v[2].u, 2);
  // ACMP selection: one per cell with photometric cost < 0.1.
  options.selection = PlanarPriorOptions::Selection::kPhotometric;
  v = SelectPriorVertices(W, H, depth, photo, geo, options);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].u, 4);  // ACMP ignores the geometric error
}

// A plain window matches wrong planes as well as the right one: with a plain mask it is
// never a vertex, however low its costs; the other pixels of its cell still are.
TEST(PlanarPrior, PlainWindowsAreNoVertices) {
  const int W = 10, H = 5;
  std::vector<float> depth(W * H, 2.f), photo(W * H, 0.5f), geo(W * H, 0.f);
  photo[1] = 0.01f;  // cell 0: the best pixel is plain
  photo[2] = 0.10f;
  photo[6] = 0.01f;  // cell 1: plain only
  std::vector<uint8_t> plain(W * H, 0);
  plain[1] = plain[6] = 1;
  PlanarPriorOptions options;
  std::vector<PlanarPriorVertex> v = SelectPriorVertices(W, H, depth, photo, geo, options, nullptr, &plain);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].u, 2);
  options.selection = PlanarPriorOptions::Selection::kPhotometric;
  v = SelectPriorVertices(W, H, depth, photo, geo, options, nullptr, &plain);
  EXPECT_TRUE(v.empty());  // photometric selection: cost < 0.1 left only plain pixels
  v = SelectPriorVertices(W, H, depth, photo, geo, options);
  EXPECT_EQ(v.size(), 2u);  // without the mask: the paper's rule
}

TEST(PlanarPrior, DepthBendsOnlyNearAStepOrKink) {
  const kernels::Camera cam = MakeCamera(60, 40);
  // A slanted plane bends nowhere, however steep.
  const kernels::Vec3 n = kernels::Normalize(kernels::Vec3{0.6f, -0.3f, -1.f});
  std::vector<float> depth =
      PlaneDepths(cam, kernels::PlaneFromDepthNormal(kernels::PixelRay(cam, 30, 20), 4.f, n));
  std::vector<uint8_t> bent = BentDepthMask(cam.width, cam.height, depth, 3, 0.01f);
  EXPECT_EQ(std::count(bent.begin(), bent.end(), 1), 0);

  // A wall at depth 4 with a strip 2 % nearer in columns 20-39 (a bar in front, its depth
  // bled onto the wall beside it): only pixels within 3 columns of either edge bend.
  depth.assign(static_cast<size_t>(cam.width) * cam.height, 4.f);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 20; u < 40; ++u) depth[v * cam.width + u] = 3.92f;
  }
  depth[5 * cam.width + 50] = 0.f;  // no depth: its neighbours' tests through it are skipped
  bent = BentDepthMask(cam.width, cam.height, depth, 3, 0.01f);
  for (int u = 0; u < cam.width; ++u) {
    const bool near_edge = (u >= 17 && u <= 22) || (u >= 37 && u <= 42);
    EXPECT_EQ(bent[20 * cam.width + u], near_edge ? 1 : 0) << "column " << u;
  }
  // Around the pixel without depth (50, 5), the directions through it are skipped, not
  // taken for a jump to infinite inverse depth.
  for (const auto& p : {std::make_pair(50, 5), std::make_pair(47, 5), std::make_pair(53, 5), std::make_pair(50, 2),
                        std::make_pair(50, 8), std::make_pair(47, 2), std::make_pair(53, 8)}) {
    EXPECT_EQ(bent[p.second * cam.width + p.first], 0) << p.first << ", " << p.second;
  }
  // A 2 % step is not a bend at a 3 % threshold.
  bent = BentDepthMask(cam.width, cam.height, depth, 3, 0.03f);
  EXPECT_EQ(std::count(bent.begin(), bent.end(), 1), 0);
}

TEST(PlanarPrior, TrianglesAcrossADepthStepTakeAPlaneOfOneSide) {
  const kernels::Camera cam = MakeCamera(60, 40);
  std::vector<float> depth(60 * 40), photo(60 * 40, 1.f), geo(60 * 40, 0.f);
  for (int v = 0; v < 40; ++v) {
    for (int u = 0; u < 60; ++u) depth[v * 60 + u] = u < 30 ? 3.f : 6.f;  // a step
  }
  for (int v = 2; v < 40; v += 5) {
    for (int u = 2; u < 60; u += 5) photo[v * 60 + u] = 0.05f;
  }
  // Every pixel's own plane faces the camera (fronto-parallel steps).
  std::vector<float> planes(4 * 60 * 40, 0.f);
  for (size_t i = 0; i < depth.size(); ++i) {
    planes[4 * i + 2] = -1.f;
    planes[4 * i + 3] = depth[i];
  }
  auto depth_at = [&](const PlanarPriorModel& model, size_t i) {
    const kernels::Plane pl{{model.plane[4 * i], model.plane[4 * i + 1], model.plane[4 * i + 2]}, model.plane[4 * i + 3]};
    return kernels::PlaneDepth(pl, kernels::PixelRay(cam, float(i % 60), float(i / 60)));
  };
  PlanarPriorOptions options;
  const PlanarPriorModel model = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, options, &planes);
  EXPECT_GT(model.num_voted_triangles, 0);
  // The vote splits the triangles over threads: any split gives the same model.
  for (const int threads : {2, 3}) {
    PlanarPriorOptions threaded = options;
    threaded.num_threads = threads;
    const PlanarPriorModel same = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, threaded, &planes);
    EXPECT_EQ(same.plane, model.plane) << threads << " threads";
    EXPECT_EQ(same.label, model.label) << threads << " threads";
    EXPECT_EQ(same.num_voted_triangles, model.num_voted_triangles) << threads << " threads";
  }
  // The triangles between the two steps' vertices vote for one of the two levels: no
  // labelled pixel carries a depth in between.
  int labelled = 0;
  for (size_t i = 0; i < model.label.size(); ++i) {
    if (!model.label[i]) continue;
    ++labelled;
    const float z = depth_at(model, i);
    EXPECT_TRUE(std::abs(z - 3.f) < 1e-3f || std::abs(z - 6.f) < 1e-3f) << "u " << i % 60 << ": " << z;
  }
  EXPECT_GT(labelled, 50 * 30);
  // Without the vote, the paper's planes through the three vertices: the triangles across
  // the step (u 27..32) slope from one level to the other.
  options.plane_vote = false;
  const PlanarPriorModel paper = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, options, &planes);
  EXPECT_EQ(paper.num_voted_triangles, 0);
  int between = 0;
  for (size_t i = 0; i < paper.label.size(); ++i) {
    const float z = depth_at(paper, i);
    between += paper.label[i] && z > 3.01f && z < 5.99f;
  }
  EXPECT_GT(between, 0);
}

// BuildPlanarPrior's model where the selected vertices on voter_only's pixels are no corners
// (as the prior stage marks the epipolar-blind ones).
PlanarPriorModel PriorWithVoters(const kernels::Camera& cam, const std::vector<float>& depth,
                                 const std::vector<float>& photo, const std::vector<float>& geo,
                                 const PlanarPriorOptions& options, const std::vector<float>* planes,
                                 const std::vector<uint8_t>& voter_only) {
  std::vector<PlanarPriorVertex> vertices =
      SelectPriorVertices(cam.width, cam.height, depth, photo, geo, options, planes);
  for (PlanarPriorVertex& vertex : vertices) {
    vertex.corner = !voter_only[static_cast<size_t>(vertex.v) * cam.width + vertex.u];
  }
  return PlanarPriorFromVertices(cam, std::move(vertices), 1.f, 10.f, options);
}

// Voter-only vertices (corner false) are no triangle corners, yet their votes count. A
// fronto-parallel wall A (depth 5) holds the corners; a plane B crosses it along row 20,
// where the corners carry B's normal, so B is a candidate of the triangles there. The
// corners are 10 px apart; two voter-only vertices per 5 px cell lie on B and outvote them
// near row 20. Left out altogether (excluded), they change nothing and every triangle keeps
// A.
TEST(PlanarPrior, VoterOnlyVerticesVoteButAreNoCorners) {
  const int W = 60, H = 40;
  const kernels::Camera cam = MakeCamera(W, H);  // f 100, principal point (30, 20)
  auto depth_b = [](int v) { return 1.f / (0.2f + 0.002f * (v - 20)); };  // B: 0.2 y + 0.2 z = 1
  const kernels::Vec3 normal_b = kernels::Normalize(kernels::Vec3{0.f, 0.2f, 0.2f});
  std::vector<float> depth(W * H, 5.f), photo(W * H, 1.f), geo(W * H, 0.f), planes(4 * W * H, 0.f);
  std::vector<uint8_t> voter_only(W * H, 0);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      kernels::Vec3 n{0.f, 0.f, -1.f};
      if (u % 10 == 0 && v % 10 == 0) {
        photo[i] = 0.05f;  // a corner, on A
        if (v == 20) n = normal_b;
      } else if ((u % 5 == 2 && v % 5 == 2) || (u % 5 == 3 && v % 5 == 3)) {
        photo[i] = 0.06f;  // on B
        depth[i] = depth_b(v);
        voter_only[i] = 1;
      }
      planes[4 * i] = n.x;
      planes[4 * i + 1] = n.y;
      planes[4 * i + 2] = n.z;
    }
  }
  PlanarPriorOptions options;
  const PlanarPriorModel voting = PriorWithVoters(cam, depth, photo, geo, options, &planes, voter_only);
  const PlanarPriorModel excluded = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, options, &planes, &voter_only);
  int num_voters = 0;
  for (const PlanarPriorVertex& vertex : voting.vertices) num_voters += !vertex.corner;
  EXPECT_EQ(num_voters, 2 * 12 * 8);
  for (int index : voting.triangles) EXPECT_TRUE(voting.vertices[index].corner) << index;
  auto on_b = [&](const PlanarPriorModel& model) {
    int count = 0;
    for (int v = 22; v < 30; ++v) {
      for (int u = 5; u < W - 5; ++u) {
        const size_t i = static_cast<size_t>(v) * W + u;
        if (!model.label[i]) continue;
        const kernels::Plane pl{{model.plane[4 * i], model.plane[4 * i + 1], model.plane[4 * i + 2]},
                                model.plane[4 * i + 3]};
        const float z = kernels::PlaneDepth(pl, kernels::PixelRay(cam, float(u), float(v)));
        count += std::abs(z - depth_b(v)) < 0.002f * depth_b(v);
      }
    }
    return count;
  };
  EXPECT_GT(on_b(voting), 100);
  EXPECT_EQ(on_b(excluded), 0);
  // Those beyond the corners' hull (u > 50 or v > 30) fall in no triangle and do not vote.
  EXPECT_GT(voting.num_vote_only_vertices, 100);
  EXPECT_LT(voting.num_vote_only_vertices, num_voters);
  // Without the vote there is nothing to vote on: every selected vertex is a corner.
  options.plane_vote = false;
  const PlanarPriorModel paper = PriorWithVoters(cam, depth, photo, geo, options, &planes, voter_only);
  for (const PlanarPriorVertex& vertex : paper.vertices) EXPECT_TRUE(vertex.corner);
  EXPECT_EQ(paper.num_vote_only_vertices, 0);
}

// Corners on one line triangulate into no triangle; a vertex that would vote inside one
// finds none (CGAL's triangulation is then one-dimensional).
TEST(PlanarPrior, VoteOnlyVertexBesideCollinearCornersIsIgnored) {
  const int W = 40, H = 30;
  const kernels::Camera cam = MakeCamera(W, H);
  std::vector<float> depth(W * H, 5.f), photo(W * H, 1.f), geo(W * H, 0.f);
  std::vector<uint8_t> voter_only(W * H, 0);
  for (int u = 2; u < W; u += 5) photo[10 * W + u] = 0.05f;  // corners on row 10 only
  photo[10 * W + 11] = 0.06f;                                   // on that row, between two
  voter_only[10 * W + 11] = 1;
  photo[22 * W + 13] = 0.06f;  // off the line
  voter_only[22 * W + 13] = 1;
  PlanarPriorOptions options;
  const PlanarPriorModel model = PriorWithVoters(cam, depth, photo, geo, options, nullptr, voter_only);
  EXPECT_EQ(model.vertices.size(), 10u);
  EXPECT_TRUE(model.triangles.empty());
  EXPECT_EQ(model.num_vote_only_vertices, 0);
  for (uint8_t l : model.label) EXPECT_EQ(l, 0);
}

// A wall seen obliquely whose vertices carry no normals, with a thin object a little in
// front of it: the triangles joining the object's vertices to the wall's take the wall's
// plane, which most vertices around them lie on.
TEST(PlanarPrior, WallTrianglesTouchingAnObjectInFrontTakeTheWallPlane) {
  const int W = 80, H = 60;
  const kernels::Camera cam = MakeCamera(W, H);
  // Wall: a plane tilted about the vertical axis (inverse depth linear in u); object:
  // columns 39..40, 3 % nearer, with vertices at u = 39 between the wall's at 37 and 42.
  std::vector<float> depth(W * H), photo(W * H, 1.f), geo(W * H, 0.f);
  auto wall = [](int u) { return 1.f / (0.25f - 0.0005f * u); };
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) depth[v * W + u] = (u == 39 || u == 40) ? 0.97f * wall(u) : wall(u);
  }
  for (int v = 2; v < H; v += 5) {
    for (int u = 2; u < W; u += 5) photo[v * W + u] = 0.05f;
    photo[v * W + 39] = 0.05f;  // the object's vertices
  }
  PlanarPriorOptions options;
  const PlanarPriorModel model = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, options);
  options.plane_vote = false;
  const PlanarPriorModel paper = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, options);
  // The wall pixels beside the object (u 38 and 41, inside triangles that join the object's
  // vertices to the wall's) within 0.5 %.
  int right = 0, right_paper = 0, total = 0;
  for (int v = 5; v < H - 5; ++v) {
    for (int u : {38, 41}) {
      const size_t i = static_cast<size_t>(v) * W + u;
      if (!model.label[i] || !paper.label[i]) continue;
      ++total;
      const kernels::Vec3 ray = kernels::PixelRay(cam, float(u), float(v));
      const float z = kernels::PlaneDepth({{model.plane[4 * i], model.plane[4 * i + 1], model.plane[4 * i + 2]},
                                           model.plane[4 * i + 3]}, ray);
      const float zp = kernels::PlaneDepth({{paper.plane[4 * i], paper.plane[4 * i + 1], paper.plane[4 * i + 2]},
                                            paper.plane[4 * i + 3]}, ray);
      right += std::abs(z - wall(u)) < 0.005f * wall(u);
      right_paper += std::abs(zp - wall(u)) < 0.005f * wall(u);
    }
  }
  ASSERT_GT(total, 60);
  EXPECT_GT(right, 0.95 * total);
  EXPECT_LT(right_paper, 0.9 * total);  // the paper's planes slope towards the object
}

// A plain wall with a few scattered vertices beside a densely textured panel in front of it:
// the triangles over the wall next to the panel take the wall's plane, although the panel's
// vertices around them outnumber the wall's (each vote weighs the vertex's spacing).
TEST(PlanarPrior, DenseVerticesOfAnObjectDoNotOutvoteThePlainWallBesideIt) {
  const int W = 120, H = 60;
  const kernels::Camera cam = MakeCamera(W, H);
  // Wall: fronto-parallel at depth 4, a vertex about every 16 px (u < 56). Panel: columns
  // 70 and right, 10 % nearer, vertices 2 px apart.
  std::vector<float> depth(W * H), photo(W * H, 1.f), geo(W * H, 0.f);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) depth[v * W + u] = u >= 70 ? 3.6f : 4.f;
  }
  for (int v = 0; v < H; v += 2) {
    for (int u = 70; u < W; u += 2) photo[v * W + u] = 0.05f;
  }
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) photo[(2 + 16 * j + (5 * i) % 7) * W + 3 + 16 * i + (7 * j) % 9] = 0.05f;
  }
  PlanarPriorOptions options;
  const PlanarPriorModel model = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, options);
  // The wall's pixels between its vertices and the panel (u 56..67), inside triangles that
  // join the two, within 0.5 % of the wall.
  const PixelCount wall = PriorDepthsNear(model, cam, 56, 68, 10, H - 10, 4.f, 0.005f);
  ASSERT_GT(wall.labelled, 40 * 12 * 9 / 10);
  EXPECT_GT(wall.near, 0.9 * wall.labelled);
}

// A plain wall beside a frame 1.4 % in front of it, with the frame's depth bled onto a strip of
// the wall next to it (vertices 0.8 % in front of the wall, their tangent planes among the
// candidates). With a symmetric 1 % band, the plane through the bled strip is within reach of
// the wall's vertices behind it and of the frame's in front, and the wall's triangles take it;
// a vertex more than 0.7 % behind a plane, which that plane would hide, does not vote for it.
TEST(PlanarPrior, WallBesideAFrameIsNotPulledTowardsTheFrame) {
  const int W = 120, H = 60;
  const kernels::Camera cam = MakeCamera(W, H);
  std::vector<float> depth(W * H), photo(W * H, 1.f), geo(W * H, 0.f), planes(4 * W * H, 0.f);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      depth[i] = (u >= 64 && u < 70) ? 3.944f : (u >= 58 && u < 64) ? 3.968f : 4.f;
      if (u >= 58 && u < 64) planes[4 * i + 2] = -1.f;  // the bled strip's tangent planes
    }
  }
  for (int v = 1; v < H; v += 2) {
    for (int u = 64; u < 70; u += 2) photo[v * W + u] = 0.05f;  // the frame: dense
  }
  for (int v = 2; v < H; v += 4) photo[v * W + 60] = 0.05f;  // the bled strip
  for (int v = 3; v < H; v += 12) {
    for (int u : {4, 16, 28, 40, 52, 76, 88, 100, 112}) photo[v * W + u] = 0.05f;  // the wall: sparse
  }
  PlanarPriorOptions options;
  const PlanarPriorModel model = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, options, &planes);
  // The wall's pixels between its last vertices and the bled strip (u 44..57) within 0.5 %.
  const PixelCount wall = PriorDepthsNear(model, cam, 44, 58, 6, H - 6, 4.f, 0.005f);
  ASSERT_GT(wall.labelled, 48 * 14 * 9 / 10);
  EXPECT_GT(wall.near, 0.9 * wall.labelled);
}

// A plain strip of wall between two objects 1.5 % in front of it (a curtain and a window
// frame), with vertices only on the objects beside it: every triangle over the strip joins
// the two objects, and every vertex around it lies on their plane. The wall's vertices
// farther out make the wall a dominant plane of the image; the strip's triangles, parallel
// to it and less than 3 % in front of it, take it.
TEST(PlanarPrior, PlainStripBetweenObjectsInFrontOfAWallTakesTheWallPlane) {
  const int W = 120, H = 60;
  const kernels::Camera cam = MakeCamera(W, H);
  std::vector<float> depth(W * H), photo(W * H, 1.f), geo(W * H, 0.f), planes(4 * W * H, 0.f);
  auto object = [](int u) { return (u >= 40 && u < 44) || (u >= 76 && u < 80); };
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      depth[i] = object(u) ? 3.94f : 4.f;
      planes[4 * i + 2] = -1.f;  // fronto-parallel tangent planes
    }
  }
  for (int v = 1; v < H; v += 3) {
    photo[v * W + 42] = 0.05f;  // the objects: dense
    photo[v * W + 77] = 0.05f;
  }
  for (int v = 3; v < H; v += 12) {
    for (int u : {4, 16, 28, 92, 104, 116}) photo[v * W + u] = 0.05f;  // the wall: sparse
  }
  PlanarPriorOptions options;
  const PlanarPriorModel model = BuildPlanarPrior(cam, depth, photo, geo, 1.f, 10.f, options, &planes);
  // The strip's pixels (u 46..73) within 0.5 % of the wall.
  const PixelCount strip = PriorDepthsNear(model, cam, 46, 74, 6, H - 6, 4.f, 0.005f);
  ASSERT_GT(strip.labelled, 28 * (H - 12) * 9 / 10);
  EXPECT_GT(strip.near, 0.95 * strip.labelled);
}

// A plain wall (grey 150, fronto-parallel at depth 4, vertices 12 px apart on the left and
// right) behind a pole (grey 60, columns 56..63, depth 2, dense vertices on both of its
// edges): the triangles between the wall's last vertices and the pole bridge the two. Their
// wall pixels take the wall's plane by colour; without the guide, or with the paper's
// setting, they take the triangles' planes, sloping towards the pole.
TEST(PlanarPrior, PlainWallPixelsOfTrianglesBridgingToAPoleTakeTheWallPlaneByColour) {
  const int W = 120, H = 60;
  const kernels::Camera cam = MakeCamera(W, H);
  auto pole = [](int u) { return u >= 56 && u < 64; };
  std::vector<float> grey(W * H);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) grey[v * W + u] = pole(u) ? 60.f : 150.f;
  }
  const kernels::ImageView guide{grey.data(), W, H};
  const kernels::Vec3 facing{0.f, 0.f, -1.f};
  std::vector<PlanarPriorVertex> vertices;
  for (int v = 3; v < H; v += 12) {
    for (int u : {4, 16, 28, 92, 104, 116}) vertices.push_back({u, v, 4.f, facing});
  }
  for (int v = 1; v < H; v += 3) {
    for (int u : {57, 62}) vertices.push_back({u, v, 2.f, facing});
  }
  PlanarPriorOptions options;
  const PlanarPriorModel model = PlanarPriorFromVertices(cam, vertices, 1.f, 10.f, options, nullptr, &guide);
  const PlanarPriorModel unguided = PlanarPriorFromVertices(cam, vertices, 1.f, 10.f, options);
  options.corner_colour_match = 0.f;
  const PlanarPriorModel paper = PlanarPriorFromVertices(cam, vertices, 1.f, 10.f, options, nullptr, &guide);
  // The wall's pixels between its last vertices and the pole (u 30..54 and 65..90): the
  // vote alone brings about half of them onto the wall.
  for (const auto& [u0, u1] : {std::pair{30, 55}, std::pair{65, 91}}) {
    const PixelCount wall = PriorDepthsNear(model, cam, u0, u1, 6, H - 6, 4.f, 0.005f);
    ASSERT_GT(wall.labelled, (u1 - u0) * (H - 12) * 9 / 10);
    EXPECT_GT(wall.near, 0.99 * wall.labelled);
    EXPECT_LT(PriorDepthsNear(unguided, cam, u0, u1, 6, H - 6, 4.f, 0.005f).near, 0.6 * wall.labelled);
    EXPECT_LT(PriorDepthsNear(paper, cam, u0, u1, 6, H - 6, 4.f, 0.005f).near, 0.6 * wall.labelled);
  }
  // The pole's pixels match no wall corner: they keep their triangles' planes.
  for (int v = 0; v < H; ++v) {
    for (int u = 56; u < 64; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      EXPECT_EQ(model.label[i], paper.label[i]);
      for (int k = 0; k < 4; ++k) EXPECT_EQ(model.plane[4 * i + k], paper.plane[4 * i + k]) << u << " " << v;
    }
  }
}

// A source view's vertex lands where its 3-D point projects in the reference, with the
// reference's depth and the normal rotated into the reference frame; points behind the
// reference are dropped.
TEST(PlanarPrior, SourceVerticesTransferToTheReferenceCamera) {
  const kernels::Camera ref = MakeCamera(80, 60);
  kernels::Camera src = MakeCamera(80, 60);
  const float a = 0.2f;  // source rotated about the y axis, and shifted
  const float R[9] = {std::cos(a), 0.f, -std::sin(a), 0.f, 1.f, 0.f, std::sin(a), 0.f, std::cos(a)};
  for (int k = 0; k < 9; ++k) src.R[k] = R[k];
  src.t[0] = -0.3f;
  src.t[2] = 0.1f;
  std::vector<PlanarPriorVertex> vertices = {{10, 20, 4.f, kernels::Normalize(kernels::Vec3{0.f, 0.f, -1.f})},
                                             {70, 5, 2.5f, kernels::Normalize(kernels::Vec3{0.3f, -0.1f, -1.f})}};
  const std::vector<PlanarPriorVertex> seen = TransferPriorVertices(src, ref, vertices);
  ASSERT_EQ(seen.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    // World point (= reference camera point): R^T (X_src - t).
    const kernels::Vec3 Xs = vertices[i].depth * kernels::PixelRay(src, float(vertices[i].u), float(vertices[i].v));
    const kernels::Vec3 d{Xs.x - src.t[0], Xs.y - src.t[1], Xs.z - src.t[2]};
    const kernels::Vec3 X{R[0] * d.x + R[3] * d.y + R[6] * d.z, R[1] * d.x + R[4] * d.y + R[7] * d.z,
                          R[2] * d.x + R[5] * d.y + R[8] * d.z};
    const kernels::Vec3 n = vertices[i].normal;
    const kernels::Vec3 nr{R[0] * n.x + R[3] * n.y + R[6] * n.z, R[1] * n.x + R[4] * n.y + R[7] * n.z,
                           R[2] * n.x + R[5] * n.y + R[8] * n.z};
    EXPECT_EQ(seen[i].u, std::lround(ref.fx * X.x / X.z + ref.cx));
    EXPECT_EQ(seen[i].v, std::lround(ref.fy * X.y / X.z + ref.cy));
    EXPECT_NEAR(seen[i].depth, X.z, 1e-5f);
    EXPECT_GT(kernels::Dot(seen[i].normal, nr), 0.99999f);
  }
  kernels::Camera behind = ref;
  behind.t[2] = -10.f;  // every point lies behind this camera
  EXPECT_TRUE(TransferPriorVertices(src, behind, vertices).empty());
}

// A ceiling whose only vertices in the reference are the crease with a wall (the ceiling
// itself is plain): its pixels lie outside the hull of the reference's own vertices. The
// source views' vertices above the image span it from the crease, with the ceiling's plane.
TEST(PlanarPrior, SourceVerticesOutsideTheImageSpanACeiling) {
  const int W = 80, H = 60;
  const kernels::Camera cam = MakeCamera(W, H);  // f 100, centre (40, 30)
  // Wall z = 5 below row 20; ceiling y = -0.5 above it (the crease is row 20 on the wall).
  auto ceiling = [](float v) { return 50.f / (30.f - v); };
  std::vector<float> depth(W * H, 5.f), photo(W * H, 1.f), geo(W * H, 0.f);
  for (int v = 0; v < 20; ++v) {
    for (int u = 0; u < W; ++u) depth[v * W + u] = 0.8f * ceiling(float(v));  // plain: wrong, no vertex
  }
  for (int v = 20; v < H; v += 5) {
    for (int u = 2; u < W; u += 5) photo[v * W + u] = 0.05f;
  }
  std::vector<PlanarPriorVertex> outside;
  for (int v : {-28, -18, -8}) {
    for (int u = -38; u < W + 38; u += 5) outside.push_back({u, v, ceiling(float(v))});
  }
  const size_t kept = outside.size() + 1;
  outside.push_back({-33, -18, 1.f});   // a second vertex in an outside cell: kept (3 per cell)
  outside.push_back({40, 10, 3.f});     // inside the image: ignored
  outside.push_back({40, -60, 0.7f});   // farther than half the image from its border: ignored
  outside.push_back({20, -5, 30.f});    // outside the depth range: ignored
  PlanarPriorOptions options;
  const PlanarPriorModel own = BuildPlanarPrior(cam, depth, photo, geo, 0.5f, 20.f, options);
  const PlanarPriorModel model = BuildPlanarPrior(cam, depth, photo, geo, 0.5f, 20.f, options, nullptr, nullptr, &outside);
  EXPECT_EQ(model.num_outside_vertices, static_cast<int>(kept));
  EXPECT_EQ(model.vertices.size(), own.vertices.size() + kept);
  int labelled_own = 0, right = 0, total = 0;
  for (int v = 0; v < 19; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      ++total;
      labelled_own += own.label[i];
      if (!model.label[i]) continue;
      const float z = kernels::PlaneDepth({{model.plane[4 * i], model.plane[4 * i + 1], model.plane[4 * i + 2]},
                                           model.plane[4 * i + 3]},
                                          kernels::PixelRay(cam, float(u), float(v)));
      right += std::abs(z - ceiling(float(v))) < 0.005f * ceiling(float(v));
    }
  }
  EXPECT_EQ(labelled_own, 0);  // the reference's own vertices do not reach above row 20
  EXPECT_GT(right, 0.9 * total);
}

}  // namespace
}  // namespace mpmvs

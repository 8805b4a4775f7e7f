#include "colmap_ext/prior/planar_prior.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "colmap_ext/util/thread_range.h"
#include "kernels/ncc.h"
#include "kernels/patch_match_pixel.h"

namespace mpmvs {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;

using kernels::Vec3;

// A vertex lies on a dominant plane within this share of its depth (kernels/DESIGN.md 31).
constexpr float kOnDominantPlane = 0.005f;

Vec3 VertexPoint(const kernels::Camera& camera, const PlanarPriorVertex& v) {
  return v.depth * kernels::PixelRay(camera, static_cast<float>(v.u), static_cast<float>(v.v));
}

// The plane with unit normal n through X, its normal turned towards the camera.
kernels::Plane FacingPlane(Vec3 n, const Vec3& X) {
  if (kernels::Dot(n, X) > 0.f) n = -n;
  return kernels::Plane{n, -kernels::Dot(n, X)};
}

// A third of the pixel area of the triangle with corners a, b, c: each corner's share.
float ThirdOfArea(const PlanarPriorVertex& a, const PlanarPriorVertex& b, const PlanarPriorVertex& c) {
  return std::abs(float(b.u - a.u) * (c.v - a.v) - float(b.v - a.v) * (c.u - a.u)) / 6.f;
}

// Each vertex's viewing ray (its depth along it is its point).
std::vector<Vec3> VertexRays(const kernels::Camera& camera, const std::vector<PlanarPriorVertex>& vertices) {
  std::vector<Vec3> rays(vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) {
    rays[i] = kernels::PixelRay(camera, static_cast<float>(vertices[i].u), static_cast<float>(vertices[i].v));
  }
  return rays;
}

// Each vertex's share of the triangles' area: a third of its incident triangles' area, in
// pixels (0 for a vertex that is no corner). Its square root weighs the vertex's vote.
std::vector<float> CornerAreas(const std::vector<PlanarPriorVertex>& vertices,
                               const std::vector<std::array<int, 3>>& faces) {
  std::vector<float> area(vertices.size(), 0.f);
  for (const std::array<int, 3>& f : faces) {
    const float third = ThirdOfArea(vertices[f[0]], vertices[f[1]], vertices[f[2]]);
    for (int k = 0; k < 3; ++k) area[f[k]] += third;
  }
  return area;
}

// A vertex that votes but is no corner: the corners of the triangle it falls in, and a third
// of that triangle's area in pixels (its vote's weight is the square root, as a corner's).
struct VoteOnlyVertex {
  int vertex;
  std::array<int, 3> corners;
  float third_of_area;
};

// Each triangle's plane by a vote of the vertices around it (kernels/DESIGN.md 15): the
// candidates are the own planes of the triangles that share a vertex with it (itself
// first) and its vertices' tangent planes; each vertex within two rings of the triangle's
// vertices votes for the candidates on which it lies; the most votes win, a tie keeps the
// earlier candidate. A wall triangle whose corners sit on an object in front of the wall,
// or whose three vertices lie on three surfaces, takes the plane that its neighbourhood
// agrees on instead of a plane through empty space. A vertex's vote weighs the square root
// of its share of the triangles' area, i.e. its spacing in pixels: a textured object, dense
// with vertices, does not outvote by number alone the few vertices that span the plain wall
// beside it (kernels/DESIGN.md 20). "On the plane" is up to 1 % in front of it but only
// 0.7 % behind it: the plane would hide a vertex behind it, and a plane between a wall and a
// frame a little in front of it no longer gathers the votes of both (kernels/DESIGN.md 26).
std::vector<kernels::Plane> VotedPlanes(const kernels::Camera& camera, const std::vector<PlanarPriorVertex>& vertices,
                                        const std::vector<std::array<int, 3>>& faces,
                                        const std::vector<kernels::Plane>& own,
                                        const std::vector<VoteOnlyVertex>& vote_only, int num_threads,
                                        int* num_changed) {
  constexpr float kInFront = 0.01f, kBehind = 0.007f;  // relative to the vertex's depth
  const size_t nv = vertices.size();
  const std::vector<Vec3> rays = VertexRays(camera, vertices);
  std::vector<Vec3> points(nv);
  for (size_t i = 0; i < nv; ++i) points[i] = vertices[i].depth * rays[i];
  std::vector<std::vector<int>> ring(nv), incident(nv);
  std::vector<float> area = CornerAreas(vertices, faces);
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      incident[faces[f][k]].push_back(static_cast<int>(f));
      ring[faces[f][k]].push_back(faces[f][(k + 1) % 3]);
      ring[faces[f][k]].push_back(faces[f][(k + 2) % 3]);
    }
  }
  std::vector<float> weight(nv);
  for (const VoteOnlyVertex& w : vote_only) {
    area[w.vertex] = w.third_of_area;
    for (int c : w.corners) ring[c].push_back(w.vertex);  // w is one ring from its corners
  }
  for (size_t i = 0; i < nv; ++i) {
    weight[i] = std::sqrt(area[i]);
    ring[i].push_back(static_cast<int>(i));
    std::sort(ring[i].begin(), ring[i].end());
    ring[i].erase(std::unique(ring[i].begin(), ring[i].end()), ring[i].end());
  }
  std::vector<kernels::Plane> chosen(faces.size());
  std::vector<uint8_t> changed(faces.size(), 0);
  // Each face reads the shared tables and writes only its own entries: any split over
  // threads gives the same planes.
  RunRangeInThreads(static_cast<int>(faces.size()), num_threads, [&](int begin, int end) {
    std::vector<int> voter_stamp(nv, -1), face_stamp(faces.size(), -1);
    std::vector<int> voters;
    // The candidate planes side by side (normal, offset) and their votes: each voter is
    // weighed against all candidates in one branch-free loop the compiler vectorises, and
    // each candidate's votes still add up in the voters' order.
    std::vector<float> nx, ny, nz, d, votes;
    auto add_candidate = [&](const kernels::Plane& plane) {
      nx.push_back(plane.n.x);
      ny.push_back(plane.n.y);
      nz.push_back(plane.n.z);
      d.push_back(plane.d);
    };
    for (int f = begin; f < end; ++f) {
      const int stamp = f;
      voters.clear();
      for (auto* column : {&nx, &ny, &nz, &d}) column->clear();
      add_candidate(own[f]);
      face_stamp[f] = stamp;
      for (int k = 0; k < 3; ++k) {
        const int v = faces[f][k];
        for (int r1 : ring[v]) {
          for (int r2 : ring[r1]) {
            if (voter_stamp[r2] != stamp) {
              voter_stamp[r2] = stamp;
              voters.push_back(r2);
            }
          }
        }
        const Vec3& normal = vertices[v].normal;
        if (kernels::Norm(normal) > 0.f) add_candidate(FacingPlane(kernels::Normalize(normal), points[v]));
        for (int g : incident[v]) {
          if (face_stamp[g] == stamp) continue;
          face_stamp[g] = stamp;
          add_candidate(own[g]);
        }
      }
      const size_t nc = d.size();
      votes.assign(nc, 0.f);
      for (int j : voters) {
        const Vec3 ray = rays[j];
        const float depth = vertices[j].depth, w = weight[j];
        for (size_t c = 0; c < nc; ++c) {
          // kernels::PlaneDepth without its test for a ray parallel to the plane: there its
          // -1 and this infinite or NaN depth are both outside every band (a vertex's depth
          // is > 0).
          const float z = -d[c] / kernels::Dot(Vec3{nx[c], ny[c], nz[c]}, ray);
          const float behind = (depth - z) / depth;
          // Quiet comparisons, both evaluated: the compiler may then run them without a
          // branch although float compares may trap (GCC's default -ftrapping-math).
          const bool above = std::isgreater(behind, -kInFront), below = std::isless(behind, kBehind);
          votes[c] += (above && below) ? w : 0.f;
        }
      }
      int best = 0;
      float best_votes = -1.f;
      for (size_t c = 0; c < nc; ++c) {
        if (votes[c] > best_votes) {
          best = static_cast<int>(c);
          best_votes = votes[c];
        }
      }
      chosen[f] = kernels::Plane{Vec3{nx[best], ny[best], nz[best]}, d[best]};
      changed[f] = best != 0;
    }
  });
  *num_changed = 0;
  for (uint8_t c : changed) *num_changed += c;
  return chosen;
}

// Whether the point at depth along ray lies on the plane (n, d), within tolerance of its depth.
// Branch-free, so that a loop over planes vectorises.
bool OnPlane(float depth, const Vec3& ray, const Vec3& n, float d, float tolerance) {
  const float z = -d / kernels::Dot(n, ray);
  const float off = (depth - z) / depth;
  return std::isgreater(off, -tolerance) && std::isless(off, tolerance);
}

// The image's dominant planes (kernels/DESIGN.md 31): greedily, the vertex tangent plane that
// the most vertices lie on (within 0.5 %), each weighing the square root of a third of its
// triangles' area as in the vote (a vertex that is no corner weighs nothing here), its
// vertices then set aside, while a plane gathers at least kDominantShare of all the weight;
// at most kMaxDominantPlanes. Candidates are at most kDominantCandidates tangent planes taken
// at even steps; the result does not depend on the number of threads.
std::vector<kernels::Plane> DominantPlanes(const kernels::Camera& camera, const std::vector<PlanarPriorVertex>& vertices,
                                           const std::vector<std::array<int, 3>>& faces, int num_threads) {
  constexpr int kMaxDominantPlanes = 6;
  constexpr float kDominantShare = 0.05f;
  constexpr size_t kDominantCandidates = 800;
  const size_t nv = vertices.size();
  const std::vector<float> area = CornerAreas(vertices, faces);
  const std::vector<Vec3> rays = VertexRays(camera, vertices);
  std::vector<float> weight(nv);
  float total = 0.f;
  for (size_t i = 0; i < nv; ++i) {
    weight[i] = std::sqrt(area[i]);
    total += weight[i];
  }
  std::vector<int> with_normal;
  for (size_t i = 0; i < nv; ++i) {
    if (kernels::Norm(vertices[i].normal) > 0.f) with_normal.push_back(static_cast<int>(i));
  }
  // The candidates side by side (normal, offset), so that each vertex is weighed against all
  // of them in one loop the compiler vectorises; each candidate's support still adds up in
  // the vertices' order, whatever the split over threads.
  std::vector<float> nx, ny, nz, d;
  const size_t step = std::max<size_t>(1, (with_normal.size() + kDominantCandidates - 1) / kDominantCandidates);
  for (size_t c = 0; c < with_normal.size(); c += step) {
    const int i = with_normal[c];
    const kernels::Plane plane = FacingPlane(kernels::Normalize(vertices[i].normal), vertices[i].depth * rays[i]);
    nx.push_back(plane.n.x);
    ny.push_back(plane.n.y);
    nz.push_back(plane.n.z);
    d.push_back(plane.d);
  }
  const int nc = static_cast<int>(d.size());
  std::vector<uint8_t> taken(nv, 0);
  std::vector<float> support(nc);
  std::vector<kernels::Plane> dominant;
  while (static_cast<int>(dominant.size()) < kMaxDominantPlanes && nc > 0) {
    std::fill(support.begin(), support.end(), 0.f);
    RunRangeInThreads(nc, num_threads, [&](int begin, int end) {
      for (size_t i = 0; i < nv; ++i) {
        if (taken[i]) continue;
        const Vec3 ray = rays[i];
        const float depth = vertices[i].depth, w = weight[i];
        for (int c = begin; c < end; ++c) {
          support[c] += OnPlane(depth, ray, Vec3{nx[c], ny[c], nz[c]}, d[c], kOnDominantPlane) ? w : 0.f;
        }
      }
    });
    const int best = static_cast<int>(std::max_element(support.begin(), support.end()) - support.begin());
    if (support[best] < kDominantShare * total) break;
    const kernels::Plane plane{Vec3{nx[best], ny[best], nz[best]}, d[best]};
    dominant.push_back(plane);
    for (size_t i = 0; i < nv; ++i) taken[i] |= OnPlane(vertices[i].depth, rays[i], plane.n, plane.d, kOnDominantPlane);
  }
  return dominant;
}

// A triangle's plane parallel to a dominant plane (within 10 degrees) and less than 3 % in
// front of it is that dominant plane, the farthest of those that qualify (kernels/DESIGN.md
// 31): a plain stretch of wall between objects a little in front of it has vertices only on
// the objects, and its triangles would otherwise carry the objects' plane.
void SnapToDominantPlanes(const kernels::Camera& camera, const std::vector<PlanarPriorVertex>& vertices,
                          const std::vector<std::array<int, 3>>& faces, const std::vector<kernels::Plane>& dominant,
                          std::vector<kernels::Plane>* planes) {
  constexpr float kSnapInFront = 0.03f, kMinCos = 0.985f;  // cos 10 degrees
  for (size_t f = 0; f < faces.size(); ++f) {
    const PlanarPriorVertex& a = vertices[faces[f][0]];
    const PlanarPriorVertex& b = vertices[faces[f][1]];
    const PlanarPriorVertex& c = vertices[faces[f][2]];
    const Vec3 ray = kernels::PixelRay(camera, (a.u + b.u + c.u) / 3.f, (a.v + b.v + c.v) / 3.f);
    kernels::Plane& plane = (*planes)[f];
    const float z = kernels::PlaneDepth(plane, ray);
    if (!(z > 0.f)) continue;
    float farthest = 0.f;
    const kernels::Plane* snap = nullptr;
    for (const kernels::Plane& d : dominant) {
      const float zd = kernels::PlaneDepth(d, ray);
      if (!(zd > 0.f) || kernels::Dot(plane.n, d.n) <= kMinCos) continue;
      const float behind = (zd - z) / zd;
      if (behind >= -kOnDominantPlane && behind <= kSnapInFront && zd > farthest) {
        farthest = zd;
        snap = &d;
      }
    }
    if (snap) plane = *snap;
  }
}

// A corner of a bridging triangle as a colour reference for the plain pixels around it
// (BridgingCorners).
struct CornerColour {
  bool usable = false;  // inside the image, in a plain patch
  int plane = -1;       // the dominant plane it lies on (index), -1: none
  float grey = 0.f, chroma0 = 0.f, chroma1 = 0.f;
};

// The bilateral weights' colour difference (kernels/ncc.h), summed in its own order.
float ColourDistance(const kernels::ImageView& guide, size_t i, const CornerColour& corner) {
  const float c0 = guide.chroma ? guide.chroma[2 * i] - corner.chroma0 : 0.f;
  const float c1 = guide.chroma ? guide.chroma[2 * i + 1] - corner.chroma1 : 0.f;
  return std::fabs(guide.data[i] - corner.grey) + std::fabs(c0) + std::fabs(c1);
}

// The corners of a triangle whose corners' depths lie over kBridgingSpan apart (it joins an
// object to the surface behind, kernels/DESIGN.md 31), or nothing for any other triangle. A
// corner in a patch of 5 x 5 px whose grey varies by more than kPlainPatchRange sits on
// texture or on an edge between surfaces, and its colour stands for none of them: not usable.
bool BridgingCorners(const kernels::Camera& camera, const kernels::ImageView& guide,
                     const std::array<const PlanarPriorVertex*, 3>& corners,
                     const std::vector<kernels::Plane>& dominant, std::array<CornerColour, 3>* colours) {
  constexpr float kBridgingSpan = 0.05f, kPlainPatchRange = 6.f;
  constexpr int kPatchRadius = 2;
  const float nearest = std::min({corners[0]->depth, corners[1]->depth, corners[2]->depth});
  const float farthest = std::max({corners[0]->depth, corners[1]->depth, corners[2]->depth});
  if (!(farthest > nearest * (1.f + kBridgingSpan))) return false;
  const int W = guide.width, H = guide.height;
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    const PlanarPriorVertex& x = *corners[k];
    CornerColour& colour = (*colours)[k];
    colour = CornerColour{};
    if (x.u < 0 || x.v < 0 || x.u >= W || x.v >= H) continue;
    float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
    for (int dv = -kPatchRadius; dv <= kPatchRadius; ++dv) {
      for (int du = -kPatchRadius; du <= kPatchRadius; ++du) {
        const size_t j = static_cast<size_t>(std::clamp(x.v + dv, 0, H - 1)) * W + std::clamp(x.u + du, 0, W - 1);
        const float g = guide.data[j];
        lo = std::min(lo, g);
        hi = std::max(hi, g);
      }
    }
    if (hi - lo > kPlainPatchRange) continue;
    const size_t j = static_cast<size_t>(x.v) * W + x.u;
    colour.usable = true;
    colour.grey = guide.data[j];
    if (guide.chroma) {
      colour.chroma0 = guide.chroma[2 * j];
      colour.chroma1 = guide.chroma[2 * j + 1];
    }
    const Vec3 ray = kernels::PixelRay(camera, float(x.u), float(x.v));
    for (size_t p = 0; p < dominant.size() && colour.plane < 0; ++p) {
      if (OnPlane(x.depth, ray, dominant[p].n, dominant[p].d, kOnDominantPlane)) colour.plane = static_cast<int>(p);
    }
    any |= colour.plane >= 0;
  }
  return any;
}

// The dominant plane (index) that pixel i of a bridging triangle takes: that of the usable
// corner on a dominant plane nearest in colour, within max_distance, unless a usable corner
// off that plane comes within kColourMargin of the same distance (two plain surfaces of like
// colour meet there, as a floor and a wall); -1: the pixel keeps the triangle's plane.
int ColourMatchedPlane(const kernels::ImageView& guide, size_t i, const std::array<CornerColour, 3>& corners,
                       float max_distance) {
  constexpr float kColourMargin = 4.f;
  float distance[3];
  float best = max_distance;
  int match = -1;
  for (int k = 0; k < 3; ++k) {
    distance[k] = corners[k].usable ? ColourDistance(guide, i, corners[k]) : 0.f;
    if (corners[k].usable && corners[k].plane >= 0 && distance[k] < best) {
      best = distance[k];
      match = k;
    }
  }
  if (match < 0) return -1;
  for (int k = 0; k < 3; ++k) {
    if (k != match && corners[k].usable && corners[k].plane != corners[match].plane &&
        distance[k] < best + kColourMargin) {
      return -1;
    }
  }
  return corners[match].plane;
}

// Appends the vertices of outside that lie outside the W x H image, within half its size of
// its border, with depth in [depth_min, depth_max]: at most per_cell in each cell of the
// selection grid extended over that margin, first come first kept.
int AddOutsideVertices(int W, int H, float depth_min, float depth_max, const PlanarPriorOptions& options,
                       const std::vector<PlanarPriorVertex>& outside, std::vector<PlanarPriorVertex>* vertices) {
  const int cs = options.cell_size;
  const int margin_x = (W / 2 + cs - 1) / cs, margin_y = (H / 2 + cs - 1) / cs;  // cells
  const int grid_x = (W + cs - 1) / cs + 2 * margin_x, grid_y = (H + cs - 1) / cs + 2 * margin_y;
  std::vector<int> count(static_cast<size_t>(grid_x) * grid_y, 0);
  int added = 0;
  for (const PlanarPriorVertex& v : outside) {
    if (v.u >= 0 && v.v >= 0 && v.u < W && v.v < H) continue;
    if (!(v.depth >= depth_min && v.depth <= depth_max)) continue;
    const int cx = (v.u >= 0 ? v.u / cs : -((-v.u + cs - 1) / cs)) + margin_x;
    const int cy = (v.v >= 0 ? v.v / cs : -((-v.v + cs - 1) / cs)) + margin_y;
    if (cx < 0 || cy < 0 || cx >= grid_x || cy >= grid_y) continue;
    int& c = count[static_cast<size_t>(cy) * grid_x + cx];
    if (c >= options.points_per_cell) continue;
    ++c;
    vertices->push_back(v);
    ++added;
  }
  return added;
}

}  // namespace

std::vector<uint8_t> BentDepthMask(int W, int H, const std::vector<float>& depth, int step, float max_relative) {
  std::vector<uint8_t> bent(static_cast<size_t>(W) * H, 0);
  constexpr int kDirections[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      if (!(depth[i] > 0.f)) continue;
      const float inverse = 1.f / depth[i];
      for (const auto& d : kDirections) {
        const int u0 = u - step * d[0], v0 = v - step * d[1], u1 = u + step * d[0], v1 = v + step * d[1];
        if (u0 < 0 || u1 < 0 || u0 >= W || u1 >= W || v0 < 0 || v1 < 0 || v0 >= H || v1 >= H) continue;
        const float z0 = depth[static_cast<size_t>(v0) * W + u0], z1 = depth[static_cast<size_t>(v1) * W + u1];
        if (!(z0 > 0.f && z1 > 0.f)) continue;
        // Inverse depth is affine in the pixel coordinates on any plane.
        if (std::abs(1.f / z0 + 1.f / z1 - 2.f * inverse) > max_relative * inverse) {
          bent[i] = 1;
          break;
        }
      }
    }
  }
  return bent;
}

std::vector<PlanarPriorVertex> TransferPriorVertices(const kernels::Camera& source,
                                                     const kernels::Camera& reference,
                                                     const std::vector<PlanarPriorVertex>& vertices) {
  // rel maps reference-camera points to the source camera; Rinv, tinv map them back.
  const kernels::RelativePose rel = kernels::ComputeRelativePose(reference, source);
  const Vec3 t{rel.tinv[0], rel.tinv[1], rel.tinv[2]};
  // Pixels far beyond any margin a caller keeps would overflow int.
  const float limit = 8.f * static_cast<float>(std::max(reference.width, reference.height));
  std::vector<PlanarPriorVertex> out;
  out.reserve(vertices.size());
  for (const PlanarPriorVertex& v : vertices) {
    const Vec3 X = kernels::MatVec(rel.Rinv, VertexPoint(source, v)) + t;
    float u, w;
    if (!kernels::ProjectCameraPoint(reference, X, &u, &w)) continue;
    if (!(std::abs(u) < limit && std::abs(w) < limit)) continue;
    PlanarPriorVertex moved{static_cast<int>(std::lround(u)), static_cast<int>(std::lround(w)), X.z};
    if (kernels::Norm(v.normal) > 0.f) moved.normal = kernels::MatVec(rel.Rinv, v.normal);
    out.push_back(moved);
  }
  return out;
}

std::vector<PlanarPriorVertex> SelectPriorVertices(int W, int H, const std::vector<float>& depth,
                                                   const std::vector<float>& photo_cost,
                                                   const std::vector<float>& geo_error,
                                                   const PlanarPriorOptions& options,
                                                   const std::vector<float>* planes,
                                                   const std::vector<uint8_t>* excluded) {
  const bool geometric = options.selection == PlanarPriorOptions::Selection::kGeometric;
  const int per_cell = geometric ? options.points_per_cell : 1;
  const int cs = options.cell_size;
  std::vector<PlanarPriorVertex> vertices;
  std::vector<std::pair<float, int>> candidates;
  for (int cy = 0; cy < H; cy += cs) {
    for (int cx = 0; cx < W; cx += cs) {
      candidates.clear();
      for (int v = cy; v < std::min(cy + cs, H); ++v) {
        for (int u = cx; u < std::min(cx + cs, W); ++u) {
          const int i = v * W + u;
          // A plain window matches nearby wrong planes about as well as the right one (on
          // smooth shading, consistently across views): it anchors no triangle. Nor does a
          // pixel where the depth bends, which may carry a nearer surface's depth.
          if (!(depth[i] > 0.f) || (excluded && (*excluded)[i])) continue;
          if (geometric) {
            // MP-MVS (paper): photometric cost < 0.2 and reprojection error < 1 px.
            if (GeometricVertexCandidate(photo_cost[i], geo_error[i], options))
              candidates.push_back({photo_cost[i] + 0.2f * geo_error[i], i});
          } else if (photo_cost[i] < options.max_cost_photometric) {
            candidates.push_back({photo_cost[i], i});
          }
        }
      }
      const int keep = std::min<int>(per_cell, candidates.size());
      std::partial_sort(candidates.begin(), candidates.begin() + keep, candidates.end());
      for (int k = 0; k < keep; ++k) {
        const int i = candidates[k].second;
        PlanarPriorVertex vertex{i % W, i / W, depth[i]};
        if (planes) vertex.normal = Vec3{(*planes)[4 * i], (*planes)[4 * i + 1], (*planes)[4 * i + 2]};
        vertices.push_back(vertex);
      }
    }
  }
  return vertices;
}

PlanarPriorModel BuildPlanarPrior(const kernels::Camera& camera, const std::vector<float>& depth,
                                  const std::vector<float>& photo_cost,
                                  const std::vector<float>& geo_error, float depth_min,
                                  float depth_max, const PlanarPriorOptions& options,
                                  const std::vector<float>* planes,
                                  const std::vector<uint8_t>* excluded,
                                  const std::vector<PlanarPriorVertex>* outside_vertices) {
  return PlanarPriorFromVertices(
      camera,
      SelectPriorVertices(camera.width, camera.height, depth, photo_cost, geo_error, options, planes, excluded),
      depth_min, depth_max, options, outside_vertices);
}

PlanarPriorModel PlanarPriorFromVertices(const kernels::Camera& camera, std::vector<PlanarPriorVertex> vertices,
                                         float depth_min, float depth_max, const PlanarPriorOptions& options,
                                         const std::vector<PlanarPriorVertex>* outside_vertices,
                                         const kernels::ImageView* guide) {
  const int W = camera.width, H = camera.height;
  PlanarPriorModel model;
  model.plane.assign(4 * static_cast<size_t>(W) * H, 0.f);
  model.label.assign(static_cast<size_t>(W) * H, 0);
  model.vertices = std::move(vertices);
  if (outside_vertices) {
    model.num_outside_vertices =
        AddOutsideVertices(W, H, depth_min, depth_max, options, *outside_vertices, &model.vertices);
  }
  // Without the vote a vertex that may not be a corner would serve no purpose: all are corners.
  if (!options.plane_vote) {
    for (PlanarPriorVertex& vertex : model.vertices) vertex.corner = true;
  }
  if (model.vertices.size() < 3) return model;

  std::vector<std::pair<Kernel::Point_2, int>> points;
  points.reserve(model.vertices.size());
  for (size_t i = 0; i < model.vertices.size(); ++i) {
    if (!model.vertices[i].corner) continue;
    points.push_back({Kernel::Point_2(model.vertices[i].u, model.vertices[i].v), static_cast<int>(i)});
  }
  Delaunay triangulation;
  triangulation.insert(points.begin(), points.end());
  if (triangulation.dimension() < 2) return model;  // collinear corners: no triangle
  std::vector<VoteOnlyVertex> vote_only;
  for (size_t i = 0; i < model.vertices.size(); ++i) {
    const PlanarPriorVertex& w = model.vertices[i];
    if (w.corner) continue;
    const Delaunay::Face_handle face = triangulation.locate(Kernel::Point_2(w.u, w.v));
    if (face == nullptr || triangulation.is_infinite(face)) continue;  // outside every triangle
    VoteOnlyVertex voter{static_cast<int>(i), {}, 0.f};
    for (int k = 0; k < 3; ++k) voter.corners[k] = face->vertex(k)->info();
    voter.third_of_area = ThirdOfArea(model.vertices[voter.corners[0]], model.vertices[voter.corners[1]],
                                      model.vertices[voter.corners[2]]);
    vote_only.push_back(voter);
  }
  model.num_vote_only_vertices = static_cast<int>(vote_only.size());

  // Every triangle's own plane through its three vertices, facing the camera.
  std::vector<std::array<int, 3>> faces;
  std::vector<kernels::Plane> own;
  for (auto face = triangulation.finite_faces_begin(); face != triangulation.finite_faces_end(); ++face) {
    std::array<int, 3> idx;
    Vec3 X[3];
    for (int k = 0; k < 3; ++k) {
      idx[k] = face->vertex(k)->info();
      X[k] = VertexPoint(camera, model.vertices[idx[k]]);
    }
    Vec3 n = kernels::Cross(X[1] - X[0], X[2] - X[0]);
    if (!(kernels::Norm(n) > 0.f)) continue;
    faces.push_back(idx);
    own.push_back(FacingPlane(kernels::Normalize(n), X[0]));
  }
  std::vector<kernels::Plane> chosen =
      options.plane_vote ? VotedPlanes(camera, model.vertices, faces, own, vote_only, options.num_threads,
                                                         &model.num_voted_triangles) : own;
  std::vector<kernels::Plane> dominant;
  if (options.plane_vote) {
    dominant = DominantPlanes(camera, model.vertices, faces, options.num_threads);
    SnapToDominantPlanes(camera, model.vertices, faces, dominant, &chosen);
  }
  // A guide of another size than the camera's is no guide of this image.
  const bool match_colours = options.plane_vote && options.corner_colour_match > 0.f && !dominant.empty() && guide &&
                             guide->width == W && guide->height == H;

  for (size_t f = 0; f < faces.size(); ++f) {
    const std::array<int, 3>& idx = faces[f];
    const kernels::Plane& plane = chosen[f];
    model.triangles.insert(model.triangles.end(), {idx[0], idx[1], idx[2]});

    // Rasterise: pixels whose centre lies inside the triangle (edges inclusive).
    const PlanarPriorVertex& a = model.vertices[idx[0]];
    const PlanarPriorVertex& b = model.vertices[idx[1]];
    const PlanarPriorVertex& c = model.vertices[idx[2]];
    const int umin = std::max(0, std::min({a.u, b.u, c.u}));
    const int umax = std::min(W - 1, std::max({a.u, b.u, c.u}));
    const int vmin = std::max(0, std::min({a.v, b.v, c.v}));
    const int vmax = std::min(H - 1, std::max({a.v, b.v, c.v}));
    const float area = float(b.u - a.u) * (c.v - a.v) - float(b.v - a.v) * (c.u - a.u);
    if (area == 0.f) continue;
    std::array<CornerColour, 3> corners;
    const bool bridging = match_colours && BridgingCorners(camera, *guide, {&a, &b, &c}, dominant, &corners);
    for (int v = vmin; v <= vmax; ++v) {
      for (int u = umin; u <= umax; ++u) {
        const float w0 = (float(b.u - u) * (c.v - v) - float(b.v - v) * (c.u - u)) / area;
        const float w1 = (float(c.u - u) * (a.v - v) - float(c.v - v) * (a.u - u)) / area;
        const float w2 = 1.f - w0 - w1;
        if (w0 < -1e-6f || w1 < -1e-6f || w2 < -1e-6f) continue;
        const size_t i = static_cast<size_t>(v) * W + u;
        // A pixel whose matched plane lies out of range there gets no prior, as any other.
        const int matched = bridging ? ColourMatchedPlane(*guide, i, corners, options.corner_colour_match) : -1;
        const kernels::Plane& pixel_plane = matched >= 0 ? dominant[matched] : plane;
        const float z_prior = kernels::PlaneDepth(pixel_plane, kernels::PixelRay(camera, float(u), float(v)));
        if (!(z_prior >= depth_min && z_prior <= depth_max)) continue;
        model.label[i] = 1;
        model.plane[4 * i + 0] = pixel_plane.n.x;
        model.plane[4 * i + 1] = pixel_plane.n.y;
        model.plane[4 * i + 2] = pixel_plane.n.z;
        model.plane[4 * i + 3] = pixel_plane.d;
      }
    }
  }
  return model;
}

std::vector<float> PriorDepthMap(const PlanarPriorModel& prior, const kernels::Camera& camera) {
  std::vector<float> depth(prior.label.size(), 0.f);
  for (size_t k = 0; k < prior.label.size(); ++k) {
    if (!prior.label[k]) continue;
    const float* p = &prior.plane[4 * k];
    const kernels::Plane plane{{p[0], p[1], p[2]}, p[3]};
    depth[k] = kernels::PlaneDepth(
        plane, kernels::PixelRay(camera, float(k % camera.width), float(k / camera.width)));
  }
  return depth;
}

}  // namespace mpmvs

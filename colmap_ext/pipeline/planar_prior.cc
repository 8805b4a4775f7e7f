#include "colmap_ext/pipeline/planar_prior.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>

#include "kernels/patch_match_pixel.h"

namespace mpmvs {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;

using kernels::Vec3;

}  // namespace

std::vector<PlanarPriorVertex> SelectPriorVertices(int W, int H, const std::vector<float>& depth,
                                                   const std::vector<float>& photo_cost,
                                                   const std::vector<float>& geo_error,
                                                   const PlanarPriorOptions& options,
                                                   const std::vector<float>* planes) {
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
          if (!(depth[i] > 0.f)) continue;
          if (geometric) {
            // MP-MVS (paper): photometric cost < 0.2 and reprojection error < 1 px.
            if (photo_cost[i] < options.max_photo_cost && geo_error[i] < options.max_geom_error)
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
                                  const std::vector<float>* planes) {
  const int W = camera.width, H = camera.height;
  PlanarPriorModel model;
  model.plane.assign(4 * static_cast<size_t>(W) * H, 0.f);
  model.label.assign(static_cast<size_t>(W) * H, 0);
  model.vertices = SelectPriorVertices(W, H, depth, photo_cost, geo_error, options, planes);
  if (model.vertices.size() < 3) return model;

  std::vector<std::pair<Kernel::Point_2, int>> points;
  points.reserve(model.vertices.size());
  for (size_t i = 0; i < model.vertices.size(); ++i) {
    points.push_back({Kernel::Point_2(model.vertices[i].u, model.vertices[i].v), static_cast<int>(i)});
  }
  Delaunay triangulation;
  triangulation.insert(points.begin(), points.end());

  const float min_normal_cos = options.straddle_normal_angle_deg > 0.f
                                   ? std::cos(options.straddle_normal_angle_deg * kernels::kPi / 180.f)
                                   : -2.f;
  for (auto face = triangulation.finite_faces_begin(); face != triangulation.finite_faces_end(); ++face) {
    int idx[3];
    Vec3 X[3];
    for (int k = 0; k < 3; ++k) {
      idx[k] = face->vertex(k)->info();
      const PlanarPriorVertex& pv = model.vertices[idx[k]];
      X[k] = pv.depth * kernels::PixelRay(camera, static_cast<float>(pv.u), static_cast<float>(pv.v));
    }
    Vec3 n = kernels::Cross(X[1] - X[0], X[2] - X[0]);
    if (kernels::Norm(n) <= 0.f) continue;
    n = kernels::Normalize(n);
    if (kernels::Dot(n, X[0]) > 0.f) n = -n;  // face the camera
    Vec3 on_plane = X[0];
    // A triangle whose plane agrees with none of its vertices' own normals spans a depth
    // edge: the area between an object's vertices and the background's is mostly
    // background, so it takes the tangent plane of its farthest vertex (kernels/DESIGN.md 14).
    int agree = 0, known = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 vertex_normal = model.vertices[idx[k]].normal;
      known += kernels::Norm(vertex_normal) > 0.f;
      agree += kernels::Dot(n, vertex_normal) >= min_normal_cos;
    }
    if (known > 0 && agree == 0) {
      int far = 0;
      for (int k = 1; k < 3; ++k) {
        if (model.vertices[idx[k]].depth > model.vertices[idx[far]].depth) far = k;
      }
      const Vec3 far_normal = model.vertices[idx[far]].normal;
      if (!(kernels::Norm(far_normal) > 0.f)) continue;
      n = kernels::Normalize(far_normal);
      if (kernels::Dot(n, X[far]) > 0.f) n = -n;
      on_plane = X[far];
      ++model.num_straddling_triangles;
    }
    const float d = -kernels::Dot(n, on_plane);
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
    const kernels::Plane plane{n, d};
    for (int v = vmin; v <= vmax; ++v) {
      for (int u = umin; u <= umax; ++u) {
        const float w0 = (float(b.u - u) * (c.v - v) - float(b.v - v) * (c.u - u)) / area;
        const float w1 = (float(c.u - u) * (a.v - v) - float(c.v - v) * (a.u - u)) / area;
        const float w2 = 1.f - w0 - w1;
        if (w0 < -1e-6f || w1 < -1e-6f || w2 < -1e-6f) continue;
        const float z_prior = kernels::PlaneDepth(plane, kernels::PixelRay(camera, float(u), float(v)));
        if (!(z_prior >= depth_min && z_prior <= depth_max)) continue;
        const size_t i = static_cast<size_t>(v) * W + u;
        model.label[i] = 1;
        model.plane[4 * i + 0] = n.x;
        model.plane[4 * i + 1] = n.y;
        model.plane[4 * i + 2] = n.z;
        model.plane[4 * i + 3] = d;
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

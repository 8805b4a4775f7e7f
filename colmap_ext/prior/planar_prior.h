#pragma once
// Planar prior model (ACMP, as modified by MP-MVS; docs/algorithm.md §8, §0): reliable pixels
// per grid cell, 2-D Delaunay triangulation (CGAL), one plane per triangle, rasterised into
// a per-pixel prior plane and label.
#include <cstdint>
#include <vector>

#include "kernels/camera.h"

namespace mpmvs::kernels {
struct ImageView;
}  // namespace mpmvs::kernels

namespace mpmvs {

struct PlanarPriorOptions {
  enum class Selection { kPhotometric, kGeometric };
  Selection selection = Selection::kGeometric;
  int cell_size = 5;
  int points_per_cell = 3;           // geometric selection; photometric takes 1 (ACMP)
  float max_photo_cost = 0.2f;       // geometric: m_p <
  float max_geom_error = 1.0f;       // geometric: m_g < (px)
  float max_cost_photometric = 0.1f;  // photometric: cost <
  // Each triangle takes the plane its neighbourhood of vertices votes for (planar_prior.cc,
  // VotedPlanes), or a dominant plane of the image a little behind it (SnapToDominantPlanes),
  // instead of its own plane through its three vertices (false: the paper).
  bool plane_vote = true;
  // With plane_vote and a guide image: in a triangle that bridges an object and the surface
  // behind it (its corners' depths over 5 % apart), a pixel whose colour difference to a
  // corner on a dominant plane of the image is under this takes that plane instead of the
  // triangle's. The difference is the bilateral weights' (grey levels plus the guide's chroma,
  // which chroma_weight scales); only corners in a plain patch count, and a corner off that
  // plane matching within 4 more keeps the triangle's plane (BridgingCorners,
  // ColourMatchedPlane; kernels/DESIGN.md 31). 0: off (the paper).
  float corner_colour_match = 12.f;
  // Geometric selection: vertices of the source views that fall outside the reference image
  // join its triangulation (PlanarPriorFromVertices' outside_vertices), so that a surface whose
  // other edge the reference does not see is spanned from edge to edge.
  bool source_vertices = true;
  // A source vertex's photometric cost must be below this (ACMP's bar, stricter than
  // max_photo_cost): nothing in the reference image can check a point outside it.
  float source_max_photo_cost = 0.1f;
  // Geometric selection from an estimate that followed no prior yet: a pixel where the depth
  // map bends (BentDepthMask over +-kVertexBendStep px) by more than this is no vertex, as a
  // surface in front bleeds its depth onto the background beside it (kernels/DESIGN.md 25).
  // 0: off (the paper). The caller applies it: it marks those pixels in the excluded mask
  // that BuildPlanarPrior and SelectPriorVertices take.
  float max_vertex_bend = 0.01f;
  // Threads for the plane vote (-1: all); the model does not depend on it.
  int num_threads = 1;
};

constexpr int kVertexBendStep = 3;

// The geometric (gp) selection's bar for a pixel with a depth (MP-MVS: m_p < 0.2, m_g < 1 px).
inline bool GeometricVertexCandidate(float photo_cost, float geo_error, const PlanarPriorOptions& options) {
  return photo_cost < options.max_photo_cost && geo_error < options.max_geom_error;
}

struct PlanarPriorVertex {
  int u = 0, v = 0;
  float depth = 0;
  kernels::Vec3 normal{0.f, 0.f, 0.f};  // the pixel's plane normal (0: unknown)
  // false: the vertex votes on the planes of the triangles around it but is no triangle's
  // corner (PlanarPriorFromVertices).
  bool corner = true;
};

struct PlanarPriorModel {
  std::vector<PlanarPriorVertex> vertices;
  std::vector<int> triangles;  // 3 vertex indices per kept triangle
  int num_voted_triangles = 0;  // triangles whose vote chose another plane than their own
  int num_outside_vertices = 0;  // vertices from outside_vertices (they come last)
  int num_vote_only_vertices = 0;  // vertices that vote, inside a triangle, but are no corners
  std::vector<float> plane;    // 4 per pixel (nx, ny, nz, d), reference camera frame
  std::vector<uint8_t> label;  // 1 where a triangle covers the pixel
};

// depth (W*H, 0 = none), photo_cost and geo_error (W*H) describe the reference image's
// current estimate. Pixels whose prior depth falls outside [depth_min, depth_max] get no
// label. excluded (W*H, optional): 1 on pixels that are never vertices (plain windows,
// kernels::PlainWindow; bent depths, BentDepthMask). outside_vertices (optional): vertices
// of other views in this camera (TransferPriorVertices); those outside the image, within
// half its size of its border and inside [depth_min, depth_max], join the selected ones,
// at most points_per_cell per cell. Every selected vertex is a triangle corner; with no guide
// image here, options.corner_colour_match does not act (PlanarPriorFromVertices). The prior
// stage selects (SelectPriorVertices), marks and builds (PlanarPriorFromVertices) in steps;
// this is the one-step form.
PlanarPriorModel BuildPlanarPrior(const kernels::Camera& camera, const std::vector<float>& depth,
                                  const std::vector<float>& photo_cost,
                                  const std::vector<float>& geo_error, float depth_min,
                                  float depth_max, const PlanarPriorOptions& options,
                                  const std::vector<float>* planes = nullptr,
                                  const std::vector<uint8_t>* excluded = nullptr,
                                  const std::vector<PlanarPriorVertex>* outside_vertices = nullptr);

// BuildPlanarPrior's model from vertices already selected (SelectPriorVertices), for callers
// that mark some as no corners between the selection and the build. With options.plane_vote
// a vertex with corner false is no triangle corner but votes on the planes of the triangles
// around the triangle it falls in, weighing the square root of a third of its area; outside
// every triangle it does nothing (kernels/DESIGN.md 29). Without the vote all are corners.
// guide (optional): the reference image (grey, and chroma where present; the camera's size)
// for options.corner_colour_match; without it every pixel takes its triangle's plane.
PlanarPriorModel PlanarPriorFromVertices(const kernels::Camera& camera, std::vector<PlanarPriorVertex> vertices,
                                         float depth_min, float depth_max, const PlanarPriorOptions& options,
                                         const std::vector<PlanarPriorVertex>* outside_vertices = nullptr,
                                         const kernels::ImageView* guide = nullptr);

// Vertices of a source view seen from the reference camera: pixel (rounded) and depth in
// the reference, normal rotated into its frame. Points behind the reference are dropped;
// the others are kept wherever they project, inside the image or not.
std::vector<PlanarPriorVertex> TransferPriorVertices(const kernels::Camera& source,
                                                     const kernels::Camera& reference,
                                                     const std::vector<PlanarPriorVertex>& vertices);

// 1 where the depth map bends at a pixel: along a row, a column or a diagonal, the second
// difference of inverse depth over +-step px exceeds max_relative of its inverse depth (zero
// on any plane: a step or a kink is near). Directions with a neighbour outside the image or
// without depth are not tested.
std::vector<uint8_t> BentDepthMask(int width, int height, const std::vector<float>& depth, int step,
                                   float max_relative);

// The prior planes' depth along each pixel's ray (0 where no triangle covers the pixel).
std::vector<float> PriorDepthMap(const PlanarPriorModel& prior, const kernels::Camera& camera);

// BuildPlanarPrior's selection: per cell_size cell, the best candidates (points_per_cell with
// the geometric selection, else one), never on excluded pixels; planes (optional) gives
// their normals. All are corners (corner true); PlanarPriorFromVertices builds the model.
std::vector<PlanarPriorVertex> SelectPriorVertices(int width, int height,
                                                   const std::vector<float>& depth,
                                                   const std::vector<float>& photo_cost,
                                                   const std::vector<float>& geo_error,
                                                   const PlanarPriorOptions& options,
                                                   const std::vector<float>* planes = nullptr,
                                                   const std::vector<uint8_t>* excluded = nullptr);

}  // namespace mpmvs

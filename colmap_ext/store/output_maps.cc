#include "colmap_ext/store/output_maps.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/store/stage_store.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/thread_range.h"
#include "colmap_ext/visualization/visualization.h"

namespace mpmvs {
namespace {

// COLMAP's consistency graph: per pixel with a depth, the sources of its view_mask (the views
// its view selection used or, after the depth check, those that confirm its depth).
ConsistencyGraph MakeConsistencyGraph(const kernels::PatchMatchProblem& problem,
                                      const kernels::PatchMatchResult& result, const FloatMap& depth_map) {
  ConsistencyGraph graph;
  graph.width = result.width;
  graph.height = result.height;
  for (int v = 0; v < result.height; ++v) {
    for (int u = 0; u < result.width; ++u) {
      const size_t i = static_cast<size_t>(v) * result.width + u;
      const uint32_t mask = result.view_mask.empty() ? 0u : result.view_mask[i];
      if (!(depth_map.data[i] > 0.f) || mask == 0u) continue;
      graph.data.push_back(u);
      graph.data.push_back(v);
      const size_t count_pos = graph.data.size();
      graph.data.push_back(0);
      // Mask bits index the sources the stage ran with, which leave out those without results.
      for (size_t s = 0; s < problem.sources.size(); ++s) {
        if (mask >> s & 1u) {
          graph.data.push_back(static_cast<int>(problem.sources[s].image_id));
          ++graph.data[count_pos];
        }
      }
    }
  }
  return graph;
}

// Colours span the depths of the scene the map shows (its 1 % to 99 % quantiles, as
// `evaluate`'s panels take them of the ground truth), not the whole search range, where a
// scene looks uniform; the search range when the map holds no depth.
void SceneDepthRange(const FloatMap& depth, const ReferenceProblem& problem, double* lo, double* hi) {
  if (!RobustRange(depth.data, 0.01, 0.99, lo, hi) || !(*hi > *lo)) {
    *lo = problem.depth_min;
    *hi = problem.depth_max;
  }
}

void WriteSceneDepthPicture(const std::string& path, const FloatMap& depth, const ReferenceProblem& problem,
                            const std::string& title) {
  double lo = 0, hi = 1;
  SceneDepthRange(depth, problem, &lo, &hi);
  WriteDepthPicture(path, depth, lo, hi, title + " (black: no depth)");
}

// At most one vertex dot per this many pixels, so that the prior stays visible under them.
constexpr int kPixelsPerVertexDot = 400;

std::string PictureBase(const DenseWorkspace& workspace, int view, const std::string& tag) {
  return JoinPaths(workspace.IntermediateDir(), "pictures/" + workspace.views[view].name + "." + tag);
}

}  // namespace

void WriteFinalMaps(WorkspaceIo* io, const StageStore& store, const DenseWorkspace& workspace,
                    const ReferenceProblem& problem,
                    const kernels::PatchMatchProblem& pm_problem, const kernels::PatchMatchResult& result,
                    const std::string& type, bool write_consistency_graph, bool write_pictures) {
  std::vector<float> depth, normal;
  kernels::ExtractDepthNormalMaps(pm_problem, result, &depth, &normal);
  FloatMap depth_map(result.width, result.height, 1), normal_map(result.width, result.height, 3);
  depth_map.data = std::move(depth);
  normal_map.data = std::move(normal);
  const auto write_maps = [&] {
    store.RemoveMapsRecord(problem.ref, type);
    io->WriteNormalMap(workspace.NormalMapPath(problem.ref, type), normal_map);
    io->WriteDepthMap(workspace.DepthMapPath(problem.ref, type), depth_map, problem.depth_min, problem.depth_max);
    if (write_consistency_graph) {
      io->WriteConsistencyGraph(workspace.ConsistencyGraphPath(problem.ref, type),
                                MakeConsistencyGraph(pm_problem, result, depth_map));
    }
    store.WriteMapsRecord(problem.ref, type);
  };
  if (!write_pictures) {
    write_maps();
    return;
  }
  // The depth picture (drawing and zlib) on a second thread while the maps and the normal
  // picture are written: in the last stage no kernel runs beside them, and on a two-view
  // pair the pictures were a third of the run's serial time. Neither writes what the other
  // reads.
  const std::string& name = workspace.views[problem.ref].name;
  const std::string base = PictureBase(workspace, problem.ref, type);
  RunBeside([&] { WriteSceneDepthPicture(base + ".depth.png", depth_map, problem, name + " " + type + " depth"); },
            [&] {
              write_maps();
              WriteNormalPicture(base + ".normal.png", normal_map,
                                 name + " " + type + " normals (RGB = x, -y, -z) black: none");
            });
}

void WriteStagePictures(const DenseWorkspace& workspace, const ReferenceProblem& problem,
                        const kernels::Camera& camera, const std::string& stage,
                        const kernels::PatchMatchResult& result, const PlanarPriorModel* prior) {
  const std::string& name = workspace.views[problem.ref].name;
  const std::string base = PictureBase(workspace, problem.ref, stage);
  FloatMap depth(result.width, result.height, 1);
  depth.data = ResultDepth(result, camera, problem.depth_min, problem.depth_max);
  WriteSceneDepthPicture(base + ".depth.png", depth, problem, name + " stage " + stage);
  if (prior) {
    FloatMap prior_depth(result.width, result.height, 1);
    prior_depth.data = PriorDepthMap(*prior, camera);
    WriteFloatMap(base + ".prior_model.bin", prior_depth);
    double lo = 0, hi = 1;
    SceneDepthRange(depth, problem, &lo, &hi);  // the stage's scale, to compare the two
    const size_t max_dots = std::max<size_t>(1, static_cast<size_t>(result.width) * result.height / kPixelsPerVertexDot);
    const size_t stride = (prior->vertices.size() + max_dots - 1) / max_dots;
    RgbImage picture = DepthPicture(
        prior_depth, lo, hi,
        name + " planar prior (black: none), white: " +
            (stride > 1 ? "1 in " + std::to_string(stride) + " vertices" : std::string("its vertices")));
    // The picture has a title band above the map: find the map's top-left by its size.
    const int top = picture.height - result.height;
    for (size_t k = 0; k < prior->vertices.size(); k += std::max<size_t>(1, stride)) {
      const PlanarPriorVertex& vertex = prior->vertices[k];
      // Source views' vertices may lie outside the image, and the picture's title band.
      if (vertex.u < 0 || vertex.v < 0 || vertex.u >= result.width || vertex.v >= result.height) continue;
      FillRect(&picture, vertex.u, top + vertex.v, 1, 1, RgbColor{255, 255, 255});
    }
    WriteRgbPng(base + ".prior_model.png", picture);
  }
}

}  // namespace mpmvs

#include "colmap_ext/store/output_maps.h"

#include <utility>
#include <vector>

#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/store/stage_store.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/visualization/visualization.h"

namespace mpmvs {
namespace {

// COLMAP's consistency graph: per pixel with a depth, the sources its view selection used.
ConsistencyGraph MakeConsistencyGraph(const ReferenceProblem& problem, const kernels::PatchMatchResult& result,
                                      const FloatMap& depth_map) {
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
      for (size_t s = 0; s < problem.src.size(); ++s) {
        if (mask >> s & 1u) {
          graph.data.push_back(problem.src[s]);
          ++graph.data[count_pos];
        }
      }
    }
  }
  return graph;
}

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
  store.RemoveMapsRecord(problem.ref, type);
  io->WriteNormalMap(workspace.NormalMapPath(problem.ref, type), normal_map);
  io->WriteDepthMap(workspace.DepthMapPath(problem.ref, type), depth_map, problem.depth_min, problem.depth_max);
  if (write_consistency_graph) {
    io->WriteConsistencyGraph(workspace.ConsistencyGraphPath(problem.ref, type),
                              MakeConsistencyGraph(problem, result, depth_map));
  }
  store.WriteMapsRecord(problem.ref, type);
  if (write_pictures) {
    const std::string& name = workspace.views[problem.ref].name;
    const std::string base = PictureBase(workspace, problem.ref, type);
    WriteDepthPicture(base + ".depth.png", depth_map, problem.depth_min, problem.depth_max,
                      name + " " + type + " depth");
    WriteNormalPicture(base + ".normal.png", normal_map, name + " " + type + " normals");
  }
}

void WriteStagePictures(const DenseWorkspace& workspace, const ReferenceProblem& problem,
                        const kernels::Camera& camera, const std::string& stage,
                        const kernels::PatchMatchResult& result, const PlanarPriorModel* prior) {
  const std::string& name = workspace.views[problem.ref].name;
  const std::string base = PictureBase(workspace, problem.ref, stage);
  FloatMap depth(result.width, result.height, 1);
  depth.data = ResultDepth(result, camera, problem.depth_min, problem.depth_max);
  WriteDepthPicture(base + ".depth.png", depth, problem.depth_min, problem.depth_max, name + " stage " + stage);
  if (prior) {
    FloatMap prior_depth(result.width, result.height, 1);
    prior_depth.data = PriorDepthMap(*prior, camera);
    WriteFloatMap(base + ".prior_model.bin", prior_depth);
    RgbImage picture = DepthPicture(prior_depth, problem.depth_min, problem.depth_max,
                                    name + " planar prior and vertices");
    // The picture has a title band above the map: find the map's top-left by its size.
    const int top = picture.height - result.height;
    for (const PlanarPriorVertex& vertex : prior->vertices) {
      // Source views' vertices may lie outside the image, and the picture's title band.
      if (vertex.u < 0 || vertex.v < 0 || vertex.u >= result.width || vertex.v >= result.height) continue;
      FillRect(&picture, vertex.u, top + vertex.v, 1, 1, RgbColor{255, 255, 255});
    }
    WriteRgbPng(base + ".prior_model.png", picture);
  }
}

}  // namespace mpmvs

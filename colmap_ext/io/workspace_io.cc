#include "colmap_ext/io/workspace_io.h"

namespace mpmvs {

std::string MpMvsWorkspaceIo::Name() const { return "mp-mvs"; }

DenseWorkspace MpMvsWorkspaceIo::Load(const std::string& path, int max_image_size) {
  return LoadDenseWorkspace(path, max_image_size);
}

GrayImage MpMvsWorkspaceIo::ReadGray(const DenseWorkspace& workspace, int view) {
  return workspace.ReadGray(view);
}

void MpMvsWorkspaceIo::WriteDepthMap(const std::string& path, const FloatMap& depth, float,
                                     float) {
  WriteFloatMap(path, depth);
}

void MpMvsWorkspaceIo::WriteNormalMap(const std::string& path, const FloatMap& normal) {
  WriteFloatMap(path, normal);
}

void MpMvsWorkspaceIo::WriteConsistencyGraph(const std::string& path,
                                             const ConsistencyGraph& graph) {
  mpmvs::WriteConsistencyGraph(path, graph);
}

}  // namespace mpmvs

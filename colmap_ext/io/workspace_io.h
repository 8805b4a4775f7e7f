#pragma once
// How mp_patch_match_stereo reads a COLMAP dense workspace and writes its maps. The stage
// loop (mp_patch_match_stereo.cc) is written once against this interface; two front ends
// plug in their own I/O:
//   - MpMvsWorkspaceIo (here): mp-mvs's own sparse-model reader, FreeImage and map writer;
//     used by `colmap-mp mp_patch_match_stereo`. Never needs COLMAP's libraries.
//   - ColmapWorkspaceIo (colmap_ext/native): COLMAP's mvs::Workspace/Model, Bitmap and
//     DepthMap/NormalMap/ConsistencyGraph writers; used by `colmap mp_patch_match_stereo`.
// Everything computed from the loaded data (depth ranges, __auto__ source selection,
// patch-match.cfg, PatchMatch, planar prior, output filter) is shared code, so both front
// ends give the same maps from the same cameras, points and grey images.
#include <string>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"

namespace mpmvs {

class WorkspaceIo {
 public:
  virtual ~WorkspaceIo() = default;

  // Short description for the log ("mp-mvs", "COLMAP 4.0.4 mvs::Workspace").
  virtual std::string Name() const = 0;

  // Loads the workspace at path: views in model image index order with cameras after
  // max_image_size (<= 0: none) and depth ranges (ComputeDepthRanges), the sparse points
  // for __auto__ source selection. Throws Error naming the file on bad input.
  virtual DenseWorkspace Load(const std::string& path, int max_image_size) = 0;

  // Grey image (values 0..255) of a view at the view's size. Throws Error naming the file.
  virtual GrayImage ReadGray(const DenseWorkspace& workspace, int view) = 0;
  // Colour image of a view at the view's size, for the chroma guide of the NCC weights
  // only (matching stays on ReadGray's grey). Both front ends read it with mp-mvs's reader.
  virtual RgbImage ReadRgb(const DenseWorkspace& workspace, int view) { return workspace.ReadRgb(view); }

  // COLMAP's depth / normal map and consistency graph files. Each write is atomic: a crash
  // never leaves a half-written file under path.
  virtual void WriteDepthMap(const std::string& path, const FloatMap& depth, float depth_min,
                             float depth_max) = 0;
  virtual void WriteNormalMap(const std::string& path, const FloatMap& normal) = 0;
  virtual void WriteConsistencyGraph(const std::string& path, const ConsistencyGraph& graph) = 0;
};

// mp-mvs's own I/O (LoadDenseWorkspace, DenseWorkspace::ReadGray, WriteFloatMap,
// WriteConsistencyGraph).
class MpMvsWorkspaceIo : public WorkspaceIo {
 public:
  std::string Name() const override;
  DenseWorkspace Load(const std::string& path, int max_image_size) override;
  GrayImage ReadGray(const DenseWorkspace& workspace, int view) override;
  void WriteDepthMap(const std::string& path, const FloatMap& depth, float depth_min,
                     float depth_max) override;
  void WriteNormalMap(const std::string& path, const FloatMap& normal) override;
  void WriteConsistencyGraph(const std::string& path, const ConsistencyGraph& graph) override;
};

}  // namespace mpmvs

#pragma once
// What the stages hand each other and share, like COLMAP's CachedWorkspace: every stage's
// result per image in stereo/mpmvs/NAME.STAGE.state.bin (the only way a stage reads another
// stage's work), and the grey images, colour guides and source depth maps that several
// reference images use, in LRU caches bounded by --PatchMatchStereo.cache_size (a third each).
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/pipeline/run_plan.h"
#include "colmap_ext/util/lru_cache.h"
#include "kernels/patch_match.h"

namespace mpmvs {

// Depth of each pixel's plane (0 where invalid or outside [depth_min, depth_max]).
std::vector<float> ResultDepth(const kernels::PatchMatchResult& result, const kernels::Camera& camera,
                               float depth_min, float depth_max);

class StageStore {
 public:
  // workspace, io and plan must outlive the store. depth_ranges: (min, max) of every view
  // that runs; a source outside it has no stage results.
  StageStore(const DenseWorkspace& workspace, WorkspaceIo* io, const RunPlan& plan,
             std::map<int, std::pair<float, float>> depth_ranges);

  std::string StatePath(int view, const std::string& stage) const;
  // Whether the stage's result of the view can be read (it ran and the view runs).
  bool HasState(int view, const std::string& stage) const;
  // Throws Error naming the file when it is damaged or of another size than the view.
  kernels::PatchMatchResult ReadState(int view, const std::string& stage) const;
  void WriteState(int view, const std::string& stage, const kernels::PatchMatchResult& result) const;
  // Whether the final COLMAP maps of this type (and the consistency graph if asked) exist.
  bool FinalOutputsExist(int view, const std::string& type) const;

  std::shared_ptr<const GrayImage> Image(int view) { return images_.Get(view); }
  // Empty for a grey picture: nothing to read or upload.
  std::shared_ptr<const std::vector<float>> ChromaGuide(int view) { return chroma_guides_.Get(view); }
  // The depth map of stage_index's result of a view, for the geometric term of its neighbours.
  std::shared_ptr<const std::vector<float>> SourceDepth(int stage_index, int view) {
    return depths_.Get({stage_index, view});
  }

 private:
  std::vector<float> ReadChromaGuide(int view) const;

  const DenseWorkspace& workspace_;
  WorkspaceIo* io_;
  const RunPlan& plan_;
  std::map<int, std::pair<float, float>> depth_ranges_;
  LruCache<int, GrayImage> images_;
  LruCache<int, std::vector<float>> chroma_guides_;
  LruCache<std::pair<int, int>, std::vector<float>> depths_;
};

}  // namespace mpmvs

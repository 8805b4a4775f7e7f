#include "colmap_ext/pipeline/stage_store.h"

#include <algorithm>

#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/pipeline/chroma_guide.h"
#include "colmap_ext/pipeline/kernel_camera.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"

namespace mpmvs {
namespace {

// Channels of a stage result file: plane (4), cost, photometric cost, geometric error.
constexpr int kStateChannels = 7;

FloatMap ResultToState(const kernels::PatchMatchResult& r) {
  FloatMap state(r.width, r.height, kStateChannels);
  const size_t n = static_cast<size_t>(r.width) * r.height;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 4; ++c) state.data[c * n + i] = r.plane[4 * i + c];
    state.data[4 * n + i] = r.cost[i];
    state.data[5 * n + i] = r.photo_cost[i];
    state.data[6 * n + i] = r.geo_error[i];
  }
  return state;
}

kernels::PatchMatchResult StateToResult(const FloatMap& state) {
  kernels::PatchMatchResult r;
  const size_t n = static_cast<size_t>(state.width) * state.height;
  r.width = state.width;
  r.height = state.height;
  r.plane.resize(4 * n);
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 4; ++c) r.plane[4 * i + c] = state.data[c * n + i];
  }
  r.cost.assign(state.data.begin() + 4 * n, state.data.begin() + 5 * n);
  r.photo_cost.assign(state.data.begin() + 5 * n, state.data.begin() + 6 * n);
  r.geo_error.assign(state.data.begin() + 6 * n, state.data.begin() + 7 * n);
  r.view_mask.assign(n, 0u);
  return r;
}

size_t CacheBytes(const std::vector<float>& values) { return values.size() * sizeof(float); }

}  // namespace

std::vector<float> ResultDepth(const kernels::PatchMatchResult& result, const kernels::Camera& camera,
                               float depth_min, float depth_max) {
  const int W = result.width, H = result.height;
  std::vector<float> depth(static_cast<size_t>(W) * H, 0.f);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      if (!(result.photo_cost[i] < kernels::kInvalidCost)) continue;
      const float* p = &result.plane[4 * i];
      const kernels::Plane plane{{p[0], p[1], p[2]}, p[3]};
      const float z = kernels::PlaneDepth(plane, kernels::PixelRay(camera, float(u), float(v)));
      if (z >= depth_min && z <= depth_max) depth[i] = z;
    }
  }
  return depth;
}

StageStore::StageStore(const DenseWorkspace& workspace, WorkspaceIo* io, const RunPlan& plan,
                       std::map<int, std::pair<float, float>> depth_ranges)
    : workspace_(workspace),
      io_(io),
      plan_(plan),
      depth_ranges_(std::move(depth_ranges)),
      images_(plan.cache_bytes / 3, [this](const int& view) { return io_->ReadGray(workspace_, view); },
              [](const GrayImage& img) { return CacheBytes(img.data); }),
      chroma_guides_(plan.cache_bytes / 3, [this](const int& view) { return ReadChromaGuide(view); },
                     CacheBytes),
      depths_(plan.cache_bytes / 3,
              [this](const std::pair<int, int>& key) {
                const int view = key.second;
                const std::pair<float, float> range = depth_ranges_.at(view);
                return ResultDepth(ReadState(view, plan_.pipeline.stages[key.first].name),
                                   ToKernelCamera(workspace_.views[view]), range.first, range.second);
              },
              CacheBytes) {}

std::string StageStore::StatePath(int view, const std::string& stage) const {
  return JoinPaths(workspace_.IntermediateDir(), workspace_.views[view].name + "." + stage + ".state.bin");
}

bool StageStore::HasState(int view, const std::string& stage) const {
  return depth_ranges_.count(view) && FileExists(StatePath(view, stage));
}

kernels::PatchMatchResult StageStore::ReadState(int view, const std::string& stage) const {
  const std::string path = StatePath(view, stage);
  const FloatMap state = ReadFloatMap(path, kStateChannels);
  const DenseView& v = workspace_.views[view];
  if (state.width != v.width || state.height != v.height) {
    ThrowFileError(path, "size differs from the image; delete stereo/mpmvs to start over");
  }
  return StateToResult(state);
}

void StageStore::WriteState(int view, const std::string& stage, const kernels::PatchMatchResult& result) const {
  WriteFloatMap(StatePath(view, stage), ResultToState(result));
}

bool StageStore::FinalOutputsExist(int view, const std::string& type) const {
  return FileExists(workspace_.DepthMapPath(view, type)) && FileExists(workspace_.NormalMapPath(view, type)) &&
         (!plan_.write_consistency_graph || FileExists(workspace_.ConsistencyGraphPath(view, type)));
}

std::vector<float> StageStore::ReadChromaGuide(int view) const {
  const RgbImage rgb = io_->ReadRgb(workspace_, view);
  const DenseView& v = workspace_.views[view];
  if (rgb.width != v.width || rgb.height != v.height) {
    throw Error(v.image_path + ": colour image is " + std::to_string(rgb.width) + "x" +
                std::to_string(rgb.height) + " but the view is " + std::to_string(v.width) + "x" +
                std::to_string(v.height));
  }
  std::vector<float> guide = MakeChromaGuide(rgb, plan_.chroma_weight);
  if (std::none_of(guide.begin(), guide.end(), [](float c) { return c != 0.f; })) guide.clear();
  return guide;
}

}  // namespace mpmvs

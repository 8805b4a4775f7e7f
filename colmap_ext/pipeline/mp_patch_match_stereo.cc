#include "colmap_ext/pipeline/mp_patch_match_stereo.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/pipeline/chroma_guide.h"
#include "colmap_ext/pipeline/planar_prior.h"
#include "colmap_ext/pipeline/stage_plan.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/lru_cache.h"
#include "colmap_ext/visualization/visualization.h"
#include "kernels/cuda_session.h"

namespace mpmvs {
namespace {

using kernels::Camera;

// Channels of a stage result file in stereo/mpmvs: plane (4), cost, photometric cost,
// geometric error.
constexpr int kStateChannels = 7;

struct Problem {
  int ref = -1;
  std::vector<int> src;
  float depth_min = 0, depth_max = 0;
};

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

void StateToResult(const FloatMap& state, kernels::PatchMatchResult* r) {
  const size_t n = static_cast<size_t>(state.width) * state.height;
  r->width = state.width;
  r->height = state.height;
  r->plane.resize(4 * n);
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 4; ++c) r->plane[4 * i + c] = state.data[c * n + i];
  }
  r->cost.assign(state.data.begin() + 4 * n, state.data.begin() + 5 * n);
  r->photo_cost.assign(state.data.begin() + 5 * n, state.data.begin() + 6 * n);
  r->geo_error.assign(state.data.begin() + 6 * n, state.data.begin() + 7 * n);
  r->view_mask.assign(n, 0u);
}

// Depth of each pixel's plane (0 where invalid), for source depth maps and the prior.
std::vector<float> StateDepth(const FloatMap& state, const Camera& camera, float depth_min,
                              float depth_max) {
  const int W = state.width, H = state.height;
  const size_t n = static_cast<size_t>(W) * H;
  std::vector<float> depth(n, 0.f);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      if (!(state.data[5 * n + i] < kernels::kInvalidCost)) continue;
      const kernels::Plane plane{{state.data[i], state.data[n + i], state.data[2 * n + i]},
                                 state.data[3 * n + i]};
      const float z = kernels::PlaneDepth(plane, kernels::PixelRay(camera, float(u), float(v)));
      if (z >= depth_min && z <= depth_max) depth[i] = z;
    }
  }
  return depth;
}

// Runs the problems of the stages on the CPU or in one CUDA session kept for the whole run
// (device cache of images and depth maps, uploads of the next reference image while the
// current one runs: kernels/cuda_session.h).
class Backend {
 public:
  Backend(const PatchMatchStereoOptions& options, bool cpu_look_ahead)
      : cpu_look_ahead_(cpu_look_ahead) {
    std::string why;
    int index = -1;
    std::stringstream ss(options.gpu_index);
    std::string first;
    std::getline(ss, first, ',');
    index = std::stoi(first);
    const int device = index < 0 ? 0 : index;
    if (kernels::CudaDeviceAvailable(device, &why)) {
      kernels::CudaSessionOptions session;
      session.gpu_index = device;
      session.cache_size_bytes = static_cast<size_t>(options.cache_size * 1024.0 * 1024.0 * 1024.0);
      cuda_ = std::make_unique<kernels::CudaSession>(session);
      name_ = "CUDA device " + std::to_string(device);
      LogInfo("CUDA device cache budget: " + std::to_string(cuda_->CacheBudgetBytes() >> 20) +
              " MB (--PatchMatchStereo.cache_size, at most half the free device memory)");
    } else {
      const int threads = options.num_threads > 0 ? options.num_threads
                                                  : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
      name_ = "CPU (" + std::to_string(threads) + " threads)";
      LogInfo("No usable CUDA device (" + why + "): using the CPU backend, " +
              std::to_string(threads) + " threads");
    }
  }
  // next: the following reference image of the stage, assembled on demand. The CUDA session
  // calls it while this problem's kernels run; the CPU backend does not call it (the
  // controller then assembles that image after this one, as always), unless cpu_look_ahead.
  void Run(const kernels::PatchMatchProblem& problem, const kernels::PatchMatchSchedule& schedule,
           kernels::PatchMatchResult* result, const kernels::NextProblemCallback& next) {
    if (cuda_) {
      cuda_->Run(problem, schedule, result, next);
    } else {
      if (cpu_look_ahead_ && next) next();
      kernels::RunPatchMatchCpu(problem, schedule, result);
    }
  }
  const std::string& Name() const { return name_; }
  void LogCacheStats() const {
    if (!cuda_) return;
    const kernels::DeviceCacheStats s = cuda_->CacheStats();
    LogInfo("CUDA device cache: " + std::to_string(s.misses) + " images/depth maps uploaded, " +
            std::to_string(s.hits) + " found on the device, " + std::to_string(s.evictions) +
            " evicted, peak " + std::to_string(s.peak_bytes >> 20) + " MB of " +
            std::to_string(cuda_->CacheBudgetBytes() >> 20) + " MB; " +
            std::to_string(s.uploaded_bytes >> 20) + " MB uploaded in all");
    if (s.over_budget_problems > 0) {
      LogWarning(std::to_string(s.over_budget_problems) +
                 " reference images needed more device memory for their images and depth maps "
                 "than the cache budget and ran over it; raise --PatchMatchStereo.cache_size");
    }
  }

 private:
  bool cpu_look_ahead_ = false;
  std::unique_ptr<kernels::CudaSession> cuda_;
  std::string name_;
};

// One reference image of a stage, ready to compute (or to resume / skip). Owns the data
// pm's pointers refer to.
struct StageReference {
  enum class Action { kFinalMapsExist, kResume, kNoSources, kCompute };
  Action action = Action::kCompute;
  const Problem* problem = nullptr;
  bool filter_here = false;
  kernels::PatchMatchProblem pm;
  std::vector<std::shared_ptr<const GrayImage>> images;
  std::shared_ptr<const std::vector<float>> chroma;  // pm.ref_image.chroma
  std::vector<std::shared_ptr<const std::vector<float>>> depths;
  kernels::PatchMatchResult input;  // the input stage's planes and costs (pm.init_*)
  PlanarPriorModel prior;           // pm.prior_*
};

class Controller {
 public:
  Controller(const MpPatchMatchRun& run, WorkspaceIo* io) : run_(run), io_(io) {}

  MpPatchMatchSummary Run();

 private:
  std::string StatePath(int view, const std::string& stage) const {
    return JoinPaths(workspace_.IntermediateDir(), workspace_.views[view].name + "." + stage + ".state.bin");
  }
  bool FinalOutputsExist(int view, const std::string& type) const {
    return FileExists(workspace_.DepthMapPath(view, type)) && FileExists(workspace_.NormalMapPath(view, type)) &&
           (!run_.colmap_options.write_consistency_graph ||
            FileExists(workspace_.ConsistencyGraphPath(view, type)));
  }
  void LoadProblems();
  // Loads and assembles reference image p of a stage (images, source depth maps, initial
  // state, planar prior); decides whether it is computed, resumed or skipped.
  std::unique_ptr<StageReference> PrepareReference(int stage_index, const Problem& p);
  // The chroma guide of a view at its working size; empty for a grey picture (nothing to
  // read or upload).
  std::vector<float> ReadChromaGuide(int view) const;
  void RunStage(int stage_index, MpPatchMatchSummary* summary);
  void WriteFinal(const Problem& problem, const kernels::PatchMatchProblem& pm_problem,
                  const kernels::PatchMatchResult& result, const std::string& type);

  MpPatchMatchRun run_;
  WorkspaceIo* io_;
  DenseWorkspace workspace_;
  PipelinePlan plan_;
  std::vector<Problem> problems_;
  std::map<int, float> view_depth_min_, view_depth_max_;
  std::unique_ptr<Backend> backend_;
  std::unique_ptr<LruCache<int, GrayImage>> images_;
  std::unique_ptr<LruCache<int, std::vector<float>>> chroma_guides_;  // empty: a grey picture
  std::unique_ptr<LruCache<std::pair<int, int>, std::vector<float>>> depths_;
};

void Controller::LoadProblems() {
  const std::string cfg = run_.config_path.empty()
                              ? JoinPaths(workspace_.path, "stereo/patch-match.cfg")
                              : run_.config_path;
  if (!FileExists(cfg)) ThrowFileError(cfg, "patch-match configuration not found");
  const std::vector<StereoProblem> specs =
      ReadPatchMatchConfig(cfg, workspace_, run_.colmap_options.min_triangulation_angle);
  for (const StereoProblem& spec : specs) {
    Problem p;
    p.ref = spec.ref;
    p.src = spec.src;
    if (static_cast<int>(p.src.size()) > run_.options.max_source_images) {
      p.src.resize(run_.options.max_source_images);
    }
    const DenseView& view = workspace_.views[p.ref];
    if (run_.colmap_options.depth_min > 0) {
      p.depth_min = static_cast<float>(run_.colmap_options.depth_min);
      p.depth_max = static_cast<float>(run_.colmap_options.depth_max);
    } else {
      p.depth_min = static_cast<float>(view.depth_min);
      p.depth_max = static_cast<float>(view.depth_max);
    }
    problems_.push_back(p);
  }
}

MpPatchMatchSummary Controller::Run() {
  const auto start = std::chrono::steady_clock::now();
  MpPatchMatchSummary summary;
  std::string error;
  if (!run_.colmap_options.Check(&error) || !run_.options.Check(&error)) throw Error(error);
  if (run_.workspace_format != "COLMAP") {
    throw Error("--workspace_format " + run_.workspace_format +
                " is not supported by mp-mvs; use a COLMAP workspace (image_undistorter --output_type COLMAP)");
  }
  LogHeading("mp_patch_match_stereo: loading workspace " + run_.workspace_path);
  workspace_ = io_->Load(run_.workspace_path, run_.colmap_options.max_image_size);
  LoadProblems();
  plan_ = MakePipelinePlan(run_.colmap_options, run_.options);
  if (!run_.colmap_options.geom_consistency && run_.options.PriorMode() == PlanarPriorMode::kGeometric) {
    LogWarning("--MPMVS.planar_prior geometric needs geometric consistency; with "
               "--PatchMatchStereo.geom_consistency 0 only the photometric stage runs");
  }

  // References that cannot run: warn and count, like COLMAP.
  std::vector<Problem> runnable;
  for (const Problem& p : problems_) {
    const std::string& name = workspace_.views[p.ref].name;
    if (p.src.empty()) {
      LogWarning("skipping " + name + ": no source images (patch-match.cfg / shared sparse points)");
      ++summary.num_skipped_no_sources;
    } else if (!(p.depth_min > 0 && p.depth_max > p.depth_min)) {
      LogWarning("skipping " + name +
                 ": it sees no sparse points, so its depth range is unknown; set "
                 "--PatchMatchStereo.depth_min and --PatchMatchStereo.depth_max");
      ++summary.num_skipped_no_depth_range;
    } else {
      runnable.push_back(p);
      view_depth_min_[p.ref] = p.depth_min;
      view_depth_max_[p.ref] = p.depth_max;
    }
  }
  problems_ = runnable;
  summary.num_references = static_cast<int>(problems_.size()) + summary.num_skipped_no_sources +
                           summary.num_skipped_no_depth_range;

  const std::string final_type = plan_.geometric_output >= 0 ? "geometric" : "photometric";
  bool all_done = !run_.options.overwrite;
  for (const Problem& p : problems_) {
    if (!FinalOutputsExist(p.ref, final_type) || !FinalOutputsExist(p.ref, "photometric")) all_done = false;
  }
  if (all_done) {
    summary.num_already_done = static_cast<int>(problems_.size());
    LogInfo("All " + std::to_string(problems_.size()) + " depth maps exist already (" + final_type +
            "); nothing to do. Use --MPMVS.overwrite 1 to recompute.");
    summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  }
  for (const Problem& p : problems_) {
    if (FinalOutputsExist(p.ref, final_type) && !run_.options.overwrite) ++summary.num_already_done;
  }

  backend_ = std::make_unique<Backend>(run_.colmap_options, run_.cpu_look_ahead);
  summary.backend = backend_->Name();
  const size_t cache_bytes = static_cast<size_t>(run_.colmap_options.cache_size * 1024.0 * 1024.0 * 1024.0);
  // Budget: a third each for grey images, chroma guides (reference images, every stage)
  // and source depth maps.
  images_ = std::make_unique<LruCache<int, GrayImage>>(
      cache_bytes / 3, [this](const int& view) { return io_->ReadGray(workspace_, view); },
      [](const GrayImage& img) { return img.data.size() * sizeof(float); });
  chroma_guides_ = std::make_unique<LruCache<int, std::vector<float>>>(
      cache_bytes / 3, [this](const int& view) { return ReadChromaGuide(view); },
      [](const std::vector<float>& g) { return g.size() * sizeof(float); });
  depths_ = std::make_unique<LruCache<std::pair<int, int>, std::vector<float>>>(
      cache_bytes / 3,
      [this](const std::pair<int, int>& key) {
        const FloatMap state = ReadFloatMap(StatePath(key.second, plan_.stages[key.first].name), kStateChannels);
        return StateDepth(state, ToKernelCamera(workspace_.views[key.second]), view_depth_min_[key.second],
                          view_depth_max_[key.second]);
      },
      [](const std::vector<float>& d) { return d.size() * sizeof(float); });

  CreateDirectories(workspace_.IntermediateDir());
  for (const Problem& p : problems_) {
    const std::string& name = workspace_.views[p.ref].name;
    for (const std::string& dir : {workspace_.DepthMapPath(p.ref, "x"), workspace_.NormalMapPath(p.ref, "x"),
                                   StatePath(p.ref, "x")}) {
      CreateDirectories(ParentPath(dir));
    }
    if (run_.options.write_pictures) {
      CreateDirectories(ParentPath(JoinPaths(workspace_.IntermediateDir(), "pictures/" + name)));
    }
  }
  LogInfo("Backend: " + backend_->Name() + "; " + std::to_string(problems_.size()) +
          " reference images; stages: " + [&] {
            std::string s;
            for (const StagePlan& st : plan_.stages) s += (s.empty() ? "" : " -> ") + st.name;
            return s;
          }());

  for (size_t s = 0; s < plan_.stages.size(); ++s) RunStage(static_cast<int>(s), &summary);
  backend_->LogCacheStats();

  summary.num_written = static_cast<int>(problems_.size()) - summary.num_already_done;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

void Controller::WriteFinal(const Problem& problem, const kernels::PatchMatchProblem& pm_problem,
                            const kernels::PatchMatchResult& result, const std::string& type) {
  std::vector<float> depth, normal;
  kernels::ExtractDepthNormalMaps(pm_problem, result, &depth, &normal);
  const int W = result.width, H = result.height;
  FloatMap depth_map(W, H, 1), normal_map(W, H, 3);
  depth_map.data = std::move(depth);
  normal_map.data = std::move(normal);
  // Normal first: fusion aborts on a depth map without its normal map.
  io_->WriteNormalMap(workspace_.NormalMapPath(problem.ref, type), normal_map);
  io_->WriteDepthMap(workspace_.DepthMapPath(problem.ref, type), depth_map, problem.depth_min,
                     problem.depth_max);
  if (run_.colmap_options.write_consistency_graph) {
    ConsistencyGraph graph;
    graph.width = W;
    graph.height = H;
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u < W; ++u) {
        const size_t i = static_cast<size_t>(v) * W + u;
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
    io_->WriteConsistencyGraph(workspace_.ConsistencyGraphPath(problem.ref, type), graph);
  }
  if (run_.options.write_pictures) {
    const std::string base = JoinPaths(workspace_.IntermediateDir(), "pictures/" + workspace_.views[problem.ref].name + "." + type);
    WriteRgbPng(base + ".depth.png", DepthPicture(depth_map, problem.depth_min, problem.depth_max, workspace_.views[problem.ref].name + " " + type + " depth"));
    WriteRgbPng(base + ".normal.png", NormalPicture(normal_map, workspace_.views[problem.ref].name + " " + type + " normals"));
  }
}

std::vector<float> Controller::ReadChromaGuide(int view) const {
  const RgbImage rgb = io_->ReadRgb(workspace_, view);
  const DenseView& v = workspace_.views[view];
  if (rgb.width != v.width || rgb.height != v.height) {
    throw Error(v.image_path + ": colour image is " + std::to_string(rgb.width) + "x" +
                std::to_string(rgb.height) + " but the view is " + std::to_string(v.width) + "x" +
                std::to_string(v.height));
  }
  std::vector<float> guide = MakeChromaGuide(rgb, static_cast<float>(run_.options.chroma_weight));
  if (std::none_of(guide.begin(), guide.end(), [](float c) { return c != 0.f; })) guide.clear();
  return guide;
}

std::unique_ptr<StageReference> Controller::PrepareReference(int stage_index, const Problem& p) {
  const StagePlan& stage = plan_.stages[stage_index];
  auto ref = std::make_unique<StageReference>();
  ref->problem = &p;
  const DenseView& view = workspace_.views[p.ref];
  const std::string final_type = plan_.geometric_output >= 0 ? "geometric" : "photometric";
  if (FinalOutputsExist(p.ref, final_type) && !run_.options.overwrite) {
    ref->action = StageReference::Action::kFinalMapsExist;
    return ref;
  }
  const bool writes_photometric = stage_index == plan_.photometric_output;
  const bool writes_geometric = stage_index == plan_.geometric_output;
  kernels::PatchMatchProblem& problem = ref->pm;
  problem.image_id = static_cast<uint32_t>(p.ref);
  problem.ref_image_id = static_cast<uint32_t>(p.ref);  // device cache ids: view indices
  problem.ref_camera = ToKernelCamera(view);
  problem.depth_min = p.depth_min;
  problem.depth_max = p.depth_max;

  const bool have_state = FileExists(StatePath(p.ref, stage.name)) && !run_.options.overwrite;
  ref->filter_here = run_.colmap_options.filter &&
                     ((writes_geometric) || (writes_photometric && plan_.geometric_output < 0));
  // Images and source depth maps: needed to compute the stage, and by the output filter.
  if (!have_state || ref->filter_here) {
    auto ref_image = images_->Get(p.ref);
    ref->images.push_back(ref_image);
    problem.ref_image = kernels::ImageView{ref_image->data.data(), ref_image->width, ref_image->height};
    if (run_.options.chroma_weight > 0) {
      ref->chroma = chroma_guides_->Get(p.ref);
      if (!ref->chroma->empty()) problem.ref_image.chroma = ref->chroma->data();
    }
    if (stage.schedule.geometric) problem.depth_maps_stage = stage.input;
    for (int src : p.src) {
      kernels::PatchMatchSource source;
      source.camera = ToKernelCamera(workspace_.views[src]);
      source.image_id = static_cast<uint32_t>(src);
      if (stage.schedule.geometric) {
        const std::string src_state = StatePath(src, plan_.stages[stage.input].name);
        if (!view_depth_min_.count(src) || !FileExists(src_state)) {
          LogWarning(view.name + ": source " + workspace_.views[src].name + " has no " +
                     plan_.stages[stage.input].name + " result; left out of this stage");
          continue;
        }
        ref->depths.push_back(depths_->Get({stage.input, src}));
        source.depth_map = ref->depths.back()->data();
      }
      auto img = images_->Get(src);
      ref->images.push_back(img);
      source.image = kernels::ImageView{img->data.data(), img->width, img->height};
      problem.sources.push_back(source);
    }
  }
  if (have_state) {
    ref->action = StageReference::Action::kResume;
    return ref;
  }
  if (problem.sources.empty()) {
    ref->action = StageReference::Action::kNoSources;
    return ref;
  }
  ref->action = StageReference::Action::kCompute;
  FloatMap input_state;
  if (stage.input >= 0) {
    input_state = ReadFloatMap(StatePath(p.ref, plan_.stages[stage.input].name), kStateChannels);
    if (input_state.width != view.width || input_state.height != view.height) {
      ThrowFileError(StatePath(p.ref, plan_.stages[stage.input].name),
                     "size differs from the image; delete stereo/mpmvs to start over");
    }
    StateToResult(input_state, &ref->input);
    problem.init_plane = ref->input.plane.data();
    problem.init_cost = ref->input.cost.data();
  }
  if (stage.kind == StageKind::kPlanarPrior) {
    PlanarPriorOptions po;
    const MpMvsOptions& o = run_.options;
    po.selection = stage.prior_geometric_selection ? PlanarPriorOptions::Selection::kGeometric
                                                   : PlanarPriorOptions::Selection::kPhotometric;
    po.cell_size = o.prior_cell_size;
    po.points_per_cell = o.prior_points_per_cell;
    po.max_photo_cost = static_cast<float>(o.prior_max_photo_cost);
    po.max_geom_error = static_cast<float>(o.prior_max_geom_error);
    po.max_cost_photometric = static_cast<float>(o.prior_max_cost_acmp);
    po.max_depth_jump = static_cast<float>(o.prior_max_depth_jump);
    po.max_edge_fraction = static_cast<float>(o.prior_max_edge);
    const std::vector<float> depth = StateDepth(input_state, problem.ref_camera, p.depth_min, p.depth_max);
    ref->prior = BuildPlanarPrior(problem.ref_camera, depth, ref->input.photo_cost, ref->input.geo_error,
                                  p.depth_min, p.depth_max, po);
    problem.prior_plane = ref->prior.plane.data();
    problem.prior_label = ref->prior.label.data();
    size_t labelled = 0;
    for (uint8_t l : ref->prior.label) labelled += l;
    LogInfo(view.name + ": planar prior with " + std::to_string(ref->prior.vertices.size()) + " vertices, " +
            std::to_string(ref->prior.triangles.size() / 3) + " triangles (" +
            std::to_string(ref->prior.num_rejected_triangles) + " rejected), " +
            std::to_string(100 * labelled / ref->prior.label.size()) + "% of pixels covered");
  }
  return ref;
}

void Controller::RunStage(int stage_index, MpPatchMatchSummary* summary) {
  const StagePlan& stage = plan_.stages[stage_index];
  StageSummary stage_summary;
  stage_summary.name = stage.name;
  const auto start = std::chrono::steady_clock::now();
  LogHeading("Stage " + std::to_string(stage_index + 1) + "/" + std::to_string(plan_.stages.size()) + ": " +
             stage.name + " (" + StageKindName(stage.kind) + ", " +
             std::to_string(stage.schedule.iterations.size()) + " iterations)");
  ProgressReporter progress("stage " + stage.name, static_cast<int>(problems_.size()));
  const bool writes_photometric = stage_index == plan_.photometric_output;
  const bool writes_geometric = stage_index == plan_.geometric_output;

  // The next reference image, when the backend had it assembled while this one ran (CUDA:
  // its uploads overlap this image's kernels). Only within a stage: the first image of the
  // next stage reads this stage's results, the last of which is still being computed. An
  // error assembling it is raised where it would have been without looking ahead.
  std::unique_ptr<StageReference> ahead;
  std::exception_ptr ahead_error;
  for (size_t i = 0; i < problems_.size(); ++i) {
    if (ahead_error) std::rethrow_exception(ahead_error);
    const std::unique_ptr<StageReference> ref =
        ahead ? std::move(ahead) : PrepareReference(stage_index, problems_[i]);
    const Problem& p = *ref->problem;
    const DenseView& view = workspace_.views[p.ref];
    const std::string state_path = StatePath(p.ref, stage.name);
    const kernels::PatchMatchProblem& problem = ref->pm;
    kernels::PatchMatchResult result;
    switch (ref->action) {
      case StageReference::Action::kFinalMapsExist:
        ++stage_summary.images_resumed;
        progress.Step(view.name + " (final maps exist, skipped)");
        continue;
      case StageReference::Action::kNoSources:
        LogWarning(view.name + ": no usable source views in stage " + stage.name + "; skipped");
        progress.Step(view.name + " (skipped)");
        continue;
      case StageReference::Action::kResume:
        StateToResult(ReadFloatMap(state_path, kStateChannels), &result);
        ++stage_summary.images_resumed;
        break;
      case StageReference::Action::kCompute: {
        auto next = [&, i]() -> const kernels::PatchMatchProblem* {
          if (i + 1 >= problems_.size()) return nullptr;
          try {
            ahead = PrepareReference(stage_index, problems_[i + 1]);
          } catch (...) {
            ahead_error = std::current_exception();
            return nullptr;
          }
          return ahead->action == StageReference::Action::kCompute ? &ahead->pm : nullptr;
        };
        backend_->Run(problem, stage.schedule, &result, next);
        // The reference pipeline median-filters every run's depths (ALGORITHM.md 9.1); later
        // stages, the planar prior and the outputs all see the filtered result.
        kernels::MedianFilterDepthsCpu(problem.ref_camera, p.depth_min, p.depth_max,
                                       run_.colmap_options.num_threads, &result);
        const FloatMap state = ResultToState(result);
        WriteFloatMap(state_path, state);
        if (run_.options.write_pictures) {
          const std::string base = JoinPaths(workspace_.IntermediateDir(), "pictures/" + view.name + "." + stage.name);
          FloatMap stage_depth(view.width, view.height, 1);
          stage_depth.data = StateDepth(state, problem.ref_camera, p.depth_min, p.depth_max);
          WriteRgbPng(base + ".depth.png", DepthPicture(stage_depth, p.depth_min, p.depth_max, view.name + " stage " + stage.name));
          if (stage.kind == StageKind::kPlanarPrior) {
            const PlanarPriorModel& prior = ref->prior;
            FloatMap prior_depth(view.width, view.height, 1);
            for (size_t k = 0; k < prior.label.size(); ++k) {
              if (!prior.label[k]) continue;
              const kernels::Plane pl{{prior.plane[4 * k], prior.plane[4 * k + 1], prior.plane[4 * k + 2]}, prior.plane[4 * k + 3]};
              prior_depth.data[k] = kernels::PlaneDepth(
                  pl, kernels::PixelRay(problem.ref_camera, float(k % view.width), float(k / view.width)));
            }
            WriteRgbPng(base + ".prior_model.png", DepthPicture(prior_depth, p.depth_min, p.depth_max, view.name + " planar prior"));
          }
        }
        ++stage_summary.images_computed;
        stage_summary.ncc_evaluations += result.init_ncc_evaluations;
        for (const auto& it : result.iterations) stage_summary.ncc_evaluations += it.ncc_evaluations;
        stage_summary.pixel_iterations +=
            static_cast<uint64_t>(result.width) * result.height * result.iterations.size();
        if (stage_summary.iterations.empty()) stage_summary.iterations = result.iterations;
        break;
      }
    }
    if (ref->filter_here && !problem.sources.empty()) {
      kernels::FilterParams filter;
      filter.min_ncc = static_cast<float>(run_.colmap_options.filter_min_ncc);
      filter.min_triangulation_angle_deg = static_cast<float>(run_.colmap_options.filter_min_triangulation_angle);
      filter.min_num_consistent = run_.colmap_options.filter_min_num_consistent;
      filter.geom_max_error = static_cast<float>(run_.colmap_options.filter_geom_consistency_max_cost);
      const size_t removed =
          kernels::FilterResultCpu(problem, stage.schedule.geometric, filter, run_.colmap_options.num_threads, &result);
      LogInfo(view.name + ": filter removed " + std::to_string(removed) + " pixels");
    }
    if (writes_photometric && (run_.options.overwrite || !FinalOutputsExist(p.ref, "photometric"))) {
      WriteFinal(p, problem, result, "photometric");
    }
    if (writes_geometric) {
      kernels::InvalidateGeometricallyInconsistent(stage.schedule.geom_max_error, &result);
      WriteFinal(p, problem, result, "geometric");
    }
    progress.Step(view.name + (ref->action == StageReference::Action::kResume ? " (resumed from stereo/mpmvs)" : ""));
  }
  stage_summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary->stages.push_back(stage_summary);
}

}  // namespace

MpPatchMatchSummary RunMpPatchMatchStereo(const MpPatchMatchRun& run, WorkspaceIo* io) {
  if (io == nullptr) throw Error("RunMpPatchMatchStereo: no workspace I/O given");
  Controller controller(run, io);
  return controller.Run();
}

kernels::Camera ToKernelCamera(const DenseView& view) {
  kernels::Camera c;
  c.width = view.width;
  c.height = view.height;
  c.fx = static_cast<float>(view.K[0]);
  c.fy = static_cast<float>(view.K[4]);
  c.cx = static_cast<float>(view.K[2]);
  c.cy = static_cast<float>(view.K[5]);
  for (int i = 0; i < 9; ++i) c.R[i] = static_cast<float>(view.R[i]);
  for (int i = 0; i < 3; ++i) c.t[i] = static_cast<float>(view.T[i]);
  return c;
}

MpPatchMatchSummary RunMpPatchMatchStereo(const MpPatchMatchRun& run) {
  MpMvsWorkspaceIo io;
  return RunMpPatchMatchStereo(run, &io);
}

}  // namespace mpmvs

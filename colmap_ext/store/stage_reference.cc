#include "colmap_ext/store/stage_reference.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "colmap_ext/plan/kernel_camera.h"
#include "colmap_ext/prior/epipolar_texture.h"
#include "colmap_ext/util/logging.h"
#include "kernels/half_resolution.h"

namespace mpmvs {
namespace {

// Marks in *excluded (allocated if empty) the pixels where depth bends by more than
// max_bend; nothing with max_bend 0.
void ExcludeBentDepths(int W, int H, const std::vector<float>& depth, float max_bend, std::vector<uint8_t>* excluded) {
  if (!(max_bend > 0.f)) return;
  const std::vector<uint8_t> bent = BentDepthMask(W, H, depth, kVertexBendStep, max_bend);
  if (excluded->empty()) excluded->assign(bent.size(), 0);
  for (size_t i = 0; i < bent.size(); ++i) (*excluded)[i] |= bent[i];
}

// Marks as no triangle corners the reference's vertices whose window of the finest scale
// varies along no source's epipolar line beyond the image noise: a plane through the
// window's edge matches in every view wherever the vertex lies along it, so the vertex
// votes but is no triangle corner (kernels/DESIGN.md 29). Only the selected vertices are
// tested: a quarter to a seventh of the candidates (adirondack 34 k of 220 k, an 8-view room
// 9-12 k of 39-60 k), whose test took 0.05 of the 0.3 s in which a prior model was built.
void MarkEpipolarBlindVertices(const kernels::PatchMatchProblem& problem, int num_threads,
                               std::vector<PlanarPriorVertex>* vertices) {
  constexpr float kMaxDifferenceToNoise = 2.f;  // as a plain window's texture (PlainWindow)
  const int W = problem.ref_camera.width;
  auto pixel = [W](const PlanarPriorVertex& vertex) { return static_cast<size_t>(vertex.v) * W + vertex.u; };
  std::vector<uint8_t> candidate(static_cast<size_t>(W) * problem.ref_camera.height, 0);
  for (const PlanarPriorVertex& vertex : *vertices) candidate[pixel(vertex)] = 1;
  std::vector<kernels::Camera> sources;
  for (const kernels::PatchMatchSource& source : problem.sources) sources.push_back(source.camera);
  const std::vector<uint8_t> blind =
      EpipolarBlindMask(problem.ref_image, problem.ref_camera, sources, kernels::WindowForScale(0),
                        problem.ref_noise_variance, kMaxDifferenceToNoise, candidate, num_threads);
  for (PlanarPriorVertex& vertex : *vertices) vertex.corner = !blind[pixel(vertex)];
}

// The reference's and its sources' images and, in geometric stages, the sources' depth
// maps of the input stage (a source without them is left out, with a warning).
void AddImagesAndSources(const StagePlan& stage, const std::string& input_stage, const DenseWorkspace& workspace,
                         const KernelFrame& frame, StageStore* store, float guide_weight, StageReference* ref) {
  const ReferenceProblem& p = *ref->problem;
  kernels::PatchMatchProblem& problem = ref->pm;
  auto ref_image = store->Image(p.ref);
  ref->images.push_back(ref_image);
  problem.ref_image = kernels::ImageView{ref_image->data.data(), ref_image->width, ref_image->height};
  if (stage.schedule.noise_floor) problem.ref_noise_variance = store->NoiseVariance(p.ref);
  if (guide_weight > 0) {
    ref->chroma = store->ChromaGuide(p.ref);
    if (!ref->chroma->empty()) problem.ref_image.chroma = ref->chroma->data();
  }
  if (stage.schedule.geometric) problem.depth_maps_stage = stage.input;
  for (int src : p.src) {
    kernels::PatchMatchSource source;
    source.camera = ToKernelCamera(workspace.views[src], frame);
    source.image_id = static_cast<uint32_t>(src);
    if (stage.schedule.geometric) {
      if (!store->HasState(src, input_stage)) {
        if (store->Runs(src)) {  // else said once when the run was planned
          LogWarning(workspace.views[p.ref].name + ": source " + workspace.views[src].name + " has no " +
                     input_stage + " result; left out of this stage");
        }
        continue;
      }
      ref->depths.push_back(store->SourceDepth(stage.input, src));
      source.depth_map = ref->depths.back()->data();
    }
    auto img = store->Image(src);
    ref->images.push_back(img);
    source.image = kernels::ImageView{img->data.data(), img->width, img->height};
    problem.sources.push_back(source);
  }
}

// The sources' own prior vertices from their results of the input stage, seen from the
// reference (PlanarPriorFromVertices keeps those outside its image). They pass a stricter test than
// the reference's own, as the reference cannot check them: photometric cost below
// source_max_photo_cost and, with the texture-adaptive prior, a window of the finest scale
// that is not plain. options.max_vertex_bend applies as to the reference's own.
std::vector<PlanarPriorVertex> SourceViewVertices(const std::string& input_stage,
                                                  const PlanarPriorOptions& options, bool adaptive,
                                                  StageStore* store, const StageReference& ref) {
  const kernels::PatchMatchProblem& problem = ref.pm;
  PlanarPriorOptions source_options = options;
  source_options.max_photo_cost = std::min(options.max_photo_cost, options.source_max_photo_cost);
  std::vector<PlanarPriorVertex> vertices;
  for (size_t k = 0; k < problem.sources.size(); ++k) {
    const int src = static_cast<int>(problem.sources[k].image_id);
    if (!store->HasState(src, input_stage)) continue;
    const kernels::PatchMatchResult result = store->ReadState(src, input_stage);
    const kernels::Camera& camera = problem.sources[k].camera;
    const std::vector<float> depth = ResultDepth(result, camera, 0.f, std::numeric_limits<float>::max());
    std::vector<uint8_t> excluded;  // pixels that are no vertices
    if (adaptive) excluded = *store->PlainWindows(src, 0);
    ExcludeBentDepths(camera.width, camera.height, depth, options.max_vertex_bend, &excluded);
    const std::vector<PlanarPriorVertex> own =
        SelectPriorVertices(camera.width, camera.height, depth, result.photo_cost, result.geo_error, source_options,
                            &result.plane, excluded.empty() ? nullptr : &excluded);
    const std::vector<PlanarPriorVertex> seen = TransferPriorVertices(camera, problem.ref_camera, own);
    vertices.insert(vertices.end(), seen.begin(), seen.end());
  }
  return vertices;
}

void AddPlanarPrior(const StagePlan& stage, const RunPlan& plan, const DenseWorkspace& workspace,
                    const std::string& input_stage, StageStore* store, StageReference* ref) {
  const ReferenceProblem& p = *ref->problem;
  PlanarPriorOptions options = plan.prior;
  options.num_threads = stage.schedule.num_threads;
  options.selection = stage.prior_geometric_selection ? PlanarPriorOptions::Selection::kGeometric
                                                      : PlanarPriorOptions::Selection::kPhotometric;
  kernels::PatchMatchProblem& problem = ref->pm;
  const std::vector<float> depth = ResultDepth(ref->input, problem.ref_camera, p.depth_min, p.depth_max);
  // With the texture-adaptive prior, pixels whose grey window of the middle mPM scale is
  // plain are no vertices (kernels/DESIGN.md 17).
  std::vector<uint8_t> excluded;  // pixels that are no vertices
  const bool adaptive = kernels::TextureAdaptivePrior(problem.ref_noise_variance, stage.schedule.prior_beta);
  if (adaptive) {
    constexpr int kVertexTextureScale = 1;
    const int coarsest = kernels::FirstFullResolutionScale(plan.pipeline.stages.front().schedule);
    // Of the grey image: colour edges split the bilateral window, yet are texture.
    excluded = *store->PlainWindows(p.ref, std::min(kVertexTextureScale, coarsest));
  }
  // Vertices where the depth bends (kernels/DESIGN.md 25): gp, from an estimate that
  // followed no prior yet.
  if (!stage.prior_geometric_selection || BuildsOnPrior(plan.pipeline, stage.input)) options.max_vertex_bend = 0.f;
  ExcludeBentDepths(problem.ref_camera.width, problem.ref_camera.height, depth, options.max_vertex_bend, &excluded);
  std::vector<PlanarPriorVertex> vertices =
      SelectPriorVertices(problem.ref_camera.width, problem.ref_camera.height, depth, ref->input.photo_cost,
                          ref->input.geo_error, options, &ref->input.plane, excluded.empty() ? nullptr : &excluded);
  if (adaptive && stage.prior_geometric_selection && options.plane_vote) {
    MarkEpipolarBlindVertices(problem, options.num_threads, &vertices);
  }
  std::vector<PlanarPriorVertex> source_vertices;
  const bool use_sources = options.source_vertices && stage.prior_geometric_selection;
  if (use_sources) source_vertices = SourceViewVertices(input_stage, options, adaptive, store, *ref);
  ref->prior = PlanarPriorFromVertices(problem.ref_camera, std::move(vertices), p.depth_min, p.depth_max, options,
                                       use_sources ? &source_vertices : nullptr, &problem.ref_image);
  problem.prior_plane = ref->prior.plane.data();
  problem.prior_label = ref->prior.label.data();
  size_t labelled = 0;
  for (uint8_t l : ref->prior.label) labelled += l;
  LogDetail(workspace.views[p.ref].name + ": planar prior with " + std::to_string(ref->prior.vertices.size()) +
          " vertices (" + std::to_string(ref->prior.num_outside_vertices) + " of source views, outside the image; " +
          std::to_string(ref->prior.num_vote_only_vertices) + " vote only), " +
          std::to_string(ref->prior.triangles.size() / 3) + " triangles (" +
          std::to_string(ref->prior.num_voted_triangles) + " take a neighbour's plane), " +
          std::to_string(100 * labelled / ref->prior.label.size()) + "% of pixels covered");
}

}  // namespace

std::unique_ptr<StageReference> PrepareStageReference(const RunPlan& plan, const DenseWorkspace& workspace,
                                                      StageStore* store, int stage_index,
                                                      const ReferenceProblem& p, bool done, bool state_needed) {
  const StagePlan& stage = plan.pipeline.stages[stage_index];
  auto ref = std::make_unique<StageReference>();
  ref->problem = &p;
  if (!state_needed || (done && store->HasState(p.ref, stage.name))) {
    ref->action = done ? StageReference::Action::kFinalMapsExist : StageReference::Action::kNotNeeded;
    return ref;
  }
  ref->write_final = !done;
  const bool writes_photometric = stage_index == plan.pipeline.photometric_output;
  const bool writes_geometric = stage_index == plan.pipeline.geometric_output;
  kernels::PatchMatchProblem& problem = ref->pm;
  problem.image_id = static_cast<uint32_t>(p.ref);
  problem.ref_image_id = static_cast<uint32_t>(p.ref);  // device cache ids: view indices
  const KernelFrame frame = ChooseKernelFrame(workspace, p.ref, p.src, p.depth_min);
  problem.ref_camera = ToKernelCamera(workspace.views[p.ref], frame);
  problem.depth_min = p.depth_min;
  problem.depth_max = p.depth_max;

  // A state keeps no view selection, which a consistency graph lists: a stage that writes maps
  // with one is computed again (the same result) rather than resumed.
  const bool writes_graph = ref->write_final && plan.write_consistency_graph &&
                            (writes_geometric || (writes_photometric && !store->FinalOutputsExist(p.ref, "photometric")));
  const bool have_state = !plan.overwrite && !writes_graph && store->HasState(p.ref, stage.name);
  ref->filter_here = ref->write_final && plan.filter &&
                     (writes_geometric || (writes_photometric && plan.pipeline.geometric_output < 0));
  // Images and source depth maps: needed to compute the stage, and by the output filter.
  const std::string input_stage = stage.input >= 0 ? plan.pipeline.stages[stage.input].name : "";
  if (!have_state || ref->filter_here) {
    AddImagesAndSources(stage, input_stage, workspace, frame, store, plan.chroma_guide_weight, ref.get());
  }
  if (have_state) {
    ref->action = StageReference::Action::kResume;
    return ref;
  }
  // No sources, or no result of the input stage to start from (it had no sources there).
  if (problem.sources.empty() || (stage.input >= 0 && !store->HasState(p.ref, input_stage))) {
    ref->action = StageReference::Action::kNoSources;
    return ref;
  }
  ref->action = StageReference::Action::kCompute;
  if (stage.input >= 0) {
    ref->input = store->ReadState(p.ref, input_stage);
    problem.init_plane = ref->input.plane.data();
    problem.init_cost = ref->input.cost.data();
  }
  if (stage.kind == StageKind::kPlanarPrior) AddPlanarPrior(stage, plan, workspace, input_stage, store, ref.get());
  return ref;
}

}  // namespace mpmvs

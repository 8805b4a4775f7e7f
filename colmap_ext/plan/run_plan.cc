#include "colmap_ext/plan/run_plan.h"

#include <unistd.h>

#include <cmath>
#include <sstream>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

PlanarPriorOptions MakePriorOptions(const MpMvsOptions& o) {
  PlanarPriorOptions po;
  po.cell_size = o.prior_cell_size;
  po.points_per_cell = o.prior_points_per_cell;
  po.max_photo_cost = static_cast<float>(o.prior_max_photo_cost);
  po.max_geom_error = static_cast<float>(o.prior_max_geom_error);
  po.max_cost_photometric = static_cast<float>(o.prior_max_cost_acmp);
  po.plane_vote = o.prior_plane_vote;
  po.corner_colour_match = static_cast<float>(o.prior_corner_colour_match);
  po.source_vertices = o.prior_source_vertices;
  po.max_vertex_bend = static_cast<float>(o.prior_vertex_bend);
  return po;
}

kernels::FilterParams MakeFilterParams(const PatchMatchStereoOptions& c) {
  kernels::FilterParams filter;
  filter.min_ncc = static_cast<float>(c.filter_min_ncc);
  filter.min_triangulation_angle_deg = static_cast<float>(c.filter_min_triangulation_angle);
  filter.min_num_consistent = c.filter_min_num_consistent;
  filter.max_reprojection_error = static_cast<float>(c.filter_geom_consistency_max_cost);
  return filter;
}

// COLMAP's gpu_index is a list ("0,1"); mp-mvs uses its first entry.
int FirstGpuIndex(const std::string& gpu_index) {
  std::stringstream ss(gpu_index);
  std::string first;
  std::getline(ss, first, ',');
  return std::stoi(first);
}

// --PatchMatchStereo.num_threads capped to what the CPU functions use, with a warning.
int CappedThreads(int requested) {
  const int max_threads = kernels::MaxCpuThreads();
  if (requested <= max_threads) return requested;
  LogWarning("--PatchMatchStereo.num_threads " + std::to_string(requested) + " capped to " +
             std::to_string(max_threads) + " (4 per hardware thread)");
  return max_threads;
}

// --PatchMatchStereo.cache_size in bytes, clamped to this machine's memory (a bound on the
// caches, not an allocation, but far more than the memory overflowed), with a warning unless
// it is the default (COLMAP's 32 GB, more than many machines have).
size_t CacheBytes(double cache_size_gb) {
  constexpr double kGb = 1024.0 * 1024.0 * 1024.0;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page_size = ::sysconf(_SC_PAGE_SIZE);
  const double memory = pages > 0 && page_size > 0 ? static_cast<double>(pages) * page_size : 64 * kGb;
  if (cache_size_gb * kGb <= memory) return static_cast<size_t>(cache_size_gb * kGb);
  if (cache_size_gb != PatchMatchStereoOptions().cache_size) LogWarning("--PatchMatchStereo.cache_size " + FormatNumber(cache_size_gb) + " capped to " +
             FormatNumber(std::floor(memory / kGb * 10) / 10) + " (GB of this machine's memory)");
  return static_cast<size_t>(memory);
}

// --MPMVS.stage as an index into the stages (-1: all); an error when this pipeline has no
// such stage (e.g. prior with --MPMVS.planar_prior none).
int FindStage(const PipelinePlan& pipeline, const std::string& name) {
  if (name == "all") return -1;
  std::string names;
  for (size_t i = 0; i < pipeline.stages.size(); ++i) {
    if (pipeline.stages[i].name == name) return static_cast<int>(i);
    names += (names.empty() ? "" : ", ") + pipeline.stages[i].name;
  }
  throw Error("--MPMVS.stage " + name + ": this run has no such stage (its stages: " + names + ", or all)");
}

}  // namespace

RunPlan MakeRunPlan(const PatchMatchStereoOptions& colmap_options, const MpMvsOptions& options,
                    bool cpu_side_work) {
  std::string error;
  if (!colmap_options.Check(&error) || !options.Check(&error)) throw Error(error);
  RunPlan plan;
  plan.pipeline = MakePipelinePlan(colmap_options, options);
  plan.final_type = plan.pipeline.geometric_output >= 0 ? "geometric" : "photometric";
  plan.prior = MakePriorOptions(options);
  plan.filter = colmap_options.filter;
  plan.filter_params = MakeFilterParams(colmap_options);
  plan.cache_bytes = CacheBytes(colmap_options.cache_size);
  plan.num_threads = CappedThreads(colmap_options.num_threads);
  plan.backend.gpu_index = FirstGpuIndex(colmap_options.gpu_index);
  plan.backend.num_threads = plan.num_threads;
  plan.backend.cache_bytes = plan.cache_bytes;
  plan.backend.cpu_side_work = cpu_side_work;
  plan.chroma_guide_weight = static_cast<float>(options.chroma_weight);
  plan.sources_per_reference = options.max_source_images;
  plan.overwrite = options.overwrite;
  plan.stage_pictures = options.write_pictures == "all";
  plan.final_pictures = plan.stage_pictures || options.write_pictures == "final";
  plan.write_consistency_graph = colmap_options.write_consistency_graph;
  plan.keep_states = options.keep_states;
  plan.allow_missing_files = colmap_options.allow_missing_files;
  plan.shard = ParseShard(options.shard);
  if (!options.image_list_path.empty()) {
    plan.image_names = ReadImageList(options.image_list_path);
    if (plan.image_names.empty()) throw Error(options.image_list_path + ": the image list names no image");
  }
  plan.only_stage = FindStage(plan.pipeline, options.stage);
  plan.claim_lease_seconds = options.claim_lease;
  return plan;
}

}  // namespace mpmvs

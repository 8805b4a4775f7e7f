#include "colmap_ext/options/patch_match_options.h"

#include <sstream>

namespace mpmvs {
namespace {

template <typename T>
bool Fail(std::string* error, const std::string& name, const T& value, const std::string& rule) {
  std::ostringstream ss;
  ss << "--" << name << " = " << value << " is invalid: must be " << rule;
  if (error) *error = ss.str();
  return false;
}

}  // namespace

bool PatchMatchStereoOptions::Check(std::string* error) const {
  const std::string p = "PatchMatchStereo.";
  if (max_image_size == 0 || max_image_size < -1)
    return Fail(error, p + "max_image_size", max_image_size, "-1 or > 0");
  if ((depth_min != -1 || depth_max != -1) && !(depth_min > 0 && depth_max > depth_min))
    return Fail(error, p + "depth_min/depth_max", std::to_string(depth_min) + "/" + std::to_string(depth_max),
                "both set with 0 < depth_min < depth_max (or both -1)");
  if (filter_min_ncc < -1 || filter_min_ncc > 1)
    return Fail(error, p + "filter_min_ncc", filter_min_ncc, "in [-1, 1]");
  if (filter_min_triangulation_angle < 0 || filter_min_triangulation_angle > 180)
    return Fail(error, p + "filter_min_triangulation_angle", filter_min_triangulation_angle, "in [0, 180]");
  if (filter_min_num_consistent < 0)
    return Fail(error, p + "filter_min_num_consistent", filter_min_num_consistent, ">= 0");
  if (filter_geom_consistency_max_cost < 0)
    return Fail(error, p + "filter_geom_consistency_max_cost", filter_geom_consistency_max_cost, ">= 0");
  if (cache_size <= 0) return Fail(error, p + "cache_size", cache_size, "> 0");
  if (num_threads < -1 || num_threads == 0) return Fail(error, p + "num_threads", num_threads, "-1 or > 0");
  if (min_triangulation_angle < 0 || min_triangulation_angle >= 180)
    return Fail(error, p + "min_triangulation_angle", min_triangulation_angle, "in [0, 180)");
  std::stringstream ss(gpu_index);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      size_t pos = 0;
      const int v = std::stoi(item, &pos);
      if (pos != item.size() || v < -1) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      return Fail(error, p + "gpu_index", gpu_index, "a comma-separated list of integers >= -1");
    }
  }
  return true;
}

PlanarPriorMode MpMvsOptions::PriorMode() const {
  if (planar_prior == "photometric") return PlanarPriorMode::kPhotometric;
  if (planar_prior == "geometric") return PlanarPriorMode::kGeometric;
  return PlanarPriorMode::kNone;
}

bool MpMvsOptions::Check(std::string* error) const {
  const std::string p = "MPMVS.";
  if (max_window_scale < 0 || max_window_scale > 4)
    return Fail(error, p + "max_window_scale", max_window_scale, "in [0, 4]");
  if (iterations_per_scale < 1) return Fail(error, p + "iterations_per_scale", iterations_per_scale, ">= 1");
  if (planar_prior != "none" && planar_prior != "photometric" && planar_prior != "geometric")
    return Fail(error, p + "planar_prior", planar_prior, "none, photometric or geometric");
  if (geom_iterations < 1) return Fail(error, p + "geom_iterations", geom_iterations, ">= 1");
  if (prior_iterations < 1) return Fail(error, p + "prior_iterations", prior_iterations, ">= 1");
  if (geom_weight < 0) return Fail(error, p + "geom_weight", geom_weight, ">= 0");
  if (geom_max_error <= 0) return Fail(error, p + "geom_max_error", geom_max_error, "> 0");
  if (prior_cell_size < 1) return Fail(error, p + "prior_cell_size", prior_cell_size, ">= 1");
  if (prior_points_per_cell < 1) return Fail(error, p + "prior_points_per_cell", prior_points_per_cell, ">= 1");
  if (prior_beta <= 0) return Fail(error, p + "prior_beta", prior_beta, "> 0");
  if (!(prior_vertex_bend >= 0 && prior_vertex_bend <= 1))
    return Fail(error, p + "prior_vertex_bend", prior_vertex_bend, "in [0, 1]");
  if (settled_pixel_skips < 0 || settled_pixel_skips > 255)
    return Fail(error, p + "settled_pixel_skips", settled_pixel_skips, "in [0, 255]");
  if (refinement_rho <= 0 || refinement_rho >= 1)
    return Fail(error, p + "refinement_rho", refinement_rho, "in (0, 1)");
  if (!(chroma_weight >= 0 && chroma_weight <= 1000))
    return Fail(error, p + "chroma_weight", chroma_weight, "in [0, 1000]");
  if (max_source_images < 1 || max_source_images > 32)
    return Fail(error, p + "max_source_images", max_source_images, "in [1, 32]");
  if (seed < 0) return Fail(error, p + "seed", seed, ">= 0");
  if (depth_check_views < 0 || depth_check_views > 32)
    return Fail(error, p + "depth_check_views", depth_check_views, "in [0, 32]");
  if (prior_rounds < 1 || prior_rounds > 4) return Fail(error, p + "prior_rounds", prior_rounds, "in [1, 4]");
  if (stage.empty()) return Fail(error, p + "stage", stage, "all or a stage name (photometric, geometric1, ...)");
  if (claim_lease < 1) return Fail(error, p + "claim_lease", claim_lease, ">= 1 (seconds)");
  return true;
}

}  // namespace mpmvs

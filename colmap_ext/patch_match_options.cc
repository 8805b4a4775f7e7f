#include "colmap_ext/patch_match_options.h"

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
  if (prior_max_depth_jump <= 0) return Fail(error, p + "prior_max_depth_jump", prior_max_depth_jump, "> 0");
  if (prior_max_edge <= 0) return Fail(error, p + "prior_max_edge", prior_max_edge, "> 0");
  if (refinement_rho <= 0 || refinement_rho >= 1)
    return Fail(error, p + "refinement_rho", refinement_rho, "in (0, 1)");
  if (!(chroma_weight >= 0 && chroma_weight <= 1000))
    return Fail(error, p + "chroma_weight", chroma_weight, "in [0, 1000]");
  if (max_source_images < 1 || max_source_images > 32)
    return Fail(error, p + "max_source_images", max_source_images, "in [1, 32]");
  if (seed < 0) return Fail(error, p + "seed", seed, ">= 0");
  return true;
}

void AddPatchMatchOptions(OptionParser* parser, PatchMatchStereoOptions* c, MpMvsOptions* m) {
  const std::string p = "PatchMatchStereo.";
  parser->Add(p + "max_image_size", &c->max_image_size, "down-scale images so max(w,h) <= this; -1 = off");
  parser->Add(p + "gpu_index", &c->gpu_index, "-1 = first usable GPU (else CPU); a GPU index");
  parser->Add(p + "depth_min", &c->depth_min, "-1 = from the sparse points");
  parser->Add(p + "depth_max", &c->depth_max, "-1 = from the sparse points");
  parser->Add(p + "geom_consistency", &c->geom_consistency, "run the geometric stages, write .geometric.bin");
  parser->Add(p + "filter", &c->filter, "COLMAP-style output filter (mp-mvs default: off)");
  parser->Add(p + "filter_min_ncc", &c->filter_min_ncc);
  parser->Add(p + "filter_min_triangulation_angle", &c->filter_min_triangulation_angle);
  parser->Add(p + "filter_min_num_consistent", &c->filter_min_num_consistent);
  parser->Add(p + "filter_geom_consistency_max_cost", &c->filter_geom_consistency_max_cost);
  parser->Add(p + "cache_size", &c->cache_size, "GB of images and maps kept in memory");
  parser->Add(p + "write_consistency_graph", &c->write_consistency_graph);
  parser->Add(p + "allow_missing_files", &c->allow_missing_files,
              "drop sources whose image or maps are missing instead of failing");
  parser->Add(p + "num_threads", &c->num_threads, "CPU threads; -1 = all cores");
  parser->Add(p + "min_triangulation_angle", &c->min_triangulation_angle,
              "degrees; __auto__ source selection in patch-match.cfg");
  parser->AddIgnored(p + "window_radius", "use --MPMVS.max_window_scale (windows 11/21/41 px)");
  parser->AddIgnored(p + "window_step", "use --MPMVS.max_window_scale (6x6 samples per window)");
  parser->AddIgnored(p + "sigma_spatial", "the bilateral weights are MP-MVS's (sigma_s = 5)");
  parser->AddIgnored(p + "sigma_color", "the bilateral weights are MP-MVS's (sigma_c = 3)");
  parser->AddIgnored(p + "num_samples", "view selection draws 15 samples (ACMH)");
  parser->AddIgnored(p + "ncc_sigma", "view selection is ACMH's");
  parser->AddIgnored(p + "incident_angle_sigma", "view selection is ACMH's");
  parser->AddIgnored(p + "num_iterations", "use --MPMVS.iterations_per_scale / --MPMVS.geom_iterations");
  parser->AddIgnored(p + "geom_consistency_regularizer", "use --MPMVS.geom_weight");
  parser->AddIgnored(p + "geom_consistency_max_cost", "use --MPMVS.geom_max_error");

  const std::string q = "MPMVS.";
  parser->Add(q + "max_window_scale", &m->max_window_scale, "S_max; 0 = single 11 px window (no mPM)");
  parser->Add(q + "iterations_per_scale", &m->iterations_per_scale);
  parser->Add(q + "distant_sampling", &m->distant_sampling, "1 = MP-MVS distant checkerboard, 0 = ACMH");
  parser->Add(q + "planar_prior", &m->planar_prior, "none | photometric (ACMP) | geometric (MP-MVS)");
  parser->Add(q + "geom_iterations", &m->geom_iterations);
  parser->Add(q + "prior_iterations", &m->prior_iterations);
  parser->Add(q + "geom_weight", &m->geom_weight, "lambda of the geometric term");
  parser->Add(q + "geom_max_error", &m->geom_max_error, "clamp of the reprojection error, px");
  parser->Add(q + "prior_max_photo_cost", &m->prior_max_photo_cost);
  parser->Add(q + "prior_max_geom_error", &m->prior_max_geom_error);
  parser->Add(q + "prior_max_cost_acmp", &m->prior_max_cost_acmp);
  parser->Add(q + "prior_cell_size", &m->prior_cell_size);
  parser->Add(q + "prior_points_per_cell", &m->prior_points_per_cell);
  parser->Add(q + "prior_max_depth_jump", &m->prior_max_depth_jump);
  parser->Add(q + "prior_max_edge", &m->prior_max_edge);
  parser->Add(q + "refinement_rho", &m->refinement_rho);
  parser->Add(q + "chroma_weight", &m->chroma_weight,
              "weight of the reference's smoothed colour in the NCC weights; 0 = grey only (paper)");
  parser->Add(q + "max_source_images", &m->max_source_images);
  parser->Add(q + "seed", &m->seed);
  parser->Add(q + "overwrite", &m->overwrite, "recompute outputs that already exist");
  parser->Add(q + "write_pictures", &m->write_pictures, "depth/normal PNGs in stereo/mpmvs/pictures");
}

}  // namespace mpmvs

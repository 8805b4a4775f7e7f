#include "colmap_ext/cli/patch_match_flags.h"

#include <string>

namespace mpmvs {

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
  parser->AddIgnored(p + "sigma_color", "the bilateral weights are MP-MVS's (sigma_c = 2.5)");
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
  parser->Add(q + "prior_rounds", &m->prior_rounds);
  parser->Add(q + "geom_weight", &m->geom_weight, "lambda of the geometric term");
  parser->Add(q + "geom_max_error", &m->geom_max_error, "clamp of the reprojection error, px");
  parser->Add(q + "prior_max_photo_cost", &m->prior_max_photo_cost);
  parser->Add(q + "prior_max_geom_error", &m->prior_max_geom_error);
  parser->Add(q + "prior_max_cost_acmp", &m->prior_max_cost_acmp);
  parser->Add(q + "prior_cell_size", &m->prior_cell_size);
  parser->Add(q + "prior_points_per_cell", &m->prior_points_per_cell);
  parser->Add(q + "prior_plane_vote", &m->prior_plane_vote,
              "each prior triangle takes the plane its neighbouring vertices vote for; 0 = its own plane (paper)");
  parser->Add(q + "prior_source_vertices", &m->prior_source_vertices,
              "gp: source views' vertices outside the reference image join its prior triangles; 0 = own vertices "
              "only (paper)");
  parser->Add(q + "prior_vertex_bend", &m->prior_vertex_bend,
              "gp, first prior: pixels where the depth bends by more than this (relative second difference of "
              "inverse depth over +-3 px) are no vertices; 0 = off (paper)");
  parser->Add(q + "prior_beta", &m->prior_beta, "photometric weight exp(-C^2/beta) of the prior run's score; 0.18 = ACMP");
  parser->Add(q + "settled_pixel_skips", &m->settled_pixel_skips,
              "a pixel whose update moved its plane by at most 0.5 % in depth and 3 degrees in normal skips this many "
              "of its next updates at the same window scale; 0 = every pixel in every pass (paper)");
  parser->Add(q + "noise_floor", &m->noise_floor,
              "floor the photometric cost at the image noise level in the geometric and prior stages; 0 = paper");
  parser->Add(q + "refinement_rho", &m->refinement_rho);
  parser->Add(q + "depth_check_views", &m->depth_check_views,
              "source views whose final depth maps must confirm a written depth within 1 %; 0 = no check (paper)");
  parser->Add(q + "chroma_weight", &m->chroma_weight,
              "weight of the reference's smoothed colour in the NCC weights; 0 = grey only (paper)");
  parser->Add(q + "max_source_images", &m->max_source_images);
  parser->Add(q + "seed", &m->seed);
  parser->Add(q + "overwrite", &m->overwrite, "recompute outputs that already exist");
  parser->Add(q + "write_pictures", &m->write_pictures, "depth/normal PNGs in stereo/mpmvs/pictures");
  parser->Add(q + "shard", &m->shard,
              "i/n: run shard i of n of the reference images (balanced by pixels x sources); same maps as one process");
  parser->Add(q + "image_list_path", &m->image_list_path, "file naming the reference images to run, one per line");
  parser->Add(q + "stage", &m->stage,
              "all, or one stage (photometric, geometric1, prior, geometric2, prior2, geometric3); its inputs must exist");
  parser->Add(q + "claim_lease", &m->claim_lease,
              "seconds before a work claim of a silent process on another host is taken over");
}

void AddMpPatchMatchRunOptions(OptionParser* parser, MpPatchMatchRun* run, std::string* pmvs_option_name) {
  parser->AddRequired("workspace_path", &run->workspace_path, "COLMAP dense workspace (image_undistorter output)");
  parser->Add("workspace_format", &run->workspace_format, "COLMAP (PMVS is not supported)");
  parser->Add("pmvs_option_name", pmvs_option_name, "accepted for COLMAP compatibility (PMVS only)");
  parser->Add("config_path", &run->config_path, "patch-match.cfg to use instead of stereo/patch-match.cfg");
  AddPatchMatchOptions(parser, &run->colmap_options, &run->options);
}

}  // namespace mpmvs

#pragma once
// Options of mp_patch_match_stereo: COLMAP's --PatchMatchStereo.* (those mp-mvs honours)
// and the method's own --MPMVS.* (defaults: docs/algorithm.md §0).
#include <cstdint>
#include <string>

namespace mpmvs {

// COLMAP's PatchMatchStereo options that keep their COLMAP meaning.
struct PatchMatchStereoOptions {
  int max_image_size = -1;      // down-scale so max(w, h) <= this (-1: off)
  std::string gpu_index = "-1";  // -1: first usable GPU, else the CPU backend
  double depth_min = -1;        // -1: from the sparse points
  double depth_max = -1;
  bool geom_consistency = true;  // run the geometric stages and write .geometric.bin
  bool filter = false;           // COLMAP-style output filter (off: mp-mvs default, §0)
  double filter_min_ncc = 0.1;
  double filter_min_triangulation_angle = 3.0;
  int filter_min_num_consistent = 2;
  double filter_geom_consistency_max_cost = 1.0;
  double cache_size = 32;  // GB for cached images and maps
  bool write_consistency_graph = false;
  bool allow_missing_files = false;
  int num_threads = -1;  // CPU backend threads (-1: all cores)
  double min_triangulation_angle = 1.0;  // __auto__ source selection (degrees)

  bool Check(std::string* error) const;
};

enum class PlanarPriorMode { kNone, kPhotometric, kGeometric };

// MP-MVS method options (--MPMVS.*).
struct MpMvsOptions {
  int max_window_scale = 2;          // S_max: windows 2^S*10+1 for S = S_max..0 (mPM)
  int iterations_per_scale = 3;      // photometric iterations per window scale
  bool distant_sampling = true;      // rs: MP-MVS distant checkerboard; false: ACMH pattern
  std::string planar_prior = "geometric";  // none | photometric (ACMP, pp) | geometric (gp)
  int geom_iterations = 2;           // per geometric pass
  int prior_iterations = 3;
  // gp: rounds of (planar prior from the last geometric pass, geometric pass); 1 is the paper.
  int prior_rounds = 2;
  double geom_weight = 0.2;          // lambda
  double geom_max_error = 2.0;       // clamp of the reprojection error (px)
  double prior_max_photo_cost = 0.2;  // gp vertex: m_p <
  double prior_max_geom_error = 1.0;  // gp vertex: m_g < (px)
  double prior_max_cost_acmp = 0.1;   // pp vertex: cost <
  int prior_cell_size = 5;
  int prior_points_per_cell = 3;      // gp; pp uses 1 (ACMP)
  // Each prior triangle takes the plane that the vertices around it vote for, among its
  // neighbours' planes and its vertices' tangent planes (false: its own plane, the paper).
  bool prior_plane_vote = true;
  // gp: the source views' vertices outside the reference image join its prior triangulation
  // (false: the reference's own vertices only, the paper).
  bool prior_source_vertices = true;
  // gp, first prior round: a pixel where the depth map's inverse depth bends by more than this
  // (relative second difference over +-3 px) is no prior vertex (0: off, the paper).
  double prior_vertex_bend = 0.01;
  // ACMP's beta: the weight of the photometric cost in the prior run's score, exp(-C^2/beta).
  // 0.18 is ACMP's; a large beta lets the prior decide wherever the views cannot.
  double prior_beta = 8;
  // Photometric cost floored at the reference's noise level in the geometric and prior
  // stages, so that noise-fitted planes do not beat consistent ones on untextured surfaces.
  bool noise_floor = true;
  double refinement_rho = 0.02;
  // A pixel whose update moved its plane by at most 0.5 % in depth and 3 degrees skips its
  // next this many updates at the same window scale (kernels/DESIGN.md 27): a third fewer
  // cost samples at the same Middlebury scores, but the synthetic rooms' ceilings lose, so
  // 0 (every pixel in every pass, the paper) is the default.
  int settled_pixel_skips = 0;
  // The written depth of a pixel must be confirmed by at least this many source views' final
  // depth maps (within 1 %, as COLMAP's stereo_fusion checks); 0: no check (the paper).
  int depth_check_views = 1;
  // Bilateral weights: grey difference + this x the smoothed chroma difference of the
  // reference (kernels/DESIGN.md item 13). 0: grey only, as ACMH / the MP-MVS code.
  double chroma_weight = 8;
  int max_source_images = 20;
  int seed = 1;
  bool overwrite = false;             // recompute outputs that already exist
  bool write_pictures = true;         // depth/normal PNGs in stereo/mpmvs/pictures
  // Splitting a run over processes (pipeline/shard.h); the maps do not depend on the split.
  std::string shard;                  // "i/n": this process runs shard i of n ("": all)
  std::string image_list_path;        // only these reference images ("": all)
  std::string stage = "all";          // one stage (photometric, geometric1, prior, ...) or all
  int claim_lease = 600;              // seconds a work claim of a silent other host is honoured

  PlanarPriorMode PriorMode() const;
  bool Check(std::string* error) const;
};

}  // namespace mpmvs

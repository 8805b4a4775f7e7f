#pragma once
// Options of mp_patch_match_stereo, each declared once, in the tables below: COLMAP's
// --PatchMatchStereo.* (those mp-mvs honours, and those it accepts and ignores) and the
// method's own --MPMVS.*. The option structs, the command-line registration
// (cli/patch_match_flags.cc), Check(), the state fingerprint, the presets, `-h` and
// docs/options.md are all made from these tables: adding an option is one line here plus the
// code that uses it.
#include <functional>
#include <string>

#include "colmap_ext/options/option_spec.h"

namespace mpmvs {

// COLMAP's general options, which every COLMAP command takes (its OptionManager's project,
// log and random options). X(TYPE, NAME, DEFAULT, RANGE, EFFECT, HELP)
#define MPMVS_GENERAL_OPTIONS(X)                                                                                       \
  X(std::string, project_path, "", OptionRange::Any(), kRun,                                                           \
    "INI project file read before the command line: top-level keys (workspace_path = dense) and [Section] keys "   \
    "(--Section.key); the command line overrides the file (COLMAP ignores the command line then)")                 \
  X(bool, log_to_stderr, false, OptionRange::Any(), kRun,                                                              \
    "1 = every log line on stderr; 0 = information on stdout, warnings and errors on stderr")                          \
  X(int, log_level, 2, OptionRange::Any(), kRun,                                                                       \
    "COLMAP's verbosity: 2 (and above) logs each image's sources, planar prior and depth check, 1 only a progress " \
    "line per image and stage, 0 (and below) only stages, summaries, warnings and errors")                             \
  X(int, random_seed, 0, OptionRange::AtLeast(-1), kRun,                                                    \
    "COLMAP's seed, counted from COLMAP's default 0: sets --MPMVS.seed to random_seed + 1 (so 0 runs mp-mvs's "        \
    "default seed 1) unless --MPMVS.seed is given; -1 (COLMAP: from the clock) keeps the seed, with a warning, as "     \
    "resumed runs and shards must draw the same random streams")

// COLMAP's PatchMatchStereo options that keep their COLMAP meaning.
// X(TYPE, NAME, DEFAULT, RANGE, EFFECT, HELP)
#define MPMVS_COLMAP_OPTIONS(X)                                                                                        \
  X(int, max_image_size, -1, OptionRange::MinusOneOrAbove(0), kInput,                                                  \
    "down-scale images so that max(width, height) <= this; -1 = full size")                                            \
  X(std::string, gpu_index, "-1", OptionRange::Any(), kRun,                                                            \
    "-1 = the first usable GPU, else the CPU backend; a GPU index (comma-separated list of integers >= -1)")           \
  X(double, depth_min, -1, OptionRange::OpenClosed(1e-6, 1e10).OrMinusOne(), kInput, "-1 = from the sparse points")    \
  X(double, depth_max, -1, OptionRange::OpenClosed(1e-6, 1e10).OrMinusOne(), kInput, "-1 = from the sparse points")    \
  X(bool, geom_consistency, true, OptionRange::Any(), kResult,                                                         \
    "run the geometric stages and write .geometric.bin")                                                               \
  X(bool, filter, false, OptionRange::Any(), kResult,                                                                  \
    "COLMAP-style filter of the written maps; off by default here, on in COLMAP: the depth_check stage already "    \
    "keeps only depths that a source's map confirms, and the filter's NCC test is least reliable on the plain "     \
    "surfaces the planar prior fills (docs/algorithm.md 9.2)")                                                         \
  X(double, filter_min_ncc, 0.1, OptionRange::Closed(-1, 1), kResult, "filter: minimum NCC")                           \
  X(double, filter_min_triangulation_angle, 3.0, OptionRange::Closed(0, 180), kResult,                                 \
    "filter: minimum triangulation angle (degrees)")                                                                   \
  X(int, filter_min_num_consistent, 2, OptionRange::Closed(0, 32), kResult,                                            \
    "filter: minimum number of consistent source views")                                                               \
  X(double, filter_geom_consistency_max_cost, 1.0, OptionRange::Closed(0, 100), kResult,                               \
    "filter: maximum forward-backward reprojection error (px)")                                                        \
  X(double, cache_size, 32, OptionRange::Above(0), kRun,                                                               \
    "GB of images and maps kept in memory; more than this machine's memory is clamped to it")                          \
  X(bool, write_consistency_graph, false, OptionRange::Any(), kRun,                                                    \
    "write stereo/consistency_graphs/ beside the maps")                                                                \
  X(bool, allow_missing_files, false, OptionRange::Any(), kInput,                                                      \
    "drop sources whose image or maps are missing instead of failing")                                                 \
  X(int, num_threads, -1, OptionRange::MinusOneOrAbove(0), kRun, "CPU threads; -1 = all cores")                        \
  X(double, min_triangulation_angle, 1.0, OptionRange::ClosedOpen(0, 180), kInput,                                     \
    "degrees; the __auto__ source selection of patch-match.cfg")

// COLMAP's PatchMatchStereo options that describe COLMAP's own algorithm: accepted and
// ignored with a warning naming what to use instead. X(NAME, HINT)
#define MPMVS_COLMAP_IGNORED_OPTIONS(X)                                                                                \
  X(window_radius, "use --MPMVS.max_window_scale (windows 11/21/41 px)")                                               \
  X(window_step, "use --MPMVS.max_window_scale (6x6 samples per window)")                                              \
  X(sigma_spatial, "the bilateral weights are MP-MVS's (sigma_s = 5)")                                                 \
  X(sigma_color, "the bilateral weights are MP-MVS's (sigma_c = 2.5)")                                                 \
  X(num_samples, "view selection draws 15 samples (ACMH)")                                                             \
  X(ncc_sigma, "view selection is ACMH's")                                                                             \
  X(incident_angle_sigma, "view selection is ACMH's")                                                                  \
  X(num_iterations, "use --MPMVS.iterations_per_scale / --MPMVS.geom_iterations")                                      \
  X(geom_consistency_regularizer, "use --MPMVS.geom_weight")                                                           \
  X(geom_consistency_max_cost, "use --MPMVS.geom_max_error")

// The method's options. FAST and PAPER: the values of `--MPMVS.preset fast` (6 iterations
// of the default's 21, one prior round, candidates costed in fewer views: docs/results.md) and
// `--MPMVS.preset paper` (MP-MVS as published).
// The options that change results come first, in the order of the state fingerprint (which
// must not change: states written by earlier builds stay valid).
// X(TYPE, NAME, DEFAULT, FAST, PAPER, RANGE, EFFECT, HELP)
#define MPMVS_METHOD_OPTIONS(X)                                                                                        \
  X(int, max_window_scale, 2, 2, 2, OptionRange::Closed(0, 4), kResult,                                                \
    "mPM: windows of 2^S*10+1 px for S = max..0 (41, 21, 11 px), 6x6 samples each; 0 = single 11 px window")           \
  X(int, iterations_per_scale, 3, 1, 3, OptionRange::Closed(1, 100), kResult,                                          \
    "photometric iterations per window scale (tau restarts at each scale)")                                            \
  X(bool, distant_sampling, true, true, true, OptionRange::Any(), kResult,                                             \
    "1 = MP-MVS distant checkerboard sampling, 0 = ACMH's pattern")                                                    \
  X(std::string, planar_prior, "geometric", "geometric", "geometric",                                                  \
    OptionRange::OneOf("none|photometric|geometric"), kResult,                                                         \
    "geometric (MP-MVS), photometric (ACMP) or none")                                                                  \
  X(int, geom_iterations, 2, 1, 2, OptionRange::Closed(1, 100), kResult, "iterations of each geometric pass")          \
  X(int, prior_iterations, 3, 1, 3, OptionRange::Closed(1, 100), kResult, "iterations of each prior-assisted run")     \
  X(int, prior_rounds, 2, 1, 1, OptionRange::Closed(1, 4), kResult,                                                    \
    "geometric prior: rounds of (planar prior from the last geometric pass, geometric pass); 1 = the paper")           \
  X(double, geom_weight, 0.2, 0.2, 0.2, OptionRange::Closed(0, 100), kResult, "lambda of the geometric term")          \
  X(double, geom_max_error, 2.0, 2.0, 2.0, OptionRange::OpenClosed(0, 100), kResult,                                   \
    "clamp of the reprojection error (px)")                                                                            \
  X(double, prior_max_photo_cost, 0.2, 0.2, 0.2, OptionRange::Closed(0, 2), kResult,                                   \
    "geometric prior vertices: photometric cost m_p below this")                                                       \
  X(double, prior_max_geom_error, 1.0, 1.0, 1.0, OptionRange::Closed(0, 100), kResult,                                 \
    "geometric prior vertices: reprojection error m_g below this (px)")                                                \
  X(double, prior_max_cost_acmp, 0.1, 0.1, 0.1, OptionRange::Closed(0, 2), kResult,                                    \
    "photometric (ACMP) prior vertices: cost below this")                                                              \
  X(int, prior_cell_size, 5, 5, 5, OptionRange::Closed(1, 100), kResult, "prior vertices: grid cell size (px)")        \
  X(int, prior_points_per_cell, 3, 3, 3, OptionRange::Closed(1, 100), kResult,                                         \
    "geometric prior vertices per cell (the photometric prior takes 1, as ACMP)")                                      \
  X(bool, prior_plane_vote, true, true, false, OptionRange::Any(), kResult,                                            \
    "each prior triangle takes the plane that the vertices around it vote for, among its neighbours' and its "         \
    "vertices' planes, or a dominant plane of the image up to 3 % behind it; 0 = its own plane through its three "     \
    "vertices (paper)")                                                                                                \
  X(double, prior_corner_colour_match, 12, 12, 0, OptionRange::Closed(0, 255), kResult,                               \
    "with the plane vote, a prior triangle whose corners' depths lie over 5 % apart (an object and the surface "      \
    "behind): a pixel whose colour difference (grey levels + chroma_weight x colour, as the NCC weights) to a "       \
    "corner in a plain patch on a dominant plane is under this takes that plane, unless a corner off it matches "      \
    "within 4 more; 0 = the triangle's plane (paper)")                                                                 \
  X(bool, prior_source_vertices, true, true, false, OptionRange::Any(), kResult,                                       \
    "geometric prior: source views' vertices just outside the reference image join its triangulation; 0 = the "        \
    "reference's own vertices only (paper)")                                                                           \
  X(double, prior_vertex_bend, 0.01, 0.01, 0, OptionRange::Closed(0, 1), kResult,                                      \
    "first geometric prior: a pixel where the inverse depth bends by more than this (relative second difference "      \
    "over +-3 px) is no vertex; 0 = off (paper)")                                                                      \
  X(double, prior_beta, 8, 8, 0.18, OptionRange::OpenClosed(0, 1000), kResult,                                         \
    "beta of the prior run's score exp(-C^2/beta)*(gamma + agreement); with noise_floor on it falls with the "         \
    "window's texture towards 0.18 and the prior acts only on plain windows; 0.18 = ACMP")                             \
  X(bool, noise_floor, true, true, false, OptionRange::Any(), kResult,                                                 \
    "floor the photometric cost at the reference's noise level in the geometric and prior stages; 0 = paper")          \
  X(double, refinement_rho, 0.02, 0.02, 0.02, OptionRange::Open(0, 1), kResult,                                        \
    "relative depth perturbation of the refinement's random planes")                                                   \
  X(int, depth_check_views, 1, 1, 0, OptionRange::Closed(0, 32), kResult,                                              \
    "source views whose final depth maps must confirm a written depth within 1 %, more where the sparse points' "     \
    "reprojection error says the poses are less exact or the sources' maps hold the image's depths only roughly "    \
    "(and depth segments under 100 px go); 0 = no depth_check stage (paper)")                                        \
  X(double, chroma_weight, 8, 8, 0, OptionRange::Closed(0, 1000), kResult,                                             \
    "bilateral NCC weights: grey difference + this x the reference's smoothed colour difference; 0 = grey only "       \
    "(paper)")                                                                                                         \
  X(int, max_source_images, 20, 20, 20, OptionRange::Closed(1, 32), kResult, "source images used per reference")       \
  X(int, seed, 1, 1, 1, OptionRange::Closed(0, 2147483647), kResult,                                                   \
    "random streams (results do not depend on thread count)")                                                          \
  X(int, settled_pixel_skips, 0, 0, 0, OptionRange::Closed(0, 255), kResultWhenSet,                                    \
    "a pixel whose update moved its plane by at most 0.5 % in depth and 3 degrees skips this many of its next "        \
    "updates at the same window scale; 0 = every pixel in every pass (paper)")                                         \
  X(int, costed_views, 0, 3, 0, OptionRange::Closed(0, 32), kResultWhenSet,                                            \
    "propagated candidates are costed in at most this many source views: those the pixel and its neighbours "          \
    "selected last, one more explored in turn; 0 = every source view (paper)")                                         \
  X(int, half_resolution_scales, 2, 2, 0, OptionRange::Closed(0, 4), kResultWhenSet,                                 \
    "mPM: the largest this many window scales (at most max_window_scale) run on the images at half resolution "      \
    "with the window of one scale less, which covers the same part of the scene, at a quarter of the cost; "         \
    "0 = all at full resolution (paper)")                                                                              \
  X(bool, overwrite, false, false, false, OptionRange::Any(), kRun, "recompute outputs that already exist")            \
  X(std::string, write_pictures, "final", "final", "final", OptionRange::OneOf("final|all|none"), kRun,              \
    "PNGs in stereo/mpmvs/pictures: final = the depth and normal maps fusion reads, all = also every stage's depth " \
    "map, the photometric maps and the planar priors, none")                                                          \
  X(bool, keep_states, false, false, false, OptionRange::Any(), kRun,                                                 \
    "keep every stage's state in stereo/mpmvs; 0 = remove each once every stage that reads it has its results and " \
    "its maps are written (resuming and shards are unaffected)")                                                      \
  X(std::string, shard, "", "", "", OptionRange::Any(), kRun,                                                          \
    "i/n: run shard i of n of the reference images (balanced by pixels x sources); same maps as one process")          \
  X(std::string, image_list_path, "", "", "", OptionRange::Any(), kRun,                                                \
    "file naming the reference images to run, one per line")                                                           \
  X(std::string, stage, "all", "all", "all",                                                                           \
    OptionRange::NonEmpty("all or a stage name (photometric, geometric1, prior, geometric2, ..., depth_check)"),       \
    kRun,                                                                                                              \
    "all, or one stage whose inputs exist: photometric, geometric1, prior, geometric2, prior2, geometric3 "            \
    "(prior3, geometric4, ... with more prior_rounds), depth_check")                                                   \
  X(int, claim_lease, 600, 600, 600, OptionRange::Closed(1, 86400), kRun,                                              \
    "seconds before a work claim of a silent process on another host is taken over")

// Visit(visit) over every declared option of Options, for const and non-const objects alike:
// Options::VisitFields(self, visit) calls visit once per option of its table.
template <typename Options>
struct VisitableOptions {
  template <typename Visitor>
  void Visit(Visitor&& visit) { Options::VisitFields(static_cast<Options&>(*this), visit); }
  template <typename Visitor>
  void Visit(Visitor&& visit) const { Options::VisitFields(static_cast<const Options&>(*this), visit); }
};

// The fields of a COLMAP option table and visiting them as visit(spec, field).
#define MPMVS_FIELD(TYPE, NAME, DEFAULT, RANGE, EFFECT, HELP) TYPE NAME = DEFAULT;
#define MPMVS_VISIT(TYPE, NAME, DEFAULT, RANGE, EFFECT, HELP) \
  visit(OptionSpec{#NAME, RANGE, OptionEffect::EFFECT, HELP}, self.NAME);

struct PatchMatchStereoOptions : VisitableOptions<PatchMatchStereoOptions> {
  MPMVS_COLMAP_OPTIONS(MPMVS_FIELD)

  bool Check(std::string* error) const;

  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor& visit) {
    MPMVS_COLMAP_OPTIONS(MPMVS_VISIT)
  }
};

struct GeneralOptions : VisitableOptions<GeneralOptions> {
  MPMVS_GENERAL_OPTIONS(MPMVS_FIELD)

  bool Check(std::string* error) const;

  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor& visit) {
    MPMVS_GENERAL_OPTIONS(MPMVS_VISIT)
  }
};

#undef MPMVS_VISIT
#undef MPMVS_FIELD

enum class PlanarPriorMode { kNone, kPhotometric, kGeometric };

// Presets: named sets of --MPMVS values, in this order (OptionPresets::values).
constexpr const char* kPresetNames[] = {"default", "fast", "paper"};
constexpr int kNumPresets = 3;
constexpr int kPaperPreset = 2;  // MP-MVS as published
template <typename T>
struct OptionPresets {
  T values[kNumPresets];
  const T& at(int preset) const { return values[preset]; }
  const T& default_value() const { return values[0]; }
  const T& paper_value() const { return values[kPaperPreset]; }
};

struct MpMvsOptions : VisitableOptions<MpMvsOptions> {
#define MPMVS_FIELD(TYPE, NAME, DEFAULT, FAST, PAPER, RANGE, EFFECT, HELP) TYPE NAME = DEFAULT;
  MPMVS_METHOD_OPTIONS(MPMVS_FIELD)
#undef MPMVS_FIELD

  PlanarPriorMode PriorMode() const;
  bool Check(std::string* error) const;

  // Every declared option: visit(spec, field, presets), presets.at(k) its value in preset k.
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor& visit) {
#define MPMVS_VISIT(TYPE, NAME, DEFAULT, FAST, PAPER, RANGE, EFFECT, HELP)                                             \
  visit(OptionSpec{#NAME, RANGE, OptionEffect::EFFECT, HELP}, self.NAME,                                               \
        OptionPresets<TYPE>{{TYPE(DEFAULT), TYPE(FAST), TYPE(PAPER)}});
    MPMVS_METHOD_OPTIONS(MPMVS_VISIT)
#undef MPMVS_VISIT
  }
};

// A preset (kPresetNames) sets every option that changes results for which given(name) is
// false; options given explicitly keep their value, and so do the options of the run (kRun).
// False for an unknown preset.
std::string PresetNames();  // "default|fast|paper"
bool ApplyPreset(const std::string& preset, const std::function<bool(const std::string& name)>& given,
                 MpMvsOptions* options);

// --MPMVS.seed for COLMAP's --random_seed (MPMVS_GENERAL_OPTIONS): random_seed + 1, so that
// COLMAP's default seed gives mp-mvs's; -1 when random_seed asks for a seed from the clock.
int SeedForRandomSeed(int random_seed);

// The values of the options that change results, one "name value" line each in declaration
// order (doubles with 17 digits; kResultWhenSet options only away from their paper value): the
// options part of the state fingerprint (store/state_record.h).
std::string ResultOptionsText(const MpMvsOptions& options);
// The values of COLMAP's options that change results, one "PatchMatchStereo.name value" line
// each in declaration order: with the text above, part of the run's fingerprint
// (store/result_fingerprint.h), on which runs sharing a workspace must agree. Not part of a
// state's fingerprint: image size, depth range and sources enter each state's inputs hash,
// and the output filter acts only on the final maps.
// include_inputs false leaves out the options that act through the inputs (kInput).
std::string ResultOptionsText(const PatchMatchStereoOptions& options, bool include_inputs = true);

// docs/options.md: every option with its default, paper value, range and help.
std::string OptionsMarkdown();

}  // namespace mpmvs

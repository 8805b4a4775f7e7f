#pragma once
// Host API of the PatchMatch engine: one reference image, its sources, a schedule of
// iterations; the CPU backend runs it over all cores, the CUDA backend on a GPU. Plain data
// in, plain data out; no I/O.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/launch_layout.h"
#include "kernels/filter.h"
#include "kernels/patch_match_pixel.h"

namespace mpmvs {
namespace kernels {

// "No id": an image (or depth map) the CUDA session must not keep for later problems.
constexpr uint32_t kNoImageId = 0xffffffffu;

struct PatchMatchSource {
  ImageView image;
  Camera camera;
  const float* depth_map = nullptr;  // required for geometric schedules (camera size)
  // Device cache id of this view (cuda_session.h; the CPU backend ignores it): the same id
  // must mean the same image (and, within one depth_maps_stage, the same depth map) for the
  // whole session. kNoImageId: uploaded for this problem only.
  uint32_t image_id = kNoImageId;
};

struct PatchMatchProblem {
  uint32_t image_id = 0;  // feeds the random streams
  // Device cache id of ref_image, in the id space of PatchMatchSource::image_id (kept apart
  // from image_id, which any caller may set for its random streams). kNoImageId: not cached.
  uint32_t ref_image_id = kNoImageId;
  // The stage whose results the sources' depth maps are, so that a view's depth map from
  // stage k and from stage k+1 are different device cache entries; -1: not cached.
  int depth_maps_stage = -1;
  Camera ref_camera;
  ImageView ref_image;
  std::vector<PatchMatchSource> sources;
  float depth_min = 0.f, depth_max = 0.f;
  // Noise variance of ref_image (grey levels^2), for the schedule's photometric noise floor.
  float ref_noise_variance = 0.f;
  // Optional starting hypotheses (4 floats per pixel, d = 0 for none) and their costs.
  const float* init_plane = nullptr;
  const float* init_cost = nullptr;
  // Optional planar prior (4 floats per pixel + label per pixel).
  const float* prior_plane = nullptr;
  const uint8_t* prior_label = nullptr;
};

// One iteration = a black pass then a red pass, at a window scale, with the good-match
// threshold of iteration index tau_index (restarting per scale).
struct IterationSpec {
  int window_scale = 0;
  int tau_index = 0;
  // Runs on the images at half resolution (half_resolution.h): a prefix of a photometric
  // schedule, run by RunWithHalfResolutionStart; window_scale is the scale used there.
  bool half_resolution = false;
};

struct PatchMatchSchedule {
  std::vector<IterationSpec> iterations;
  PatternKind pattern = PatternKind::kDistant;
  bool geometric = false;
  bool use_prior = false;
  // The values of user options come from the run's plan (colmap_ext/options declares them
  // with their defaults); they have none here, and Check() refuses the zeros of those that
  // must be set.
  float geom_lambda = 0.f;     // --MPMVS.geom_weight
  float geom_error_clamp = 0.f;  // --MPMVS.geom_max_error (px)
  // Floor the photometric cost at the reference's noise level (PassParams::noise_variance).
  bool noise_floor = false;    // --MPMVS.noise_floor
  float prior_beta = 0.f;      // --MPMVS.prior_beta
  float refinement_rho = 0.f;  // --MPMVS.refinement_rho
  // Updates a pixel skips after an update that left its plane settled (PassParams::
  // settled_skips, kernels/DESIGN.md 27); 0: none (the paper).
  int settled_skips = 0;       // --MPMVS.settled_pixel_skips
  // Source views the propagated candidates are costed in (PassParams::costed_views); 0: all.
  int costed_views = 0;        // --MPMVS.costed_views
  uint64_t seed = 0;           // --MPMVS.seed
  int num_threads = -1;        // --PatchMatchStereo.num_threads (CPU backend: -1 = all cores)
  uint32_t stage_id = 0;       // distinguishes the random streams of different stages
  // Constants of the method (ACMP's prior, ACMH's good-match threshold), not options.
  float prior_gamma = 0.5f;
  float prior_sigma_normal_deg = 5.f;
  float tau0 = 0.8f;
  float tau_alpha = 90.f;

  // Throws std::invalid_argument with a message when inconsistent.
  void Check() const;
};

struct IterationStats {
  int window_scale = 0;
  int window_side = 0;
  // Ran on the images at half resolution (kernels/half_resolution.h): window_scale and
  // window_side count half-resolution pixels, and the window covers the one of scale + 1.
  bool half_resolution = false;
  PatternKind pattern = PatternKind::kDistant;
  float tau = 0.f;
  uint64_t ncc_evaluations = 0;  // view x hypothesis NCCs computed (36 samples each)
  double seconds = 0.0;
};

struct PatchMatchResult {
  int width = 0, height = 0;
  std::vector<float> plane;  // 4 per pixel
  std::vector<float> cost, photo_cost, geo_error;
  std::vector<uint32_t> view_mask;
  uint64_t init_ncc_evaluations = 0;
  std::vector<IterationStats> iterations;
};

// Called after every iteration with (done, total).
using ProgressCallback = std::function<void(int, int)>;

void RunPatchMatchCpu(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                      PatchMatchResult* result, const ProgressCallback& progress = nullptr);

// The most worker threads the CPU functions use: 4 per hardware thread (more only cost
// memory; results do not depend on the count). Larger requests are capped to it.
int MaxCpuThreads();

// Thrown by the CPU functions when the system refuses to start their worker threads (thread
// or memory limits); the threads already started have finished their work.
class ThreadStartError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The NCC cost the CPU backend runs, compiled with its flags (vectorised where the build
// allows), so tests can hold it against the shared scalar ComputeNccCost; and its name:
// "AVX-512", "AVX2" or "scalar". src.quads is used when set (MakeQuadImage).
float CpuBackendNccCost(const RefPatch& patch, const ImageView& src, const float H[9], int u, int v,
                        const WindowSpec& window);
const char* CpuBackendNccName();

// The GPU runtime of this build's GPU backend: "CUDA" (also in builds without one) or "HIP"
// (kernels/*.cu compiled by hipcc for AMD GPUs), for the messages that name the device.
const char* GpuRuntimeName();

// How many CUDA devices the driver reports; 0 without a driver, a device or CUDA in the build.
int CudaDeviceCount();
// Whether a CUDA device can be used (false with the reason in *why when the build has no
// CUDA or no device/driver is present: any CUDA error counts as "no device").
bool CudaDeviceAvailable(int gpu_index, std::string* why);
// Same contract as RunPatchMatchCpu; throws std::runtime_error when CUDA is unusable.
void RunPatchMatchCuda(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                       int gpu_index, PatchMatchResult* result,
                       const ProgressCallback& progress = nullptr);

// COLMAP-style filter of a finished result (host, all cores): filtered pixels get
// photometric cost 2, i.e. no depth in ExtractDepthNormalMaps. geometric: also require
// forward-backward consistency with the sources' depth maps. Returns the pixels removed.
size_t FilterResultCpu(const PatchMatchProblem& problem, bool geometric, const FilterParams& filter,
                       int num_threads, PatchMatchResult* result);

// Per pixel, the relative difference within which min_views sources' depth maps confirm its
// depth (PixelConfirmingDifference; kNoDepthDifference where none can): W*H entries, all cores.
std::vector<float> ConfirmingDifferencesCpu(const PatchMatchProblem& problem, int min_views, int num_threads,
                                            const PatchMatchResult& result);

// Invalidates (photometric cost 2) the valid pixels whose confirming difference (above) is
// not under max_relative_error; returns how many.
size_t InvalidateUnconfirmedDepths(const std::vector<float>& confirming_differences, float max_relative_error,
                                   PatchMatchResult* result);

// Sets result->view_mask, per pixel, to the sources (bit s: problem.sources[s]) whose depth
// maps confirm its depth within max_relative_error (PixelConfirmingViews); 0 without one.
void MarkConfirmingViewsCpu(const PatchMatchProblem& problem, float max_relative_error, int num_threads,
                            PatchMatchResult* result);

// 1 where the reference image's window of `window` around the pixel is plain (PlainWindow),
// W*H entries (host, all cores).
std::vector<uint8_t> PlainWindowMaskCpu(const ImageView& ref, const WindowSpec& window,
                                        float noise_variance, int num_threads);

// Median filter of the result's depths (median_filter.h), two checkerboard passes, all
// cores (num_threads <= 0: all).
void MedianFilterDepthsCpu(const Camera& camera, float depth_min, float depth_max, int num_threads,
                           PatchMatchResult* result);

// Marks pixels whose geometric term is saturated (no selected source view reprojects
// within geom_max_error) as invalid (photometric cost 2); returns how many. Such pixels are
// occluded or outside every source view in practice (colmap_ext/DESIGN.md).
size_t InvalidateGeometricallyInconsistent(float geom_max_error, PatchMatchResult* result);

// Depth (W*H, 0 = invalid) and camera-frame normal (3 planes of W*H, COLMAP layout) maps.
void ExtractDepthNormalMaps(const PatchMatchProblem& problem, const PatchMatchResult& result,
                            std::vector<float>* depth, std::vector<float>* normal);

// Builds the per-pass parameters shared by both backends (sources must outlive the params).
PassParams MakePassParams(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                          const SourceView* sources);
// SourceViews (with relative poses) for a problem.
std::vector<SourceView> MakeSourceViews(const PatchMatchProblem& problem);

// Pass setup shared by both backends, so they draw the same random streams and use the same
// window and good-match threshold in every pass. The initialisation pass uses the window
// of the first iteration.
void SetInitPass(const PatchMatchSchedule& schedule, PassParams* params);
// Checkerboard pass `color` (0 = black, 1 = red; black runs first) of iteration `iteration`.
void SetCheckerboardPass(const PatchMatchSchedule& schedule, int iteration, int color,
                         PassParams* params);
IterationStats MakeIterationStats(const PatchMatchSchedule& schedule, int iteration,
                                  uint64_t ncc_evaluations, double seconds);
// Sizes result's buffers for a width x height reference image (StateLayout of
// launch_layout.h) with the values before initialisation; clears the statistics.
void ResetResult(int width, int height, PatchMatchResult* result);

}  // namespace kernels
}  // namespace mpmvs

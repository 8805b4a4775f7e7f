// CPU backend: runs the shared per-pixel functions of patch_match_pixel.h over all cores.
// Pixels of one checkerboard colour are independent, so rows are handed out dynamically;
// results do not depend on the thread count (counter-based random numbers).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "kernels/median_filter.h"
#include "kernels/ncc_simd.h"
#include "kernels/pass_loop.h"
#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {
namespace {

#if defined(MPMVS_HAVE_SIMD_NCC)
using CpuNcc = SimdNcc;
#else
using CpuNcc = ScalarNcc;
#endif

int HardwareThreads() {
  const unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 1;
}

int ResolveThreads(int requested) {
  return requested > 0 ? std::min(requested, MaxCpuThreads()) : HardwareThreads();
}

// Calls fn(row, &counter) for every row, on num_threads threads (at most one per row);
// returns the summed counter.
template <typename Fn>
uint64_t ParallelRows(int num_rows, int num_threads, const Fn& fn) {
  num_threads = std::max(1, std::min(num_threads, num_rows));
  std::atomic<int> next{0};
  std::vector<uint64_t> counters(num_threads, 0);
  auto worker = [&](int t) {
    uint32_t local = 0;
    uint64_t total = 0;
    for (int row = next.fetch_add(1); row < num_rows; row = next.fetch_add(1)) {
      local = 0;
      fn(row, &local);
      total += local;
    }
    counters[t] = total;
  };
  if (num_threads == 1) {
    worker(0);
  } else {
    std::vector<std::thread> threads;
    try {
      threads.reserve(num_threads);
      for (int t = 0; t < num_threads; ++t) threads.emplace_back(worker, t);
    } catch (const std::exception& e) {
      // Destroying a joinable std::thread would std::terminate: let the started threads
      // finish the rows, then report.
      for (auto& th : threads) th.join();
      throw ThreadStartError("could not start CPU worker thread " + std::to_string(threads.size() + 1) +
                             " of " + std::to_string(num_threads) + " (" + e.what() +
                             "): the system's thread or memory limits allow fewer threads");
    }
    for (auto& th : threads) th.join();
  }
  uint64_t sum = 0;
  for (uint64_t c : counters) sum += c;
  return sum;
}

// RunPassLoop's passes on the host cores: rows of the image handed out to threads.
class CpuPasses {
 public:
  CpuPasses(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
            PatchMatchResult* result, const ProgressCallback& progress)
      : problem_(problem),
        schedule_(schedule),
        result_(result),
        progress_(progress),
        threads_(ResolveThreads(schedule.num_threads)),
        width_(problem.ref_camera.width),
        height_(problem.ref_camera.height) {
    ResetResult(width_, height_, result);
    state_.plane = result->plane.data();
    state_.cost = result->cost.data();
    state_.photo_cost = result->photo_cost.data();
    state_.geo_error = result->geo_error.data();
    state_.view_mask = result->view_mask.data();
    if (schedule.settled_skips > 0) {
      skips_left_.assign(static_cast<size_t>(width_) * height_, 0);
      state_.skips_left = skips_left_.data();
    }
  }

  void Initialize(const PassParams& params) {
    result_->init_ncc_evaluations = ParallelRows(height_, threads_, [&](int v, uint32_t* count) {
      for (int u = 0; u < width_; ++u) {
        InitializePixel<CpuNcc>(params, state_, problem_.init_plane, problem_.init_cost, u, v,
                                count);
      }
    });
  }

  void BeginIteration(int) {
    start_ = std::chrono::steady_clock::now();
    evaluations_ = 0;
  }

  void Checkerboard(const PassParams& params, int) {
    const int color = params.color;
    evaluations_ += ParallelRows(height_, threads_, [&](int v, uint32_t* count) {
      for (int u = CheckerboardRowBegin(v, color); u < width_; u += 2) {
        UpdatePixel<CpuNcc>(params, state_, u, v, count);
      }
    });
  }

  void EndIteration(int iteration) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    result_->iterations.push_back(MakeIterationStats(schedule_, iteration, evaluations_, seconds));
    if (progress_) progress_(iteration + 1, static_cast<int>(schedule_.iterations.size()));
  }

 private:
  const PatchMatchProblem& problem_;
  const PatchMatchSchedule& schedule_;
  PatchMatchResult* result_;
  const ProgressCallback& progress_;
  const int threads_;
  const int width_, height_;
  PixelState state_;
  std::vector<uint8_t> skips_left_;  // PixelState::skips_left
  std::chrono::steady_clock::time_point start_;
  uint64_t evaluations_ = 0;
};

}  // namespace

int MaxCpuThreads() { return 4 * HardwareThreads(); }

void RunPatchMatchCpu(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                      PatchMatchResult* result, const ProgressCallback& progress) {
  schedule.Check();
  std::vector<SourceView> sources = MakeSourceViews(problem);
#if defined(MPMVS_HAVE_SIMD_NCC)
  // Packed-neighbour copies of 8-bit source images for the vectorised NCC (+1x image memory).
  std::vector<std::vector<uint32_t>> quads(sources.size());
  for (size_t s = 0; s < sources.size(); ++s) {
    if (MakeQuadImage(sources[s].image, &quads[s])) sources[s].image.quads = quads[s].data();
  }
#endif
  const PassParams params = MakePassParams(problem, schedule, sources.data());
  CpuPasses passes(problem, schedule, result, progress);
  RunPassLoop(schedule, params, &passes);
}

float CpuBackendNccCost(const RefPatch& patch, const ImageView& src, const float H[9], int u, int v,
                        const WindowSpec& window) {
  return NccCost<CpuNcc>(patch, src, H, u, v, window);
}

const char* CpuBackendNccName() {
#if defined(MPMVS_HAVE_SIMD_NCC) && defined(__AVX512F__) && defined(__AVX512VL__)
  return "AVX-512";
#elif defined(MPMVS_HAVE_SIMD_NCC)
  return "AVX2";
#else
  return "scalar";
#endif
}

std::vector<uint8_t> PlainWindowMaskCpu(const ImageView& ref, const WindowSpec& window,
                                        float noise_variance, int num_threads) {
  std::vector<uint8_t> plain(static_cast<size_t>(ref.width) * ref.height, 0);
  ParallelRows(ref.height, ResolveThreads(num_threads), [&](int v, uint32_t*) {
    RefPatch patch;
    for (int u = 0; u < ref.width; ++u) {
      ComputeRefPatch(ref, u, v, window, &patch, /*with_texture=*/true);
      plain[static_cast<size_t>(v) * ref.width + u] = PlainWindow(patch, noise_variance);
    }
  });
  return plain;
}

void MedianFilterDepthsCpu(const Camera& camera, float depth_min, float depth_max, int num_threads,
                           PatchMatchResult* result) {
  MedianFilterInput in;
  in.camera = camera;
  in.depth_min = depth_min;
  in.depth_max = depth_max;
  in.plane = result->plane.data();
  in.cost = result->cost.data();
  in.photo_cost = result->photo_cost.data();
  const int threads = ResolveThreads(num_threads);
  for (int color = 0; color < 2; ++color) {  // the second pass sees the first's output
    ParallelRows(result->height, threads, [&](int v, uint32_t*) {
      for (int u = (v + color) % 2; u < result->width; u += 2) MedianFilterPixel(in, u, v);
    });
  }
}

namespace {

// per_pixel(state, u, v) of every pixel of the result (state points into it, read only), all
// cores: W*H values.
template <class T, class PerPixel>
std::vector<T> MapPixels(int num_threads, const PatchMatchResult& result, const PerPixel& per_pixel) {
  PixelState state;
  state.plane = const_cast<float*>(result.plane.data());
  state.photo_cost = const_cast<float*>(result.photo_cost.data());
  const int W = result.width;
  std::vector<T> values(static_cast<size_t>(W) * result.height);
  ParallelRows(result.height, ResolveThreads(num_threads), [&](int v, uint32_t*) {
    for (int u = 0; u < W; ++u) values[static_cast<size_t>(v) * W + u] = per_pixel(state, u, v);
  });
  return values;
}

// Invalidates (photometric cost 2) each pixel with an estimate that keep(state, u, v) rejects,
// all pixels decided before any changes; returns how many.
template <class Keep>
size_t InvalidateRejectedPixels(int num_threads, PatchMatchResult* result, const Keep& keep_pixel) {
  const std::vector<uint8_t> keep = MapPixels<uint8_t>(num_threads, *result, keep_pixel);
  size_t removed = 0;
  for (size_t i = 0; i < keep.size(); ++i) {
    if (!keep[i] && result->photo_cost[i] < kInvalidCost) {
      result->photo_cost[i] = kInvalidCost;
      ++removed;
    }
  }
  return removed;
}

// Parameters of a geometric pass: what the depth check reads of the sources' depth maps.
PassParams SourceDepthParams(const PatchMatchProblem& problem, const std::vector<SourceView>& sources) {
  PatchMatchSchedule schedule;
  schedule.geometric = true;
  return MakePassParams(problem, schedule, sources.data());
}

}  // namespace

size_t FilterResultCpu(const PatchMatchProblem& problem, bool geometric, const FilterParams& filter,
                       int num_threads, PatchMatchResult* result) {
  const std::vector<SourceView> sources = MakeSourceViews(problem);
  PatchMatchSchedule schedule;
  schedule.geometric = geometric;
  // Reprojection errors clamp above the filter's threshold, so the clamp never passes a view.
  schedule.geom_error_clamp = filter.max_reprojection_error + 1.f;
  PassParams params = MakePassParams(problem, schedule, sources.data());
  params.window = WindowForScale(0);  // once, not per pixel and view (36 square roots)
  return InvalidateRejectedPixels(num_threads, result, [&](const PixelState& state, int u, int v) {
    return PixelPassesFilter<CpuNcc>(params, filter, state, u, v);
  });
}

std::vector<float> ConfirmingDifferencesCpu(const PatchMatchProblem& problem, int min_views, int num_threads,
                                            const PatchMatchResult& result) {
  const std::vector<SourceView> sources = MakeSourceViews(problem);
  const PassParams params = SourceDepthParams(problem, sources);
  return MapPixels<float>(num_threads, result, [&](const PixelState& state, int u, int v) {
    return PixelConfirmingDifference(params, state, u, v, min_views);
  });
}

size_t InvalidateUnconfirmedDepths(const std::vector<float>& confirming_differences, float max_relative_error,
                                   PatchMatchResult* result) {
  const int W = result->width;
  return InvalidateRejectedPixels(1, result, [&](const PixelState&, int u, int v) {
    return confirming_differences[static_cast<size_t>(v) * W + u] < max_relative_error;
  });
}

void MarkConfirmingViewsCpu(const PatchMatchProblem& problem, float max_relative_error, int num_threads,
                            PatchMatchResult* result) {
  const std::vector<SourceView> sources = MakeSourceViews(problem);
  const PassParams params = SourceDepthParams(problem, sources);
  result->view_mask = MapPixels<uint32_t>(num_threads, *result, [&](const PixelState& state, int u, int v) {
    return PixelConfirmingViews(params, state, u, v, max_relative_error);
  });
}

}  // namespace kernels
}  // namespace mpmvs

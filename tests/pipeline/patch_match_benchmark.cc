// Speed and memory figures of the PatchMatch engine (not a test: it prints numbers).
//   build/tests/mpmvs_benchmarks
// Counters: seconds per depth map, Mpix*iterations/s, cost samples/s (view x hypothesis
// NCCs actually evaluated x 36 window samples / wall second), cost samples per pixel and
// iteration, peak resident memory; for whole runs also cores busy (CPU time / wall time) and
// the share of the wall time outside the parallel work.
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <thread>

#include "tests/kernel_schedule_util.h"
#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/colmap_runner.h"
#include "colmap_ext/util/file_util.h"
#include "kernels/patch_match.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;

double PeakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

// Resident memory now (not the peak), from /proc/self/statm.
double ResidentMiB() {
  long pages = 0, resident = 0;
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (f) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return resident * static_cast<double>(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// Runs body in a forked child (so that its memory is its own); whether it exited 0. usage
// (optional) receives the child's resource usage, its peak resident memory included.
bool RunInChildProcess(const std::function<void()>& body, rusage* usage) {
  const pid_t child = ::fork();
  if (child == 0) {
    try {
      body();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      ::_exit(1);
    }
    ::_exit(0);
  }
  int status = 0;
  rusage ignored{};
  return child > 0 && ::wait4(child, &status, 0, usage ? usage : &ignored) == child && WIFEXITED(status) &&
         WEXITSTATUS(status) == 0;
}

std::string ScratchDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "mpmvs_bench" / name;
  fs::create_directories(dir);
  return dir.string();
}

// The synthetic plane scene in a scratch directory, generated once.
std::string PlaneScene(const std::string& name, int width, int height, int num_views, double tilt_deg,
                       int supersampling) {
  const std::string dir = ScratchDir(name);
  if (!FileExists(dir + "/gt/scene_info.json")) {
    SyntheticSceneOptions o;
    o.scene = "plane";
    o.width = width;
    o.height = height;
    o.num_views = num_views;
    o.plane_tilt_deg = tilt_deg;
    o.supersampling = supersampling;
    o.write_gt_points = false;  // the benchmarks read the images and cameras only
    GenerateSyntheticScene(o, dir);
  }
  return dir;
}

// View 0 of a workspace as reference with views 1..num_sources as sources (their images are
// kept in *images, which must outlive the problem).
kernels::PatchMatchProblem ViewZeroProblem(const DenseWorkspace& ws, int num_sources, std::vector<GrayImage>* images) {
  images->clear();
  for (int i = 0; i <= num_sources; ++i) images->push_back(ws.ReadGray(i));
  kernels::PatchMatchProblem problem;
  problem.ref_camera = ToKernelCamera(ws.views[0]);
  problem.ref_image = {(*images)[0].data.data(), (*images)[0].width, (*images)[0].height};
  for (int s = 1; s <= num_sources; ++s) {
    const GrayImage& img = (*images)[s];
    problem.sources.push_back({{img.data.data(), img.width, img.height}, ToKernelCamera(ws.views[s]), nullptr});
  }
  problem.depth_min = ws.views[0].depth_min;
  problem.depth_max = ws.views[0].depth_max;
  return problem;
}

// Photometric mPM stage (9 iterations) of one 640x480 reference image with 4 sources of the
// synthetic plane scene, on `threads` threads.
void BM_PhotometricStage(benchmark::State& state) {
  static const std::string dir = PlaneScene("plane640", 640, 480, 5, 40.0, 3);
  const DenseWorkspace ws = LoadDenseWorkspace(dir, -1);
  std::vector<GrayImage> images;
  const kernels::PatchMatchProblem problem = ViewZeroProblem(ws, static_cast<int>(ws.views.size()) - 1, &images);
  kernels::PatchMatchSchedule schedule = mpmvs::test::ScheduleWithOptionDefaults();
  for (int s = 2; s >= 0; --s) {
    for (int t = 0; t < 3; ++t) schedule.iterations.push_back({s, t});
  }
  schedule.num_threads = static_cast<int>(state.range(0));
  uint64_t samples = 0, pixel_iterations = 0;
  double seconds = 0;
  for (auto _ : state) {
    kernels::PatchMatchResult result;
    const auto start = std::chrono::steady_clock::now();
    kernels::RunPatchMatchCpu(problem, schedule, &result);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    uint64_t nccs = result.init_ncc_evaluations;
    for (const auto& it : result.iterations) nccs += it.ncc_evaluations;
    samples += nccs * kernels::kWindowSamples;
    pixel_iterations += static_cast<uint64_t>(result.width) * result.height * result.iterations.size();
  }
  state.counters["s_per_map"] = seconds / state.iterations();
  state.counters["Mpix_it_per_s"] = pixel_iterations / seconds / 1e6;
  state.counters["samples_per_s"] = samples / seconds;
  state.counters["samples_per_px_it"] = static_cast<double>(samples) / pixel_iterations;
  state.counters["samples_per_s_per_thread"] = samples / seconds / state.range(0);
  state.counters["peak_MiB"] = PeakMemoryMiB();
}
BENCHMARK(BM_PhotometricStage)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// Time of the photometric stage's iterations against the number of source views and the
// image size (it should grow no faster than pixels x sources x iterations). The
// synthetic plane scene with 17 views; reference view 0 with its first N sources; one
// window scale, 3 iterations, 2 threads. Prints a table and the fitted exponents
// (least squares of log time on log sources / log pixels).
struct SweepPoint {
  int sources, width, height;
  double seconds, samples_per_px_it;
};

SweepPoint RunSweepPoint(int num_sources, int width, int height) {
  const std::string dir = PlaneScene("sweep_" + std::to_string(width), width, height, 17, 30.0, 1);
  const DenseWorkspace ws = LoadDenseWorkspace(dir, -1);
  std::vector<GrayImage> images;
  const kernels::PatchMatchProblem problem = ViewZeroProblem(ws, num_sources, &images);
  kernels::PatchMatchSchedule schedule = mpmvs::test::ScheduleWithOptionDefaults();
  for (int t = 0; t < 3; ++t) schedule.iterations.push_back({0, t});
  schedule.num_threads = 2;
  kernels::PatchMatchResult result;
  kernels::RunPatchMatchCpu(problem, schedule, &result);
  SweepPoint p{num_sources, width, height, 0.0, 0.0};
  uint64_t nccs = 0;
  for (const auto& it : result.iterations) {
    p.seconds += it.seconds;
    nccs += it.ncc_evaluations;
  }
  p.samples_per_px_it = static_cast<double>(nccs) * kernels::kWindowSamples / (static_cast<double>(width) * height * result.iterations.size());
  return p;
}

// Slope of log(y) against log(x).
double LogLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) mx += std::log(x[i]) / x.size(), my += std::log(y[i]) / y.size();
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += (std::log(x[i]) - mx) * (std::log(y[i]) - my);
    sxx += (std::log(x[i]) - mx) * (std::log(x[i]) - mx);
  }
  return sxy / sxx;
}

void BM_ScalingSweep(benchmark::State& state) {
  for (auto _ : state) {
    std::vector<double> n, t_n, px, t_px;
    std::printf("\n%8s %12s %12s %14s %16s\n", "sources", "image", "Mpx", "s (3 its)", "samples/px/it");
    auto row = [](const SweepPoint& p) {
      std::printf("%8d %5dx%-6d %12.2f %14.2f %16.0f\n", p.sources, p.width, p.height,
                  p.width * p.height / 1e6, p.seconds, p.samples_per_px_it);
    };
    for (int sources : {2, 4, 8, 16}) {  // at 1 Mpx
      const SweepPoint p = RunSweepPoint(sources, 1152, 864);
      row(p);
      n.push_back(sources);
      t_n.push_back(p.seconds);
    }
    for (const auto& size : std::vector<std::pair<int, int>>{{576, 432}, {816, 612}, {1152, 864}, {1632, 1224}}) {
      const SweepPoint p = RunSweepPoint(4, size.first, size.second);  // 0.25, 0.5, 1, 2 Mpx
      row(p);
      px.push_back(static_cast<double>(size.first) * size.second);
      t_px.push_back(p.seconds);
    }
    state.counters["exponent_sources"] = LogLogSlope(n, t_n);
    state.counters["exponent_pixels"] = LogLogSlope(px, t_px);
    state.counters["peak_MiB"] = PeakMemoryMiB();
  }
}
BENCHMARK(BM_ScalingSweep)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// Cost samples per pixel and iteration against the number of source views (2-20), with the
// candidates costed in every view (the default) and in 3 (--MPMVS.costed_views 3, the fast
// preset): reference view 0 of a 21-view plane scene at 576x432, one window scale, 3
// iterations, 2 threads. Prints a table; the counters are the ratios 20 sources / 4 sources.
void BM_SamplesAgainstSources(benchmark::State& state) {
  const std::string dir = PlaneScene("sources_576", 576, 432, 21, 30.0, 1);
  const DenseWorkspace ws = LoadDenseWorkspace(dir, -1);
  for (auto _ : state) {
    std::printf("\n%8s %22s %22s\n", "sources", "samples/px/it (all)", "samples/px/it (3)");
    double at4[2] = {0, 0}, at20[2] = {0, 0};
    for (int sources : {2, 4, 8, 16, 20}) {
      std::vector<GrayImage> images;
      const kernels::PatchMatchProblem problem = ViewZeroProblem(ws, sources, &images);
      double per_px_it[2];
      for (int k = 0; k < 2; ++k) {
        kernels::PatchMatchSchedule schedule = mpmvs::test::ScheduleWithOptionDefaults();
        for (int t = 0; t < 3; ++t) schedule.iterations.push_back({0, t});
        schedule.num_threads = 2;
        schedule.costed_views = k == 0 ? 0 : 3;
        kernels::PatchMatchResult result;
        kernels::RunPatchMatchCpu(problem, schedule, &result);
        uint64_t nccs = 0;
        for (const auto& it : result.iterations) nccs += it.ncc_evaluations;
        per_px_it[k] = static_cast<double>(nccs) * kernels::kWindowSamples /
                       (static_cast<double>(result.width) * result.height * result.iterations.size());
        if (sources == 4) at4[k] = per_px_it[k];
        if (sources == 20) at20[k] = per_px_it[k];
      }
      std::printf("%8d %22.0f %22.0f\n", sources, per_px_it[0], per_px_it[1]);
    }
    state.counters["all_views_20_over_4"] = at20[0] / at4[0];
    state.counters["costed_3_20_over_4"] = at20[1] / at4[1];
  }
}
BENCHMARK(BM_SamplesAgainstSources)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// Figures of a whole run: cores busy (CPU time / wall time), the share of the wall time
// outside the parallel work, cost samples per pixel and iteration and per second.
void SetWholeRunCounters(const MpPatchMatchSummary& summary, benchmark::State* state) {
  double samples = 0, pixel_iterations = 0;
  for (const StageSummary& st : summary.stages) {
    samples += static_cast<double>(st.ncc_evaluations) * kernels::kWindowSamples;
    pixel_iterations += static_cast<double>(st.pixel_iterations);
  }
  state->counters["cores_busy"] = summary.cpu_seconds / summary.seconds;
  state->counters["serial_share"] = summary.serial_seconds / summary.seconds;
  state->counters["samples_per_px_it"] = pixel_iterations > 0 ? samples / pixel_iterations : 0;
  state->counters["samples_per_s"] = samples / summary.seconds;
  state->counters["s_per_map"] = summary.seconds / std::max(1, summary.num_written);
}

// The whole run on a real two-view Middlebury 2014 pair (~0.36 Mpx each), both images.
// Arg 0: the ACMH baseline of issue 4 (ablation row "ACMH": 11 px windows, ACMH pattern, no
// prior; photometric + two geometric passes), the "under 5 s on 2 cores" target.
// Arg 1: the default MP-MVS pipeline (7 stages, 21 iterations: two prior rounds).
// Arg 2: the same with --MPMVS.settled_pixel_skips 2 (kernels/DESIGN.md 27).
// Arg 3: --MPMVS.preset fast.
void BM_MiddleburyTwoViewPipeline(benchmark::State& state) {
  const bool mpmvs = state.range(0) >= 1;
  const std::string dataset = std::string(MPMVS_SHARED_DATA_DIR) + "/middlebury2014_adirondack";
  if (!fs::is_directory(dataset) || !ColmapAvailable()) {
    state.SkipWithError("needs ../shared/data/middlebury2014_adirondack and colmap");
    return;
  }
  const std::string ws = ScratchDir("adirondack");
  if (!DirectoryExists(ws + "/stereo")) {
    RunColmap({"image_undistorter", "--image_path", dataset + "/images", "--input_path", dataset + "/sparse",
               "--output_path", ws, "--output_type", "COLMAP"},
              ws + "/../undistorter.log");
  }
  double seconds = 0;
  for (auto _ : state) {
    fs::remove_all(ws + "/stereo/mpmvs");
    for (const char* d : {"/stereo/depth_maps", "/stereo/normal_maps"}) {
      for (const auto& e : fs::directory_iterator(ws + d)) fs::remove(e.path());
    }
    MpPatchMatchRun run;
    run.workspace_path = ws;
    run.options.write_pictures = "none";
    if (!mpmvs) {
      run.options.max_window_scale = 0;
      run.options.distant_sampling = false;
      run.options.planar_prior = "none";
    }
    if (state.range(0) == 2) run.options.settled_pixel_skips = 2;
    if (state.range(0) == 3) ApplyPreset("fast", [](const std::string&) { return false; }, &run.options);
    const MpPatchMatchSummary summary = RunMpPatchMatchStereo(run);
    seconds += summary.seconds;
    SetWholeRunCounters(summary, &state);
  }
  state.counters["s_whole_run"] = seconds / state.iterations();
  state.counters["peak_MiB"] = PeakMemoryMiB();
}
BENCHMARK(BM_MiddleburyTwoViewPipeline)->ArgName("mpmvs")->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// A whole run on 8 views of the synthetic room (320x240, untextured walls) with all cores:
// how busy they are over the run and how much of its wall time is serial work.
// Arg 0: the default; Arg 1: --MPMVS.preset fast.
void BM_EightViewRoomRun(benchmark::State& state) {
  const std::string dir = ScratchDir("room8");
  if (!FileExists(dir + "/gt/scene_info.json")) {
    SyntheticSceneOptions o = SyntheticSceneOptions::ForScene("room_window");
    o.width = 320;
    o.height = 240;
    o.num_views = 8;
    o.write_gt_points = false;
    GenerateSyntheticScene(o, dir);
  }
  for (auto _ : state) {
    fs::remove_all(dir + "/stereo/mpmvs");
    for (const char* d : {"/stereo/depth_maps", "/stereo/normal_maps"}) {
      for (const auto& e : fs::directory_iterator(dir + d)) fs::remove(e.path());
    }
    MpPatchMatchRun run;
    run.workspace_path = dir;
    if (state.range(0) == 1) ApplyPreset("fast", [](const std::string&) { return false; }, &run.options);
    SetWholeRunCounters(RunMpPatchMatchStereo(run), &state);
  }
  state.counters["peak_MiB"] = PeakMemoryMiB();
}
BENCHMARK(BM_EightViewRoomRun)->ArgName("fast")->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// Peak resident memory of a run on large images (issue 33): the synthetic plane scene with
// 5 views at 3200x2130 (COLMAP's default max_image_size) or 6000x4000, the five maps with a
// short schedule (photometric stage only, one iteration at the 11 px window) and
// --PatchMatchStereo.cache_size 1. The run is a child process, so that each size has its
// own peak (which includes the small resident memory of this process at the fork,
// parent_MiB). The bound it should keep: the cache plus one reference image's working set,
// its state (32 bytes per pixel) and the packed copies of its sources' images (4 bytes per
// pixel each); the reference's grey and chroma buffers (12 bytes per pixel) come on top.
// The 6000x4000 scene takes about fourteen minutes here (--benchmark_filter=
// LargeImageMemory/3200 for the smaller one alone).
void BM_LargeImageMemory(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int height = width == 6000 ? 4000 : 2130;
  constexpr int kViews = 5;
  // Generated in a child process too: the run's child starts with this process's resident
  // memory, which must not hold the scene's buffers.
  const std::string name = "large_" + std::to_string(width);
  if (!RunInChildProcess([&] { PlaneScene(name, width, height, kViews, 30.0, 1); }, nullptr)) {
    state.SkipWithError("generating the large scene failed");
    return;
  }
  const std::string dir = ScratchDir(name);
  const double parent_mib = ResidentMiB();
  double peak_mib = 0, seconds = 0;
  for (auto _ : state) {
    fs::remove_all(dir + "/stereo/mpmvs");
    const auto start = std::chrono::steady_clock::now();
    MpPatchMatchRun run;
    run.workspace_path = dir;
    run.colmap_options.cache_size = 1;
    run.colmap_options.geom_consistency = false;
    run.options.max_window_scale = 0;
    run.options.iterations_per_scale = 1;
    run.options.half_resolution_scales = 0;
    run.options.overwrite = true;
    run.options.write_pictures = "none";
    rusage usage{};
    if (!RunInChildProcess([&] { RunMpPatchMatchStereo(run); }, &usage)) {
      state.SkipWithError("the run on the large images failed");
      return;
    }
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    peak_mib = usage.ru_maxrss / 1024.0;
  }
  const double pixels = static_cast<double>(width) * height;
  const double bound_mib = 1024.0 + (32.0 + 4.0 * (kViews - 1)) * pixels / (1024.0 * 1024.0);
  state.counters["Mpx"] = pixels / 1e6;
  state.counters["s_run"] = seconds;
  state.counters["peak_MiB"] = peak_mib;
  state.counters["bound_MiB"] = bound_mib;
  state.counters["peak_over_bound"] = peak_mib / bound_mib;
  state.counters["parent_MiB"] = parent_mib;  // included in peak_MiB
}
BENCHMARK(BM_LargeImageMemory)->Arg(3200)->Arg(6000)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace mpmvs

BENCHMARK_MAIN();

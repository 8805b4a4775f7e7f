#include "kernels/half_resolution.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mpmvs {
namespace kernels {
namespace {

// 2x2 means of `channels` interleaved floats per pixel.
std::vector<float> HalveInterleaved(const float* data, int width, int height, int channels, bool round) {
  const int w = width / 2, h = height / 2;
  std::vector<float> out(static_cast<size_t>(w) * h * channels);
  for (int j = 0; j < h; ++j) {
    const float* row0 = data + static_cast<size_t>(2 * j) * width * channels;
    const float* row1 = row0 + static_cast<size_t>(width) * channels;
    for (int i = 0; i < w; ++i) {
      for (int c = 0; c < channels; ++c) {
        const size_t a = static_cast<size_t>(2 * i) * channels + c, b = a + channels;
        const float mean = 0.25f * (row0[a] + row0[b] + row1[a] + row1[b]);
        out[(static_cast<size_t>(j) * w + i) * channels + c] = round ? std::nearbyint(mean) : mean;
      }
    }
  }
  return out;
}

bool AllIntegers(const ImageView& image) {
  const size_t n = static_cast<size_t>(image.width) * image.height;
  for (size_t i = 0; i < n; ++i) {
    if (image.data[i] != std::floor(image.data[i])) return false;
  }
  return true;
}

void RequireHalvable(const char* what, int width, int height) {
  if (width < 2 || height < 2) {
    throw std::invalid_argument(std::string(what) + " of " + std::to_string(width) + "x" + std::to_string(height) +
                                " px cannot be halved");
  }
}

}  // namespace

std::vector<float> HalveImage(const ImageView& image) {
  RequireHalvable("an image", image.width, image.height);
  return HalveInterleaved(image.data, image.width, image.height, 1, AllIntegers(image));
}

std::vector<float> HalveChroma(const float* chroma, int width, int height) {
  RequireHalvable("a chroma guide", width, height);
  return HalveInterleaved(chroma, width, height, 2, false);
}

Camera HalveCamera(const Camera& camera) {
  Camera half = camera;
  half.width = camera.width / 2;
  half.height = camera.height / 2;
  half.fx = 0.5f * camera.fx;
  half.fy = 0.5f * camera.fy;
  half.cx = 0.5f * (camera.cx - 0.5f);
  half.cy = 0.5f * (camera.cy - 0.5f);
  return half;
}

void MakeHalfResolutionProblem(const PatchMatchProblem& full, HalfResolutionProblem* half) {
  if (full.init_plane || full.prior_plane) {
    throw std::invalid_argument("half-resolution iterations start a photometric run: no starting planes or prior");
  }
  half->images.clear();
  half->images.reserve(1 + full.sources.size());  // the views below point into them
  PatchMatchProblem& p = half->problem;
  p = PatchMatchProblem();
  p.image_id = full.image_id;
  p.ref_camera = HalveCamera(full.ref_camera);
  half->images.push_back(HalveImage(full.ref_image));
  p.ref_image = ImageView{half->images.back().data(), p.ref_camera.width, p.ref_camera.height};
  half->chroma.clear();
  if (full.ref_image.chroma) {
    half->chroma = HalveChroma(full.ref_image.chroma, full.ref_image.width, full.ref_image.height);
    p.ref_image.chroma = half->chroma.data();
  }
  p.depth_min = full.depth_min;
  p.depth_max = full.depth_max;
  p.ref_noise_variance = 0.25f * full.ref_noise_variance;  // of a mean of 4 pixels
  for (const PatchMatchSource& s : full.sources) {
    if (s.depth_map) throw std::invalid_argument("half-resolution iterations are photometric: no depth maps");
    PatchMatchSource source;
    source.camera = HalveCamera(s.camera);
    half->images.push_back(HalveImage(s.image));
    source.image = ImageView{half->images.back().data(), source.camera.width, source.camera.height};
    p.sources.push_back(source);
  }
}

void UpsampleHalfResolutionResult(const PatchMatchResult& half, int width, int height, std::vector<float>* plane,
                                  std::vector<float>* cost) {
  const StateLayout layout = MakeStateLayout(width, height);
  plane->assign(layout.plane_floats, 0.f);
  cost->assign(layout.cost_floats, kInvalidCost);
  if (half.width <= 0 || half.height <= 0) return;
  for (int v = 0; v < height; ++v) {
    const int hv = std::min(v / 2, half.height - 1);
    for (int u = 0; u < width; ++u) {
      const int hidx = hv * half.width + std::min(u / 2, half.width - 1);
      if (!(half.photo_cost[hidx] < kInvalidCost)) continue;
      const int idx = v * width + u;
      StorePlane(plane->data(), idx, LoadPlane(half.plane.data(), hidx));
      (*cost)[idx] = half.photo_cost[hidx];
    }
  }
}

bool HasHalfResolutionIterations(const PatchMatchSchedule& schedule) {
  return !schedule.iterations.empty() && schedule.iterations.front().half_resolution;
}

double IterationWork(const PatchMatchSchedule& schedule) {
  double work = 0;
  for (const IterationSpec& spec : schedule.iterations) work += spec.half_resolution ? 0.25 : 1.0;
  return work;
}

int FirstFullResolutionScale(const PatchMatchSchedule& schedule) {
  if (schedule.iterations.empty()) return 0;
  const IterationSpec& first = schedule.iterations.front();
  return FullResolutionScale(first.window_scale, first.half_resolution);
}

void RunWithHalfResolutionStart(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                                const BackendRunFunction& run, PatchMatchResult* result,
                                const ProgressCallback& progress) {
  schedule.Check();
  PatchMatchSchedule coarse = schedule, fine = schedule;
  coarse.iterations.clear();
  fine.iterations.clear();
  for (const IterationSpec& spec : schedule.iterations) {
    IterationSpec plain = spec;
    plain.half_resolution = false;
    (spec.half_resolution ? coarse : fine).iterations.push_back(plain);
  }
  if (coarse.iterations.empty() || fine.iterations.empty()) {
    throw std::invalid_argument("a half-resolution start needs iterations at both resolutions");
  }
  const int total = static_cast<int>(schedule.iterations.size());
  const int num_coarse = static_cast<int>(coarse.iterations.size());
  HalfResolutionProblem half;
  MakeHalfResolutionProblem(problem, &half);
  PatchMatchResult half_result;
  run(half.problem, coarse, &half_result,
      progress ? ProgressCallback([&](int done, int) { progress(done, total); }) : ProgressCallback(), false);

  PatchMatchProblem start = problem;
  std::vector<float> plane, cost;
  UpsampleHalfResolutionResult(half_result, problem.ref_camera.width, problem.ref_camera.height, &plane, &cost);
  start.init_plane = plane.data();
  start.init_cost = cost.data();
  run(start, fine, result,
      progress ? ProgressCallback([&](int done, int) { progress(num_coarse + done, total); }) : ProgressCallback(),
      true);
  result->init_ncc_evaluations += half_result.init_ncc_evaluations;
  for (IterationStats& stats : half_result.iterations) stats.half_resolution = true;
  result->iterations.insert(result->iterations.begin(), half_result.iterations.begin(), half_result.iterations.end());
}

}  // namespace kernels
}  // namespace mpmvs

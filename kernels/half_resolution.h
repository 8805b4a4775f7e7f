#pragma once
// mPM's larger windows on the images at half resolution (--MPMVS.half_resolution_scales).
// A window of scale S covers at full resolution what a window of scale S-1 covers at half,
// with the same 6x6 samples, on a quarter of the pixels. A schedule's half-resolution
// iterations (IterationSpec::half_resolution, a prefix of the photometric schedule) run on a
// half-resolution copy of the problem; its planes, each full-resolution pixel taking the
// plane of the half-resolution pixel that covers it, start the full-resolution iterations
// (kernels/DESIGN.md 30). Host code shared by both backends; plain data, no I/O.
#include <functional>
#include <vector>

#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {

// 2x2 box reduction of an image (width/2 x height/2; an odd last row or column is dropped).
// Values are rounded to integers where all the input's are, so that an 8-bit image keeps
// the CPU backend's packed bilinear samples (MakeQuadImage).
std::vector<float> HalveImage(const ImageView& image);
// The same reduction of a chroma guide (2 floats per pixel).
std::vector<float> HalveChroma(const float* chroma, int width, int height);
// The camera of a halved image: its pixel (i, j) is the mean of the full image's pixels
// 2i..2i+1 x 2j..2j+1, whose centre is the full image's coordinate (2i + 0.5, 2j + 0.5).
Camera HalveCamera(const Camera& camera);

// A problem at half resolution and the images it points to.
struct HalfResolutionProblem {
  PatchMatchProblem problem;
  std::vector<std::vector<float>> images;  // the reference's, then each source's
  std::vector<float> chroma;
};
// The photometric problem of `full` at half resolution: images, chroma guide and cameras
// halved, the noise variance of a 4-pixel mean, no device cache ids (the halved images are
// uploaded for this problem only). Throws std::invalid_argument for a problem with depth
// maps, a prior or starting planes, or an image under 2x2 pixels.
void MakeHalfResolutionProblem(const PatchMatchProblem& full, HalfResolutionProblem* half);

// Starting planes and costs of a width x height image from a half-resolution result: each
// pixel takes the plane and photometric cost of the half-resolution pixel covering it
// (clamped at an odd last row or column); pixels without a valid estimate there get none
// (d = 0, cost kInvalidCost).
void UpsampleHalfResolutionResult(const PatchMatchResult& half, int width, int height, std::vector<float>* plane,
                                  std::vector<float>* cost);

bool HasHalfResolutionIterations(const PatchMatchSchedule& schedule);
// The schedule's iterations weighed by their pixels: a half-resolution one counts a quarter.
double IterationWork(const PatchMatchSchedule& schedule);
// The window scale an iteration's window covers at full resolution: a half-resolution
// iteration's scale plus one.
inline int FullResolutionScale(int window_scale, bool half_resolution) {
  return window_scale + (half_resolution ? 1 : 0);
}
// FullResolutionScale of the schedule's first iteration: the run's largest window.
int FirstFullResolutionScale(const PatchMatchSchedule& schedule);

// Runs `problem` on one backend: `median_filter` says whether to median-filter the result
// (only the full-resolution run's), `last` whether this is the full-resolution run.
using BackendRunFunction = std::function<void(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                                              PatchMatchResult* result, const ProgressCallback& progress,
                                              bool last)>;
// The schedule's half-resolution iterations on MakeHalfResolutionProblem's problem, then the
// others at full resolution from its upsampled planes; result: the full-resolution one, its
// statistics those of both runs (NCCs counted where they were computed). progress counts
// the iterations of both.
void RunWithHalfResolutionStart(const PatchMatchProblem& problem, const PatchMatchSchedule& schedule,
                                const BackendRunFunction& run, PatchMatchResult* result,
                                const ProgressCallback& progress = nullptr);

}  // namespace kernels
}  // namespace mpmvs

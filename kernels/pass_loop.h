#pragma once
// The pass sequence of a PatchMatch run, written once for every backend: the
// initialisation pass, then per iteration of the schedule a black and a red checkerboard
// pass, each set up by SetInitPass / SetCheckerboardPass so that every backend draws the
// same random streams with the same window and good-match threshold. The backends only
// run the passes (cpu_backend.cc; the CUDA launches of cuda_passes.h).
#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {

// Runs the passes of `schedule` on `passes`, which provides
//   void Initialize(const PassParams& params);                  the initialisation pass
//   void BeginIteration(int iteration);
//   void Checkerboard(const PassParams& params, int iteration); the pass of params.color
//   void EndIteration(int iteration);
// `params` comes from MakePassParams; the per-pass fields are set here.
template <class Passes>
void RunPassLoop(const PatchMatchSchedule& schedule, PassParams params, Passes* passes) {
  SetInitPass(schedule, &params);
  passes->Initialize(params);
  const int total = static_cast<int>(schedule.iterations.size());
  for (int it = 0; it < total; ++it) {
    passes->BeginIteration(it);
    for (int color = 0; color < 2; ++color) {
      SetCheckerboardPass(schedule, it, color, &params);
      passes->Checkerboard(params, it);
    }
    passes->EndIteration(it);
  }
}

}  // namespace kernels
}  // namespace mpmvs

#pragma once
// The CUDA backend's passes without the CUDA API: what one thread of each kernel does,
// and which kernel runs over which launch layout into which NCC counter. cuda_backend.cu
// launches them on the device; tests/kernels/cuda_backend_test.cc runs the same sequence with the
// same thread bodies on the host, so everything but the CUDA calls is tested without a GPU.
// No CUDA types here.
#include "kernels/launch_layout.h"
#include "kernels/pass_loop.h"

namespace mpmvs {
namespace kernels {

// One thread of the initialisation kernel (ImageLaunchLayout); the device uses ScalarNcc.
MPMVS_HD inline void InitializeThread(const PassParams& params, const PixelState& state,
                                      const float* init_plane, const float* init_cost,
                                      Dim2 block, Dim2 block_dim, Dim2 thread, uint32_t* count) {
  int u, v;
  if (ImageThreadPixel(params.ref_camera.width, params.ref_camera.height, block, block_dim,
                       thread, &u, &v)) {
    InitializePixel<ScalarNcc>(params, state, init_plane, init_cost, u, v, count);
  }
}

// One thread of a checkerboard kernel of colour params.color (CheckerboardLaunchLayout).
MPMVS_HD inline void CheckerboardThread(const PassParams& params, const PixelState& state,
                                        Dim2 block, Dim2 block_dim, Dim2 thread,
                                        uint32_t* count) {
  int u, v;
  if (CheckerboardThreadPixel(params.ref_camera.width, params.ref_camera.height, params.color,
                              block, block_dim, thread, &u, &v)) {
    UpdatePixel<ScalarNcc>(params, state, u, v, count);
  }
}

enum class PassKernel { kInitialize, kCheckerboard };

// The NCC counters of a run: [0] the initialisation, [1 + it] iteration it.
constexpr int kInitCounter = 0;
inline int IterationCounter(int iteration) { return 1 + iteration; }
inline int NumNccCounters(int iterations) { return 1 + iterations; }

// RunPassLoop's passes as kernel launches. Launch provides
//   void Run(PassKernel kernel, const LaunchLayout& layout, const PassParams& params,
//            int counter);                  one kernel over `layout`, counting into `counter`
//   void Queued(int mark);                  mark 0 after the initialisation, it + 1 after
//                                           iteration it
// An empty image launches nothing but still passes every mark.
template <class Launch>
class LaunchedPasses {
 public:
  LaunchedPasses(int width, int height, Launch* launch)
      : launch_(launch),
        empty_(MakeStateLayout(width, height).num_pixels == 0),
        init_layout_(ImageLaunchLayout(width, height)),
        pass_layout_(CheckerboardLaunchLayout(width, height)) {}

  void Initialize(const PassParams& params) {
    if (!empty_) launch_->Run(PassKernel::kInitialize, init_layout_, params, kInitCounter);
    launch_->Queued(0);
  }
  void BeginIteration(int) {}
  void Checkerboard(const PassParams& params, int iteration) {
    if (!empty_) {
      launch_->Run(PassKernel::kCheckerboard, pass_layout_, params, IterationCounter(iteration));
    }
  }
  void EndIteration(int iteration) { launch_->Queued(iteration + 1); }

 private:
  Launch* launch_;
  bool empty_;
  LaunchLayout init_layout_, pass_layout_;
};

// Queues the passes of `schedule` (params from MakePassParams) on `launch`.
template <class Launch>
void LaunchPasses(const PatchMatchSchedule& schedule, const PassParams& params, Launch* launch) {
  LaunchedPasses<Launch> passes(params.ref_camera.width, params.ref_camera.height, launch);
  RunPassLoop(schedule, params, &passes);
}

}  // namespace kernels
}  // namespace mpmvs

#pragma once
// Which backend a run uses and how (pipeline/backend.h runs it): part of the run plan.
#include <cstddef>

namespace mpmvs {

struct BackendOptions {
  int gpu_index = -1;         // -1: the first CUDA device if usable, else the CPU
  int num_threads = -1;       // CPU threads (-1: all cores)
  size_t cache_bytes = 0;     // device cache budget (CUDA)
  // The CPU runs the controller's side work beside its passes (pipeline/backend.h); tests
  // turn it off to compare with the serial order.
  bool cpu_side_work = true;
};

}  // namespace mpmvs

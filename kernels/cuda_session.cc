// Host parts of cuda_session.h, in every build; the session itself is cuda_session.cu
// (cuda_stubs.cc in builds without CUDA).
#include "kernels/cuda_session.h"

#include <stdexcept>
#include <string>

namespace mpmvs {
namespace kernels {

void CudaSessionOptions::Check() const {
  if (gpu_index < 0) {
    throw std::invalid_argument("CUDA session: gpu index must be >= 0, got " +
                                std::to_string(gpu_index));
  }
}

}  // namespace kernels
}  // namespace mpmvs

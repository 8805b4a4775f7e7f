// Host parts of cuda_session.h, in every build; the session itself is cuda_session.cu.
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

// Builds without CUDA (no nvcc, or -DMPMVS_ENABLE_CUDA=OFF); otherwise cuda_session.cu.
#if !defined(MPMVS_WITH_CUDA)
class CudaSession::Impl {};

CudaSession::CudaSession(const CudaSessionOptions&) {
  throw std::runtime_error("this build of mp-mvs has no CUDA backend");
}
CudaSession::~CudaSession() = default;

void CudaSession::Run(const PatchMatchProblem&, const PatchMatchSchedule&, PatchMatchResult*,
                      const NextProblemCallback&, const ProgressCallback&) {
  throw std::runtime_error("this build of mp-mvs has no CUDA backend");
}

DeviceCacheStats CudaSession::CacheStats() const { return DeviceCacheStats(); }
size_t CudaSession::CacheBudgetBytes() const { return 0; }
#endif

}  // namespace kernels
}  // namespace mpmvs

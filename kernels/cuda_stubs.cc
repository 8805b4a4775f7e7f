// The CUDA entry points of builds without CUDA (no nvcc, or -DMPMVS_ENABLE_CUDA=OFF):
// CudaDeviceAvailable says why not, everything else throws. Compiled only in those builds,
// in place of cuda_backend.cu and cuda_session.cu.
#include <stdexcept>
#include <string>

#include "kernels/cuda_session.h"
#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {
namespace {
[[noreturn]] void ThrowNoCuda() {
  throw std::runtime_error("this build of mp-mvs has no CUDA backend");
}
}  // namespace

const char* GpuRuntimeName() { return "CUDA"; }

int CudaDeviceCount() { return 0; }

bool CudaDeviceAvailable(int, std::string* why) {
  if (why) {
    *why = "this build of mp-mvs has no CUDA backend (nvcc not found at build time or "
           "-DMPMVS_ENABLE_CUDA=OFF)";
  }
  return false;
}

void RunPatchMatchCuda(const PatchMatchProblem&, const PatchMatchSchedule&, int,
                       PatchMatchResult*, const ProgressCallback&) {
  ThrowNoCuda();
}

class CudaSession::Impl {};

CudaSession::CudaSession(const CudaSessionOptions&) { ThrowNoCuda(); }
CudaSession::~CudaSession() = default;

void CudaSession::Run(const PatchMatchProblem&, const PatchMatchSchedule&, PatchMatchResult*,
                      const NextProblemCallback&, const ProgressCallback&) {
  ThrowNoCuda();
}

DeviceCacheStats CudaSession::CacheStats() const { return DeviceCacheStats(); }
size_t CudaSession::CacheBudgetBytes() const { return 0; }

}  // namespace kernels
}  // namespace mpmvs

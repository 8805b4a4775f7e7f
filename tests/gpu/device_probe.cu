// Step 1 of tests/gpu/check_on_device.sh: can the CUDA runtime of this nvcc use device 0?
// Built with nvcc's default target (PTX included, so the driver compiles it for any newer
// device); runs one kernel there. Prints key=value lines and exits 0, or one line
// "error=<why>" and exits 1. Not part of the CMake build.
#include <cstdio>

#include <cuda_runtime.h>

__global__ void WriteAnswer(int* out) { *out = 42; }

static int Fail(const char* what, cudaError_t error) {
  std::printf("error=%s: %s\n", what, cudaGetErrorString(error));
  return 1;
}

int main() {
  int count = 0;
  cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) return Fail("cudaGetDeviceCount", e);
  if (count == 0) {
    std::printf("error=the CUDA runtime sees no device\n");
    return 1;
  }
  cudaDeviceProp p;
  if ((e = cudaGetDeviceProperties(&p, 0)) != cudaSuccess) return Fail("cudaGetDeviceProperties", e);
  int* answer = nullptr;
  if ((e = cudaMalloc(&answer, sizeof(int))) != cudaSuccess) return Fail("cudaMalloc", e);
  WriteAnswer<<<1, 1>>>(answer);
  if ((e = cudaGetLastError()) != cudaSuccess) return Fail("kernel launch", e);
  int host = 0;
  if ((e = cudaMemcpy(&host, answer, sizeof(int), cudaMemcpyDeviceToHost)) != cudaSuccess) {
    return Fail("cudaMemcpy after the kernel", e);
  }
  cudaFree(answer);
  if (host != 42) {
    std::printf("error=the probe kernel wrote %d, not 42\n", host);
    return 1;
  }
  int driver = 0, runtime = 0;
  cudaDriverGetVersion(&driver);
  cudaRuntimeGetVersion(&runtime);
  const unsigned char* u = reinterpret_cast<const unsigned char*>(p.uuid.bytes);
  std::printf("devices=%d\nname=%s\ncc=%d%d\nmemory_mib=%zu\nmultiprocessors=%d\n", count, p.name, p.major,
              p.minor, p.totalGlobalMem >> 20, p.multiProcessorCount);
  std::printf("uuid=GPU-%02x%02x%02x%02x-%02x%02x-%02x%02x-%02x%02x-%02x%02x%02x%02x%02x%02x\n", u[0], u[1], u[2],
              u[3], u[4], u[5], u[6], u[7], u[8], u[9], u[10], u[11], u[12], u[13], u[14], u[15]);
  std::printf("driver=%d.%d\nruntime=%d.%d\n", driver / 1000, driver % 1000 / 10, runtime / 1000,
              runtime % 1000 / 10);
  return 0;
}

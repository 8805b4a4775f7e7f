// The backend choice (pipeline/backend.h) as the user reads it in the log.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "colmap_ext/pipeline/backend.h"

namespace mpmvs {
namespace {

// A machine without a GPU is the usual case, not a fault: one calm line, nothing on stderr.
TEST(Backend, WithoutCudaDeviceSaysSoInOneCalmLine) {
  if (kernels::CudaDeviceCount() > 0) GTEST_SKIP() << "a CUDA device is present";
  BackendOptions options;
  options.num_threads = 3;
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  const Backend backend(options);
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(err, "");
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_NE(out.find("; running on the CPU with 3 threads\n"), std::string::npos) << out;
  EXPECT_EQ(out.find("failed"), std::string::npos) << out;
  EXPECT_EQ(out.find("(nvcc"), std::string::npos) << out;
  EXPECT_EQ(backend.Name(), "CPU (3 threads)");
}

}  // namespace
}  // namespace mpmvs

#pragma once
// Shared helpers of the tests: temporary folders, locating ../shared/data and `colmap`.
#include <string>

#include "colmap_ext/synthetic/synthetic_scene.h"

namespace mpmvs {
namespace test {

// A fresh empty folder under $TMPDIR (or /tmp) named after the running test; removed by
// the destructor unless MPMVS_KEEP_TEST_DIRS is set.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// ../shared/data (MPMVS_SHARED_DATA env overrides); "" when absent.
std::string SharedDataDir();
// A dataset folder under SharedDataDir(), or "" when absent.
std::string SharedDataset(const std::string& name);
// Path of the `colmap` executable (MPMVS_COLMAP_EXE env or PATH), "" when absent.
std::string ColmapExecutable();
// The built colmap-mp.
std::string ColmapMpExecutable();

// A small synthetic textured plane tilted 35 degrees away from every camera, written as a
// dense workspace into dir (the quick scene of most pipeline tests).
SyntheticScene WriteSmallPlaneScene(const std::string& dir, int width, int height, int num_views);

// Runs a shell command, returns its exit code; output goes to log_path when given.
int RunCommand(const std::string& command, const std::string& log_path = "");
std::string ReadTextFile(const std::string& path);

}  // namespace test
}  // namespace mpmvs

// Skips the current test with a clear message when a dataset / colmap is missing.
#define MPMVS_REQUIRE_DATASET(var, name)                                              \
  const std::string var = ::mpmvs::test::SharedDataset(name);                         \
  if (var.empty()) {                                                                  \
    GTEST_SKIP() << "dataset " << name << " not found (expected ../shared/data/" << name \
                 << " beside the project, or set MPMVS_SHARED_DATA)";                 \
  }
#define MPMVS_REQUIRE_COLMAP(var)                                                     \
  const std::string var = ::mpmvs::test::ColmapExecutable();                          \
  if (var.empty()) {                                                                  \
    GTEST_SKIP() << "the `colmap` executable is not on PATH (apt-get install colmap)"; \
  }

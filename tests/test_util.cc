#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace mpmvs {
namespace test {

TempDir::TempDir() {
  const char* tmp = std::getenv("TMPDIR");
  const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "mpmvs";
  for (char& c : name) {
    if (c == '/') c = '_';
  }
  fs::path base = fs::path(tmp ? tmp : "/tmp") / "mpmvs_tests";
  path_ = (base / (name + "_" + std::to_string(::getpid()))).string();
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  if (!std::getenv("MPMVS_KEEP_TEST_DIRS")) {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
}

std::string SharedDataDir() {
  const char* env = std::getenv("MPMVS_SHARED_DATA");
  fs::path dir = env ? fs::path(env) : fs::path(MPMVS_SHARED_DATA_DIR);
  std::error_code ec;
  if (fs::is_directory(dir, ec)) return fs::canonical(dir).string();
  return "";
}

std::string SharedDataset(const std::string& name) {
  const std::string dir = SharedDataDir();
  if (dir.empty()) return "";
  const fs::path path = fs::path(dir) / name;
  std::error_code ec;
  return fs::is_directory(path, ec) ? path.string() : "";
}

std::string ColmapExecutable() {
  if (const char* env = std::getenv("MPMVS_COLMAP_EXE")) return env;
  const char* path = std::getenv("PATH");
  if (!path) return "";
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    const fs::path candidate = fs::path(dir) / "colmap";
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) return candidate.string();
  }
  return "";
}

SyntheticScene WriteSmallPlaneScene(const std::string& dir, int width, int height, int num_views) {
  SyntheticSceneOptions scene;
  scene.scene = "plane";
  scene.width = width;
  scene.height = height;
  scene.num_views = num_views;
  scene.plane_tilt_deg = 35;
  return GenerateSyntheticScene(scene, dir);
}

std::string ColmapMpExecutable() { return MPMVS_COLMAP_MP_EXE; }

int RunCommand(const std::string& command, const std::string& log_path) {
  std::string full = command;
  if (!log_path.empty()) full += " > '" + log_path + "' 2>&1";
  const int status = std::system(full.c_str());
  if (status == -1) return -1;
  return WEXITSTATUS(status);
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream ss;
  ss << file.rdbuf();
  return ss.str();
}

}  // namespace test
}  // namespace mpmvs

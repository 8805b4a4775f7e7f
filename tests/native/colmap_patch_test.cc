// The COLMAP patches (patches/colmap-mp_patch_match_stereo.patch for 3.12.x - 4.0.x and
// patches/colmap-4.1.x-head/ for 4.1.x and the development head) without COLMAP's sources (CI has none): the
// patch parses with `git apply`, touches exactly src/colmap/exe/colmap.cc and
// src/colmap/exe/CMakeLists.txt, only adds lines, names things that exist in this
// repository, applies to the pre-image it describes, and patches/check_patch.sh accepts that
// tree and fails loudly on a drifted one. Skips when `git` is not installed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_util.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;

const std::string kCheckScript = std::string(MPMVS_SOURCE_DIR) + "/patches/check_patch.sh";

bool HaveGit() { return test::RunCommand("git --version > /dev/null 2>&1") == 0; }

#define MPMVS_REQUIRE_GIT()                                             \
  if (!HaveGit()) {                                                     \
    GTEST_SKIP() << "`git` is not installed; the patch checks need it"; \
  }

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Per file of the patch: lines before ("-" and " ") and added lines ("+"), hunk by hunk.
struct FileHunks {
  std::vector<std::vector<std::string>> pre_image;
  std::vector<std::string> added;
  int removed = 0;
};

std::map<std::string, FileHunks> ParsePatch(const std::string& text) {
  std::map<std::string, FileHunks> files;
  FileHunks* current = nullptr;
  bool in_hunk = false;
  for (const std::string& line : Lines(text)) {
    if (line.rfind("diff --git ", 0) == 0) {
      in_hunk = false;
      current = nullptr;
    } else if (line.rfind("+++ b/", 0) == 0) {
      current = &files[line.substr(6)];
    } else if (line.rfind("@@ ", 0) == 0 && current != nullptr) {
      current->pre_image.emplace_back();
      in_hunk = true;
    } else if (in_hunk && current != nullptr && !line.empty()) {
      if (line[0] == ' ') current->pre_image.back().push_back(line.substr(1));
      if (line[0] == '-') {
        current->pre_image.back().push_back(line.substr(1));
        ++current->removed;
      }
      if (line[0] == '+') current->added.push_back(line.substr(1));
    }
  }
  return files;
}

// A tree whose two files hold only the patch's pre-image lines, hunks separated by filler.
void WritePreImageTree(const std::string& root, const std::map<std::string, FileHunks>& files) {
  for (const auto& [path, hunks] : files) {
    fs::create_directories(fs::path(root + "/" + path).parent_path());
    std::ofstream out(root + "/" + path);
    for (size_t h = 0; h < hunks.pre_image.size(); ++h) {
      if (h > 0) out << "// filler between hunks\n# filler between hunks\n\n";
      for (const std::string& line : hunks.pre_image[h]) out << line << "\n";
    }
  }
}

// One run of every test per patch variant (path relative to patches/).
class ColmapPatch : public ::testing::TestWithParam<std::string> {
 protected:
  const std::string kPatch = std::string(MPMVS_SOURCE_DIR) + "/patches/" + GetParam();
};

INSTANTIATE_TEST_SUITE_P(Variants, ColmapPatch,
                         ::testing::Values("colmap-mp_patch_match_stereo.patch",
                                           "colmap-4.1.x-head/colmap-mp_patch_match_stereo.patch"));

TEST_P(ColmapPatch, ParsesAndTouchesExactlyTheTwoCommandFiles) {
  MPMVS_REQUIRE_GIT();
  ASSERT_TRUE(fs::exists(kPatch)) << kPatch;
  test::TempDir tmp;
  fs::copy_file(kPatch, tmp / "p.patch");
  // From an empty folder outside any git repository: git only parses the patch.
  ASSERT_EQ(test::RunCommand("cd '" + tmp.path() + "' && git apply --numstat p.patch > numstat.txt 2> err.txt"), 0)
      << test::ReadTextFile(tmp / "err.txt");
  ASSERT_EQ(test::RunCommand("cd '" + tmp.path() + "' && git apply --stat p.patch > stat.txt 2>&1"), 0);
  std::map<std::string, std::pair<int, int>> numstat;
  for (const std::string& line : Lines(test::ReadTextFile(tmp / "numstat.txt"))) {
    std::istringstream in(line);
    int added = -1, removed = -1;
    std::string path;
    in >> added >> removed >> path;
    numstat[path] = {added, removed};
  }
  ASSERT_EQ(numstat.size(), 2u) << test::ReadTextFile(tmp / "numstat.txt");
  ASSERT_TRUE(numstat.count("src/colmap/exe/colmap.cc"));
  ASSERT_TRUE(numstat.count("src/colmap/exe/CMakeLists.txt"));
  for (const auto& [path, counts] : numstat) {
    EXPECT_GT(counts.first, 0) << path;
    EXPECT_EQ(counts.second, 0) << path << ": the patch only adds lines";
  }
  EXPECT_NE(test::ReadTextFile(tmp / "stat.txt").find("2 files changed"), std::string::npos);
}

TEST_P(ColmapPatch, NamesAHeaderFunctionAndTargetThatExist) {
  const std::map<std::string, FileHunks> files = ParsePatch(test::ReadTextFile(kPatch));
  ASSERT_EQ(files.size(), 2u);
  std::string cc, cmake;
  for (const std::string& l : files.at("src/colmap/exe/colmap.cc").added) cc += l + "\n";
  for (const std::string& l : files.at("src/colmap/exe/CMakeLists.txt").added) cmake += l + "\n";
  EXPECT_NE(cc.find("#include \"colmap_ext/native/mp_patch_match_stereo_native.h\""), std::string::npos) << cc;
  EXPECT_NE(cc.find("\"mp_patch_match_stereo\""), std::string::npos) << cc;
  EXPECT_NE(cc.find("&mpmvs::RunColmapMpPatchMatchStereo"), std::string::npos) << cc;
  const std::string header =
      test::ReadTextFile(std::string(MPMVS_SOURCE_DIR) + "/colmap_ext/native/mp_patch_match_stereo_native.h");
  EXPECT_NE(header.find("int RunColmapMpPatchMatchStereo(int argc, char** argv);"), std::string::npos);
  EXPECT_NE(cmake.find("find_package(mpmvs"), std::string::npos) << cmake;
  EXPECT_NE(cmake.find("target_link_libraries(colmap_main mpmvs::mpmvs_colmap_command)"), std::string::npos)
      << "COLMAP links colmap_main with the plain signature, so the patch must too:\n" << cmake;
  const std::string config = test::ReadTextFile(std::string(MPMVS_SOURCE_DIR) + "/cmake/mpmvs-config.cmake.in");
  EXPECT_NE(config.find("add_library(mpmvs::mpmvs_colmap_command INTERFACE IMPORTED)"), std::string::npos);
}

TEST_P(ColmapPatch, AppliesToItsPreImageAndCheckScriptDetectsDrift) {
  MPMVS_REQUIRE_GIT();
  const std::map<std::string, FileHunks> files = ParsePatch(test::ReadTextFile(kPatch));
  ASSERT_EQ(files.size(), 2u);
  test::TempDir tmp;
  WritePreImageTree(tmp / "good", files);
  const std::string check = "'" + kCheckScript + "' ";
  EXPECT_EQ(test::RunCommand(check + "'" + (tmp / "good") + "'", tmp / "good.log"), 0)
      << test::ReadTextFile(tmp / "good.log");
  // Applying for real adds the command; the script then reports it as applied.
  ASSERT_EQ(test::RunCommand("cd '" + (tmp / "good") + "' && git apply '" + kPatch + "'"), 0);
  EXPECT_NE(test::ReadTextFile(tmp / "good/src/colmap/exe/colmap.cc").find("mp_patch_match_stereo"),
            std::string::npos);
  EXPECT_EQ(test::RunCommand(check + "'" + (tmp / "good") + "'", tmp / "applied.log"), 0)
      << test::ReadTextFile(tmp / "applied.log");

  // COLMAP moved: the include of the MVS commands, a context line of colmap.cc, changed ->
  // loud failure.
  WritePreImageTree(tmp / "drift", files);
  const std::string cc_path = tmp / "drift/src/colmap/exe/colmap.cc";
  std::string cc = test::ReadTextFile(cc_path);
  const std::string mvs_include = "#include \"colmap/exe/mvs.h\"";
  const size_t pos = cc.find(mvs_include);
  ASSERT_NE(pos, std::string::npos);
  cc.replace(pos, mvs_include.size(), "#include \"colmap/exe/dense.h\"");
  std::ofstream(cc_path) << cc;
  EXPECT_EQ(test::RunCommand(check + "'" + (tmp / "drift") + "'", tmp / "drift.log"), 1)
      << test::ReadTextFile(tmp / "drift.log");
  EXPECT_NE(test::ReadTextFile(tmp / "drift.log").find("FAILED"), std::string::npos);
}

}  // namespace
}  // namespace mpmvs

// Two mp_patch_match_stereo runs on one workspace (schedule/work_claims.h): a run leaves an
// image whose stage another live process holds, does its other images, then waits for it;
// a run with other options stops before it writes anything.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>

#include "colmap_ext/schedule/work_claims.h"
#include "colmap_ext/util/file_util.h"
#include "tests/io_test_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;

std::string Exe() { return "'" + test::ColmapMpExecutable() + "'"; }

std::string RunCommandLine(const std::string& ws) {
  return Exe() + " mp_patch_match_stereo --workspace_path " + ws +
         " --PatchMatchStereo.num_threads 1 --MPMVS.write_pictures none";
}

// sha256 of every depth and normal map of the workspace, one line per file.
std::string MapSums(const std::string& ws, const std::string& out) {
  test::RunCommand("cd " + ws + "/stereo && sha256sum depth_maps/*.bin normal_maps/*.bin > " + out);
  return test::ReadTextFile(out);
}

// Waits up to 120 s for text to appear in the file; true when it did.
bool WaitForText(const std::string& path, const std::string& text) {
  for (int i = 0; i < 1200; ++i) {
    if (test::ReadTextFile(path).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

class ConcurrentRuns : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(test::RunCommand(Exe() + " generate_scene --scene indoor --width 96 --height 72 --num_views 4 "
                                       "--output_path " + tmp_ / "base",
                               tmp_ / "gen.log"),
              0);
    test::RunCommand("cp -r " + tmp_ / "base" + " " + tmp_ / "one" + " && cp -r " + tmp_ / "base" + " " +
                     tmp_ / "shared");
    ASSERT_EQ(test::RunCommand(RunCommandLine(tmp_ / "one"), tmp_ / "one.log"), 0);
    expected_ = MapSums(tmp_ / "one", tmp_ / "one.sums");
    ASSERT_FALSE(expected_.empty());
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(tmp_ / "shared/images")) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    ASSERT_FALSE(names.empty());
    first_image_ = names.front();
  }

  std::string Claims() const { return tmp_ / "shared/stereo/mpmvs/claims"; }

  test::TempDir tmp_;
  std::string expected_;
  std::string first_image_;
};

TEST_F(ConcurrentRuns, HeldImageIsLeftForLaterThenWaitedFor) {
  WorkClaims other(Claims(), 600);  // this test process plays the other live run
  ASSERT_EQ(other.TryClaim(first_image_ + ".photometric"), WorkClaims::Result::kClaimed);
  int rc = -1;
  std::thread run([&] { rc = test::RunCommand(RunCommandLine(tmp_ / "shared"), tmp_ / "shared.log"); });
  const bool waited = WaitForText(tmp_ / "shared.log", "to finish stage photometric");
  other.Release(first_image_ + ".photometric");
  run.join();
  const std::string log = test::ReadTextFile(tmp_ / "shared.log");
  EXPECT_TRUE(waited) << log;
  EXPECT_NE(log.find(first_image_ + ": stage photometric is being run by"), std::string::npos) << log;
  EXPECT_NE(log.find("doing other images first"), std::string::npos) << log;
  // It did the other images before waiting: their photometric maps exist by then.
  ASSERT_EQ(rc, 0) << log;
  EXPECT_EQ(MapSums(tmp_ / "shared", tmp_ / "shared.sums"), expected_);
}

TEST_F(ConcurrentRuns, TwoRunsAtOnceWriteTheMapsOfOne) {
  const std::string cmd = RunCommandLine(tmp_ / "shared");
  ASSERT_EQ(test::RunCommand("(" + cmd + " > " + tmp_ / "a.log" + " 2>&1 & " + cmd + " > " + tmp_ / "b.log" +
                             " 2>&1; r=$?; wait $! && exit $r)"),
            0)
      << test::ReadTextFile(tmp_ / "a.log") << test::ReadTextFile(tmp_ / "b.log");
  EXPECT_EQ(MapSums(tmp_ / "shared", tmp_ / "shared.sums"), expected_);
  // Nothing left behind: every claim released, the runs' registrations gone.
  int left = 0;
  for (const auto& e : fs::recursive_directory_iterator(Claims())) left += e.is_regular_file();
  EXPECT_EQ(left, 0);
}

// A run that waited for another run's image found, once it had the claim, that the other run
// had meanwhile finished every image and removed the states no stage reads any more (here this
// test plays that run: it writes the final maps of a whole run and removes the states). The
// waiting run judges the image again from the disk: it keeps those maps and reads no state.
// Before, it prepared the image from what it had judged before waiting and stopped with
// "file does not exist" (or computed from results that were gone).
TEST_F(ConcurrentRuns, ResultsFinishedByTheRunWaitedForAreKeptNotRead) {
  WorkClaims other(Claims(), 600);
  ASSERT_EQ(other.TryClaim(first_image_ + ".prior2"), WorkClaims::Result::kClaimed);
  int rc = -1;
  std::thread run([&] { rc = test::RunCommand(RunCommandLine(tmp_ / "shared"), tmp_ / "shared.log"); });
  const bool waited = WaitForText(tmp_ / "shared.log", "to finish stage prior2");
  const std::string one = tmp_ / "one/stereo", shared = tmp_ / "shared/stereo";
  test::RunCommand("cp " + one + "/depth_maps/* " + shared + "/depth_maps/ && cp " + one + "/normal_maps/* " + shared +
                   "/normal_maps/ && cp " + one + "/mpmvs/*.maps.json " + shared + "/mpmvs/ && rm -f " + shared +
                   "/mpmvs/*.state.bin");
  other.Release(first_image_ + ".prior2");
  run.join();
  const std::string log = test::ReadTextFile(tmp_ / "shared.log");
  EXPECT_TRUE(waited) << log;
  ASSERT_EQ(rc, 0) << log;
  EXPECT_NE(log.find(first_image_ + " (final maps exist, skipped)", log.find("to finish stage prior2")), std::string::npos) << log;
  EXPECT_EQ(log.find("no usable source views"), std::string::npos) << log;
  EXPECT_EQ(MapSums(tmp_ / "shared", tmp_ / "shared.sums"), expected_);
}

// A state whose claim another process holds may be being read there: a run that finds it no
// longer needed leaves it (the holder's own removal takes it later). Here a finished
// workspace with every state kept, one image's geometric depth map removed, is run again
// while this test holds another image's photometric claim: every other state goes, that one
// stays.
TEST_F(ConcurrentRuns, StateAnotherProcessHoldsTheClaimOfIsNotRemoved) {
  ASSERT_EQ(test::RunCommand(RunCommandLine(tmp_ / "shared") + " --MPMVS.keep_states 1", tmp_ / "kept.log"), 0)
      << test::ReadTextFile(tmp_ / "kept.log");
  test::RunCommand("cd " + tmp_ / "shared/stereo/depth_maps" + " && rm \"$(ls *.geometric.bin | tail -1)\"");
  const std::string held = tmp_ / ("shared/stereo/mpmvs/" + first_image_ + ".photometric.state.bin");
  ASSERT_TRUE(fs::exists(held));
  WorkClaims other(Claims(), 600);
  ASSERT_EQ(other.TryClaim(first_image_ + ".photometric"), WorkClaims::Result::kClaimed);
  ASSERT_EQ(test::RunCommand(RunCommandLine(tmp_ / "shared"), tmp_ / "again.log"), 0)
      << test::ReadTextFile(tmp_ / "again.log");
  std::vector<std::string> states;
  for (const auto& e : fs::directory_iterator(tmp_ / "shared/stereo/mpmvs")) {
    if (e.path().string().find(".state.bin") != std::string::npos) states.push_back(e.path());
  }
  EXPECT_EQ(states, std::vector<std::string>{held}) << test::ReadTextFile(tmp_ / "again.log");
}

TEST_F(ConcurrentRuns, RunWithOtherOptionsStopsBeforeWritingAnything) {
  test::RunCommand("rm -rf " + tmp_ / "shared/stereo/depth_maps/*" + " " + tmp_ / "shared/stereo/normal_maps/*");
  {
    WorkClaims other(Claims(), 600);
    EXPECT_TRUE(other.RegisterRun("other-options").empty());
    EXPECT_EQ(test::RunCommand(RunCommandLine(tmp_ / "shared"), tmp_ / "refused.log"), 1);
    const std::string log = test::ReadTextFile(tmp_ / "refused.log");
    EXPECT_NE(log.find("another mp_patch_match_stereo run with other options (" + WorkClaims::ThisHost() +
                       ":" + std::to_string(::getpid()) + ")"),
              std::string::npos)
        << log;
    int written = 0;
    for (const auto& e : fs::recursive_directory_iterator(tmp_ / "shared/stereo")) {
      const std::string name = e.path().filename();
      written += name.find(".state.") != std::string::npos || name.find(".bin") != std::string::npos;
    }
    EXPECT_EQ(written, 0);
  }
  // Once the other run has ended, the same command runs.
  ASSERT_EQ(test::RunCommand(RunCommandLine(tmp_ / "shared"), tmp_ / "after.log"), 0)
      << test::ReadTextFile(tmp_ / "after.log");
  EXPECT_EQ(MapSums(tmp_ / "shared", tmp_ / "shared.sums"), expected_);
}

// Issue 35, defect 1: not only --MPMVS options; every option that changes a result takes part
// in the check, COLMAP's and the patch-match.cfg the run reads. Run A (the default options)
// is held on its first image by this test; runs with another max_image_size, filter, depth
// range or configuration stop at once (timeout: before the fix they joined in and waited).
TEST_F(ConcurrentRuns, RunWithOtherColmapOptionsOrConfigIsRefusedWhileOneRuns) {
  WorkClaims other(Claims(), 600);
  ASSERT_EQ(other.TryClaim(first_image_ + ".photometric"), WorkClaims::Result::kClaimed);
  int rc = -1;
  std::thread run_a([&] { rc = test::RunCommand(RunCommandLine(tmp_ / "shared"), tmp_ / "a.log"); });
  const bool waiting = WaitForText(tmp_ / "a.log", "to finish stage photometric");
  std::string other_cfg;  // every image, with at most two sources instead of __auto__, 20
  for (const auto& e : fs::directory_iterator(tmp_ / "shared/images")) {
    other_cfg += e.path().filename().string() + "\n__auto__, 2\n";
  }
  test::WriteText(tmp_ / "other.cfg", other_cfg);
  const std::vector<std::string> others = {"--PatchMatchStereo.max_image_size 48", "--PatchMatchStereo.filter 1",
                                           "--PatchMatchStereo.depth_min 0.5 --PatchMatchStereo.depth_max 50",
                                           "--config_path " + tmp_ / "other.cfg"};
  std::vector<std::string> logs;
  std::vector<int> rcs;
  for (size_t k = 0; k < others.size(); ++k) {
    const std::string log = tmp_ / ("b" + std::to_string(k) + ".log");
    rcs.push_back(test::RunCommand("timeout 20 " + RunCommandLine(tmp_ / "shared") + " " + others[k], log));
    logs.push_back(test::ReadTextFile(log));
  }
  other.Release(first_image_ + ".photometric");
  run_a.join();
  EXPECT_TRUE(waiting) << test::ReadTextFile(tmp_ / "a.log");
  for (size_t k = 0; k < others.size(); ++k) {
    EXPECT_EQ(rcs[k], 1) << others[k] << "\n" << logs[k];
    EXPECT_NE(logs[k].find("another mp_patch_match_stereo run with other options"), std::string::npos)
        << others[k] << "\n" << logs[k];
  }
  // Run A went on alone: the maps of one run with its options.
  ASSERT_EQ(rc, 0) << test::ReadTextFile(tmp_ / "a.log");
  EXPECT_EQ(MapSums(tmp_ / "shared", tmp_ / "shared.sums"), expected_);
}

// Issue 35, defect 4: --MPMVS.image_list_path naming some images, run alone, waited forever
// for results "that other processes compute". Alone (no other run with its options for
// min(60 s, claim_lease)), it stops and says what to run; a killed wait releases its claims.
TEST_F(ConcurrentRuns, ImageListRunAloneStopsSayingWhatToRun) {
  test::WriteText(tmp_ / "list.txt", first_image_ + "\n");
  const std::string cmd = "timeout 60 " + RunCommandLine(tmp_ / "shared") + " --MPMVS.image_list_path " +
                          tmp_ / "list.txt" + " --MPMVS.claim_lease 3";
  const auto start = std::chrono::steady_clock::now();
  const int rc = test::RunCommand(cmd, tmp_ / "alone.log");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string log = test::ReadTextFile(tmp_ / "alone.log");
  EXPECT_EQ(rc, 1) << log;
  EXPECT_LT(seconds, 30) << log;
  EXPECT_NE(log.find("no other mp_patch_match_stereo run with the same options"), std::string::npos) << log;
  EXPECT_NE(log.find("without --MPMVS.image_list_path"), std::string::npos) << log;
  int left = 0;
  for (const auto& e : fs::recursive_directory_iterator(Claims())) left += e.is_regular_file();
  EXPECT_EQ(left, 0) << log;

  // The same list with the other images' run started beside it: both finish, the maps of one run.
  test::RunCommand("rm -rf " + tmp_ / "shared/stereo/mpmvs");
  const std::string list_run = RunCommandLine(tmp_ / "shared") + " --MPMVS.image_list_path " + tmp_ / "list.txt";
  ASSERT_EQ(test::RunCommand("(" + list_run + " > " + tmp_ / "l.log" + " 2>&1 & " + RunCommandLine(tmp_ / "shared") +
                             " > " + tmp_ / "all.log" + " 2>&1; r=$?; wait $! && exit $r)"),
            0)
      << test::ReadTextFile(tmp_ / "l.log") << test::ReadTextFile(tmp_ / "all.log");
  EXPECT_EQ(MapSums(tmp_ / "shared", tmp_ / "shared.sums"), expected_);
}

TEST_F(ConcurrentRuns, KilledWaitLeavesNoClaimBehind) {
  WorkClaims other(Claims(), 600);  // holds the first image, so that the run waits for it
  ASSERT_EQ(other.TryClaim(first_image_ + ".photometric"), WorkClaims::Result::kClaimed);
  test::RunCommand(RunCommandLine(tmp_ / "shared") + " > " + tmp_ / "killed.log" + " 2>&1 & echo $! > " +
                   tmp_ / "pid");
  const bool waiting = WaitForText(tmp_ / "killed.log", "to finish stage photometric");
  const std::string pid = "$(cat " + tmp_ / "pid" + ")";
  test::RunCommand("kill -TERM " + pid + "; while kill -0 " + pid + " 2>/dev/null; do sleep 0.1; done");
  EXPECT_TRUE(waiting) << test::ReadTextFile(tmp_ / "killed.log");
  other.Release(first_image_ + ".photometric");
  std::vector<std::string> left;
  for (const auto& e : fs::recursive_directory_iterator(Claims())) {
    if (e.is_regular_file()) left.push_back(e.path());
  }
  EXPECT_TRUE(left.empty()) << left.front() << "\n" << test::ReadTextFile(tmp_ / "killed.log");
  EXPECT_NE(test::ReadTextFile(tmp_ / "killed.log").find("interrupted"), std::string::npos)
      << test::ReadTextFile(tmp_ / "killed.log");
}

}  // namespace
}  // namespace mpmvs

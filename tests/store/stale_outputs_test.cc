// Stale and damaged outputs of an earlier run, missing input files and the messages that
// report them (issue 12, defects 4, 5 and 7): a rerun never keeps a damaged map as good,
// never resumes from intermediate state of other options or inputs, and says what it did.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"
#include "colmap_ext/store/state_record.h"
#include "colmap_ext/util/error.h"
#include "tests/io_test_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;

struct CapturedRun {
  MpPatchMatchSummary summary;
  std::string log;    // stdout and stderr
  std::string error;  // what() of an Error, "" when the run succeeded
};

CapturedRun RunCaptured(const MpPatchMatchRun& run) {
  CapturedRun r;
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  try {
    r.summary = RunMpPatchMatchStereo(run);
  } catch (const Error& e) {
    r.error = e.what();
  }
  r.log = testing::internal::GetCapturedStdout();
  r.log += testing::internal::GetCapturedStderr();
  return r;
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

MpPatchMatchRun SmallRun(const std::string& dir) {
  MpPatchMatchRun run;
  run.workspace_path = dir;
  run.options.write_pictures = "none";
  run.options.keep_states = true;  // the tests below look at the states a finished run leaves
  run.options.max_window_scale = 1;
  run.options.iterations_per_scale = 2;
  run.options.geom_iterations = 1;
  run.options.prior_iterations = 1;
  return run;
}

std::string Depth(const std::string& dir, const std::string& name, const std::string& type) {
  return dir + "/stereo/depth_maps/" + name + "." + type + ".bin";
}

void Truncate(const std::string& path, uintmax_t keep_bytes) { fs::resize_file(path, keep_bytes); }

// --- defect 4: final maps ------------------------------------------------------------------

TEST(StaleOutputs, TruncatedFinalMapWithoutIntermediatesIsMovedAsideAndRecomputed) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  const MpPatchMatchRun run = SmallRun(tmp.path());
  ASSERT_EQ(RunCaptured(run).error, "");
  const std::string photometric = Depth(tmp.path(), "view_00.png", "photometric");
  const std::string geometric = Depth(tmp.path(), "view_00.png", "geometric");
  const std::string good_photometric = test::ReadTextFile(photometric);
  const std::string good_geometric = test::ReadTextFile(geometric);
  fs::remove_all(tmp / "stereo/mpmvs");
  Truncate(photometric, 1000);

  const CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(Contains(r.log, photometric)) << r.log;
  EXPECT_TRUE(fs::exists(photometric + ".damaged-1")) << r.log;
  EXPECT_EQ(fs::file_size(photometric + ".damaged-1"), 1000u);
  // The same maps as the first run (sources' intermediate results recomputed for it).
  EXPECT_EQ(test::ReadTextFile(photometric), good_photometric);
  EXPECT_EQ(test::ReadTextFile(geometric), good_geometric);
  EXPECT_EQ(r.summary.num_written, 1);
  EXPECT_EQ(r.summary.num_already_done, 2);

  // Now all is well: a rerun does nothing.
  const CapturedRun again = RunCaptured(run);
  EXPECT_EQ(again.summary.num_written, 0);
  EXPECT_EQ(again.summary.num_already_done, 3);
}

TEST(StaleOutputs, MapsOfAnotherImageSizeAreNotKept) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  MpPatchMatchRun run = SmallRun(tmp.path());
  run.colmap_options.max_image_size = 48;
  ASSERT_EQ(RunCaptured(run).error, "");
  EXPECT_EQ(ReadFloatMap(Depth(tmp.path(), "view_01.png", "geometric"), 1).width, 48);

  run.colmap_options.max_image_size = -1;
  const CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_EQ(r.summary.num_written, 3) << r.log;
  for (const std::string name : {"view_00.png", "view_01.png", "view_02.png"}) {
    for (const std::string type : {"photometric", "geometric"}) {
      const FloatMap depth = ReadFloatMap(Depth(tmp.path(), name, type), 1);
      EXPECT_EQ(depth.width, 64) << name << " " << type;
      EXPECT_EQ(depth.height, 48) << name << " " << type;
      const FloatMap normal = ReadFloatMap(tmp.path() + "/stereo/normal_maps/" + name + "." + type + ".bin", 3);
      EXPECT_EQ(normal.width, 64) << name << " " << type;
    }
  }
}

// --- issue 36, item 9: a change of options is no damage --------------------------------------

// Every file under dir whose name holds `part`.
std::vector<std::string> FilesNamed(const std::string& dir, const std::string& part) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().filename().string().find(part) != std::string::npos) found.push_back(e.path());
  }
  return found;
}

int CountLines(const std::string& text, const std::string& part) {
  int n = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) n += Contains(line, part);
  return n;
}

TEST(StaleOutputs, ChangedMaxImageSizeRecomputesTheMapsWithoutDebrisOrWarnings) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  MpPatchMatchRun run = SmallRun(tmp.path());
  run.colmap_options.max_image_size = 48;
  ASSERT_EQ(RunCaptured(run).error, "");

  run.colmap_options.max_image_size = -1;
  const CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_EQ(r.summary.num_written, 3) << r.log;
  EXPECT_EQ(FilesNamed(tmp / "stereo", ".damaged").size(), 0u) << r.log;
  EXPECT_EQ(CountLines(r.log, "WARNING"), 0) << r.log;
  // One line says what changed and that the maps are recomputed.
  EXPECT_EQ(CountLines(r.log, "max_image_size"), 1) << r.log;
  EXPECT_EQ(ReadFloatMap(Depth(tmp.path(), "view_01.png", "geometric"), 1).width, 64);
}

TEST(StaleOutputs, ChangedMpmvsResultOptionRecomputesTheMaps) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  MpPatchMatchRun run = SmallRun(tmp.path());
  ASSERT_EQ(RunCaptured(run).error, "");
  const std::string geometric = Depth(tmp.path(), "view_00.png", "geometric");
  const std::string seed1 = test::ReadTextFile(geometric);

  run.options.seed = 7;
  CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_FALSE(Contains(r.log, "nothing to do")) << r.log;
  EXPECT_EQ(r.summary.num_written, 3) << r.log;
  EXPECT_EQ(CountLines(r.log, "MPMVS.seed"), 1) << r.log;
  EXPECT_TRUE(test::ReadTextFile(geometric) != seed1);
  EXPECT_EQ(FilesNamed(tmp / "stereo", ".damaged").size(), 0u) << r.log;

  // The same options again: the maps are kept.
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_EQ(r.summary.num_written, 0) << r.log;
  EXPECT_EQ(r.summary.num_already_done, 3) << r.log;

  // A speed option at its paper value has no line in the fingerprint, whatever the default:
  // maps of the former full-resolution default are recomputed both ways, the log naming it.
  const int half_scales = run.options.half_resolution_scales;
  ASSERT_GT(half_scales, 0);
  run.options.half_resolution_scales = 0;
  r = RunCaptured(run);
  EXPECT_EQ(r.summary.num_written, 3) << r.log;
  EXPECT_TRUE(Contains(r.log, "-> (the paper's value)")) << r.log;
  run.options.half_resolution_scales = half_scales;
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_EQ(r.summary.num_written, 3) << r.log;
  EXPECT_TRUE(Contains(r.log, "half_resolution_scales (the paper's value) -> " + std::to_string(half_scales)))
      << r.log;
}

// --- issue 35, defect 2: a valid header with a damaged payload ---------------------------------

TEST(StaleOutputs, DamagedPayloadBehindAValidHeaderIsNotKept) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  const MpPatchMatchRun run = SmallRun(tmp.path());
  ASSERT_EQ(RunCaptured(run).error, "");
  const std::string depth0 = Depth(tmp.path(), "view_00.png", "geometric");
  const std::string normal0 = tmp / "stereo/normal_maps/view_00.png.geometric.bin";
  const std::string normal1 = tmp / "stereo/normal_maps/view_01.png.geometric.bin";
  const std::string good_depth = test::ReadTextFile(depth0);
  const std::string good_normal = test::ReadTextFile(normal0);

  // Random values (some negative, one NaN) behind a valid header; another image's map.
  {
    FloatMap noise(64, 48, 1);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> dist(-5.f, 5.f);
    for (float& v : noise.data) v = dist(rng);
    noise.data[7] = std::nanf("");
    WriteFloatMap(depth0, noise);
  }
  fs::copy_file(normal1, normal0, fs::copy_options::overwrite_existing);

  CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(fs::exists(depth0 + ".damaged-1")) << r.log;
  EXPECT_TRUE(fs::exists(normal0 + ".damaged-1")) << r.log;
  EXPECT_TRUE(test::ReadTextFile(depth0) == good_depth);
  EXPECT_TRUE(test::ReadTextFile(normal0) == good_normal);
  EXPECT_EQ(r.summary.num_written, 1) << r.log;

  // Without the maps' records (stereo/mpmvs deleted, or maps from COLMAP): the values are
  // still checked (finite, not negative, inside the depth range; unit or zero normals).
  fs::remove_all(tmp / "stereo/mpmvs");
  const std::string depth1 = Depth(tmp.path(), "view_01.png", "photometric");
  FloatMap map = ReadFloatMap(depth1, 1);
  map.data[100] = -1.f;
  WriteFloatMap(depth1, map);
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(fs::exists(depth1 + ".damaged-1")) << r.log;
  EXPECT_TRUE(Contains(r.log, depth1)) << r.log;
  EXPECT_EQ(r.summary.num_written, 1) << r.log;
}

// --- defect 4: intermediate state -----------------------------------------------------------

TEST(StaleOutputs, DamagedIntermediateStateIsRecomputedNotUsed) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  const MpPatchMatchRun run = SmallRun(tmp.path());
  ASSERT_EQ(RunCaptured(run).error, "");
  const std::string geometric = Depth(tmp.path(), "view_00.png", "geometric");
  const std::string good = test::ReadTextFile(geometric);

  // Random payload behind a valid header in one state file, another truncated.
  const std::string random_state = tmp / "stereo/mpmvs/view_00.png.photometric.state.bin";
  const std::string truncated_state = tmp / "stereo/mpmvs/view_01.png.photometric.state.bin";
  ASSERT_TRUE(fs::exists(random_state));
  {
    const FloatMap state = ReadFloatMap(random_state);
    FloatMap noise(state.width, state.height, state.channels);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> dist(-1.f, 1.f);
    for (float& v : noise.data) v = dist(rng);
    WriteFloatMap(random_state, noise);
  }
  Truncate(truncated_state, 500);
  for (const auto& entry : fs::directory_iterator(tmp / "stereo/depth_maps")) fs::remove(entry.path());
  for (const auto& entry : fs::directory_iterator(tmp / "stereo/normal_maps")) fs::remove(entry.path());

  const CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(Contains(r.log, random_state)) << r.log;
  EXPECT_TRUE(Contains(r.log, truncated_state)) << r.log;
  ASSERT_FALSE(r.summary.stages.empty());
  EXPECT_EQ(r.summary.stages[0].images_computed, 2);
  EXPECT_EQ(r.summary.stages[0].images_resumed, 1);
  EXPECT_EQ(test::ReadTextFile(geometric), good);
  EXPECT_EQ(r.summary.num_written, 3);
}

TEST(StaleOutputs, IntermediateStateOfOtherOptionsOrImagesIsNotResumed) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  MpPatchMatchRun run = SmallRun(tmp.path());
  ASSERT_EQ(RunCaptured(run).error, "");
  auto delete_final_maps = [&] {
    for (const auto& entry : fs::directory_iterator(tmp / "stereo/depth_maps")) fs::remove(entry.path());
  };

  // Another seed changes every stage's result: nothing may be resumed.
  delete_final_maps();
  run.options.seed = 7;
  CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  for (const StageSummary& s : r.summary.stages) {
    EXPECT_EQ(s.images_computed, 3) << s.name;
    EXPECT_EQ(s.images_resumed, 0) << s.name;
  }
  EXPECT_TRUE(Contains(r.log, "stereo/mpmvs")) << r.log;

  // Same options again: everything resumes.
  delete_final_maps();
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  for (const StageSummary& s : r.summary.stages) EXPECT_EQ(s.images_resumed, 3) << s.name;

  // A changed image: its states are recomputed (and those that use it as a source).
  delete_final_maps();
  {
    std::vector<uint8_t> bytes;
    const std::string png = tmp / "images/view_02.png";
    std::ifstream in(png, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
    // Re-encode the same picture under another name is not needed: append a harmless byte.
    bytes.push_back(0);
    test::WriteBytes(png, bytes);
  }
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_GE(r.summary.stages[0].images_computed, 1) << r.log;
}

// States carry the math revision in their options hash: states an older mp-mvs computed
// with other per-pixel math (whose options text had another or no revision line) are
// recomputed, never resumed.
TEST(StaleOutputs, StatesOfAnotherMathRevisionHaveAnotherOptionsHash) {
  const std::string text = StateOptionsText(MpMvsOptions{});
  const std::string line = "math_revision " + std::to_string(kStateMathRevision) + "\n";
  ASSERT_EQ(text.rfind(line, 0), 0u) << text;
  const std::string older = text.substr(line.size());
  EXPECT_NE(HashText(text), HashText(older));
  EXPECT_NE(HashText(text), HashText("math_revision " + std::to_string(kStateMathRevision - 1) + "\n" + older));
}

// --- defect 5: --PatchMatchStereo.allow_missing_files ---------------------------------------

TEST(StaleOutputs, MissingImageFailsNamingAllowMissingFilesOrIsSkippedWithIt) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 4);
  fs::remove(tmp / "images/view_03.png");
  MpPatchMatchRun run = SmallRun(tmp.path());
  CapturedRun r = RunCaptured(run);
  EXPECT_TRUE(Contains(r.error, "view_03.png")) << r.error << r.log;
  EXPECT_TRUE(Contains(r.error, "allow_missing_files")) << r.error;
  EXPECT_FALSE(fs::exists(Depth(tmp.path(), "view_00.png", "geometric")));

  run.colmap_options.allow_missing_files = true;
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(Contains(r.log, "view_03.png")) << r.log;
  EXPECT_EQ(r.summary.num_written, 3);
  EXPECT_TRUE(fs::exists(Depth(tmp.path(), "view_00.png", "geometric")));
  EXPECT_FALSE(fs::exists(Depth(tmp.path(), "view_03.png", "photometric")));
}

// --- defect 7: messages -----------------------------------------------------------------------

TEST(StaleOutputs, EveryImageSkippedIsNotReportedAsAlreadyDone) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 2);
  {
    std::ofstream cfg(tmp / "stereo/patch-match.cfg");
    cfg << "view_00.png\nview_00.png\nview_01.png\nview_01.png\n";
  }
  const CapturedRun r = RunCaptured(SmallRun(tmp.path()));
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_FALSE(Contains(r.log, "exist already")) << r.log;
  EXPECT_TRUE(Contains(r.log, "No reference image can run")) << r.log;
  EXPECT_EQ(r.summary.num_already_done, 0);
  EXPECT_EQ(r.summary.num_written, 0);
}

TEST(StaleOutputs, WrittenCountsEachReferenceOnceAndOnlyWithItsFinalMaps) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  {
    std::ofstream cfg(tmp / "stereo/patch-match.cfg");
    cfg << "view_00.png\n__all__\nview_01.png\n__all__\nview_00.png\n__all__\n";
  }
  // view_02, a source but no reference, is left out of the geometric stages (issue 35.5).
  MpPatchMatchRun run = SmallRun(tmp.path());
  run.colmap_options.allow_missing_files = true;
  CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_EQ(r.summary.num_written, 2) << r.log;
  EXPECT_EQ(r.summary.num_references, 2);
  EXPECT_TRUE(Contains(r.log, "more than once")) << r.log;

  // view_00's only source cannot run (no sources of its own): view_00 has photometric maps
  // but no geometric result, which leaves view_02 without sources in the later geometric
  // stages. Neither has its final (geometric) maps, so neither counts as written.
  test::TempDir tmp2;
  test::WriteSmallPlaneScene(tmp2.path(), 64, 48, 3);
  {
    std::ofstream cfg(tmp2 / "stereo/patch-match.cfg");
    cfg << "view_00.png\nview_01.png\nview_01.png\nview_01.png\nview_02.png\n__all__\n";
  }
  r = RunCaptured(SmallRun(tmp2.path()));
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(fs::exists(Depth(tmp2.path(), "view_00.png", "photometric")));
  EXPECT_FALSE(fs::exists(Depth(tmp2.path(), "view_00.png", "geometric")));
  EXPECT_FALSE(fs::exists(Depth(tmp2.path(), "view_02.png", "geometric")));
  EXPECT_EQ(r.summary.num_written, 0) << r.log;
}

// Issue 35, defect 5: a patch-match.cfg listing only some references. A source that is no
// reference has no results for the geometric stages: as COLMAP on missing source maps, the
// run stops before any work unless allow_missing_files leaves such sources out; a
// reference listing itself is reported; the summary accounts for every image.
TEST(StaleOutputs, ConfigWithSourcesThatAreNoReferencesStopsOrLeavesThemOutSaidSo) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  test::WriteText(tmp / "stereo/patch-match.cfg",
                  "view_00.png\nview_01.png, view_02.png\nview_01.png\nview_01.png, view_00.png\n");
  MpPatchMatchRun run = SmallRun(tmp.path());
  CapturedRun r = RunCaptured(run);
  EXPECT_TRUE(Contains(r.error, "view_02.png")) << r.error << r.log;
  EXPECT_TRUE(Contains(r.error, "allow_missing_files")) << r.error;
  EXPECT_FALSE(fs::exists(Depth(tmp.path(), "view_00.png", "photometric")));

  run.colmap_options.allow_missing_files = true;
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(Contains(r.log, "view_02.png")) << r.log;
  EXPECT_EQ(r.summary.num_written, 2) << r.log;
  EXPECT_EQ(r.summary.num_not_references, 1) << r.log;

  // Without geometric stages nothing is missing.
  test::TempDir tmp2;
  test::WriteSmallPlaneScene(tmp2.path(), 64, 48, 3);
  test::WriteText(tmp2 / "stereo/patch-match.cfg", "view_00.png\nview_00.png, view_01.png\n");
  run = SmallRun(tmp2.path());
  run.colmap_options.geom_consistency = false;
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(Contains(r.log, "lists itself as a source")) << r.log;
  EXPECT_EQ(r.summary.num_written, 1);
  EXPECT_EQ(r.summary.num_references, 1);
  EXPECT_EQ(r.summary.num_not_references, 2);
}

// Issue 35, defect 8: in a single-stage run a source's missing result of the previous stage
// was an error even with allow_missing_files, which in a whole run leaves such sources out.
TEST(StaleOutputs, AllowMissingFilesLeavesOutASourceWithoutItsResultInAStageRun) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  MpPatchMatchRun run = SmallRun(tmp.path());
  run.options.stage = "photometric";
  ASSERT_EQ(RunCaptured(run).error, "");
  fs::remove(tmp / "stereo/mpmvs/view_02.png.photometric.state.bin");
  // The stage for view_00 and view_01, whose own inputs are there; view_02 is their source.
  test::WriteText(tmp / "list.txt", "view_00.png\nview_01.png\n");
  run.options.image_list_path = tmp / "list.txt";
  run.options.stage = "geometric1";
  CapturedRun r = RunCaptured(run);
  EXPECT_TRUE(Contains(r.error, "view_02.png.photometric.state.bin")) << r.error << r.log;
  EXPECT_TRUE(Contains(r.error, "allow_missing_files")) << r.error;

  run.colmap_options.allow_missing_files = true;
  r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  EXPECT_TRUE(Contains(r.log, "source view_02.png has no photometric result")) << r.log;
  EXPECT_TRUE(fs::exists(tmp / "stereo/mpmvs/view_00.png.geometric1.state.bin")) << r.log;
}

TEST(StaleOutputs, WorkspacePathThatIsAFileIsCalledAFile) {
  test::TempDir tmp;
  test::WriteText(tmp / "ws", "not a folder");
  MpPatchMatchRun run = SmallRun(tmp / "ws");
  const CapturedRun r = RunCaptured(run);
  EXPECT_TRUE(Contains(r.error, "is a file")) << r.error;
  EXPECT_FALSE(Contains(r.error, "does not exist")) << r.error;
}

TEST(StaleOutputs, GpuIndexWithoutThatDeviceWarnsAndUsesTheCpu) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 48, 36, 2);
  MpPatchMatchRun run = SmallRun(tmp.path());
  run.colmap_options.gpu_index = "3";
  run.colmap_options.geom_consistency = false;
  const CapturedRun r = RunCaptured(run);
  ASSERT_EQ(r.error, "") << r.log;
  if (!Contains(r.summary.backend, "CPU")) GTEST_SKIP() << "a CUDA device 3 exists";
  EXPECT_TRUE(Contains(r.log, "W")) << r.log;
  EXPECT_TRUE(Contains(r.log, "gpu_index 3")) << r.log;
}

TEST(StaleOutputs, TrackPointIndexOutOfRangeIsReported) {
  test::TempDir tmp;
  SparseModel model = test::MakeSampleModel();
  model.points[0].track.push_back({model.images[0].image_id, 99});
  fs::create_directories(tmp / "bin");
  WriteSparseModelBinary(model, tmp / "bin");
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  std::string error;
  try {
    ReadSparseModel(tmp / "bin");
  } catch (const Error& e) {
    error = e.what();
  }
  const std::string log = testing::internal::GetCapturedStdout() + testing::internal::GetCapturedStderr();
  EXPECT_TRUE(Contains(log + error, "2D point 99")) << log << error;
  EXPECT_TRUE(Contains(log + error, "points3D.bin")) << log << error;
}

}  // namespace
}  // namespace mpmvs

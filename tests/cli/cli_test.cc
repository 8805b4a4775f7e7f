// The colmap-mp executable as a user runs it: help, option errors, bad workspaces, COLMAP
// pass-through, and that a failed run leaves earlier outputs untouched.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int code;
  std::string output;
};

CliRun ColmapMp(const std::string& args, const std::string& log) {
  CliRun r;
  r.code = test::RunCommand("'" + test::ColmapMpExecutable() + "' " + args, log);
  r.output = test::ReadTextFile(log);
  return r;
}

TEST(Cli, HelpListsTheCommands) {
  test::TempDir tmp;
  const CliRun r = ColmapMp("help", tmp / "log");
  EXPECT_EQ(r.code, 0);
  for (const char* c : {"mp_patch_match_stereo", "demo", "evaluate", "ablation", "stereo_fusion"}) {
    EXPECT_NE(r.output.find(c), std::string::npos) << c;
  }
  const CliRun h = ColmapMp("mp_patch_match_stereo -h", tmp / "log2");
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.output.find("--MPMVS.max_window_scale"), std::string::npos);
  EXPECT_NE(h.output.find("--PatchMatchStereo.geom_consistency"), std::string::npos);
}

TEST(Cli, OptionErrorsAreClear) {
  test::TempDir tmp;
  CliRun r = ColmapMp("mp_patch_match_stereo --workspace_path " + tmp.path() + " --PatchMatchStereo.bogus 1",
                   tmp / "log");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("unknown option --PatchMatchStereo.bogus"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--PatchMatchStereo.max_image_size"), std::string::npos);  // lists valid ones
  r = ColmapMp("mp_patch_match_stereo --workspace_path " + tmp.path() + " --PatchMatchStereo.max_image_size big",
               tmp / "log");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("bad value 'big' for option --PatchMatchStereo.max_image_size"), std::string::npos);
  r = ColmapMp("mp_patch_match_stereo", tmp / "log");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("missing required option --workspace_path"), std::string::npos);
  r = ColmapMp("mp_patch_match_stereo --workspace_path " + tmp.path() + " --MPMVS.max_window_scale 9", tmp / "log");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("MPMVS.max_window_scale"), std::string::npos);
  r = ColmapMp("mp_patch_match_stereo --workspace_path " + tmp.path() + " --MPMVS.chroma_weight -1", tmp / "log");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("MPMVS.chroma_weight"), std::string::npos);
}

TEST(Cli, MissingWorkspaceNamesThePath) {
  test::TempDir tmp;
  const std::string missing = tmp / "no_such_workspace";
  const CliRun r = ColmapMp("mp_patch_match_stereo --workspace_path " + missing, tmp / "log");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find(missing), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(missing));
}

TEST(Cli, OtherCommandsGoToColmapWithTheirExitCode) {
  MPMVS_REQUIRE_COLMAP(colmap);
  test::TempDir tmp;
  // A failing colmap command: same exit code and message as colmap itself.
  const int direct = test::RunCommand("'" + colmap + "' stereo_fusion --workspace_path " + tmp.path(), tmp / "d");
  const CliRun r = ColmapMp("stereo_fusion --workspace_path " + tmp.path(), tmp / "log");
  EXPECT_EQ(r.code, direct);
  EXPECT_NE(direct, 0);
  EXPECT_EQ(r.output, test::ReadTextFile(tmp / "d"));
  // A working one: model_converter writes a text model.
  test::WriteSmallPlaneScene(tmp / "ws", 48, 36, 2);
  fs::create_directories(tmp / "txt");
  const CliRun c = ColmapMp("model_converter --input_path " + (tmp / "ws/sparse") + " --output_path " + (tmp / "txt") +
                             " --output_type TXT",
                         tmp / "log2");
  EXPECT_EQ(c.code, 0) << c.output;
  EXPECT_TRUE(fs::exists(tmp / "txt/images.txt"));
}

TEST(Cli, VersionAsOptionOrCommand) {
  test::TempDir tmp;
  for (const char* form : {"--version", "version"}) {
    const CliRun r = ColmapMp(form, tmp / "log");
    EXPECT_EQ(r.code, 0) << form;
    EXPECT_EQ(r.output.rfind("colmap-mp ", 0), 0u) << r.output;
  }
}

// A script written for COLMAP runs MP-MVS under COLMAP's command name, and says so.
TEST(Cli, PatchMatchStereoUnderColmapsNameRunsMpMvs) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 48, 36, 2);
  const CliRun r = ColmapMp("patch_match_stereo --workspace_path " + tmp.path() +
                                " --workspace_format COLMAP --PatchMatchStereo.geom_consistency true",
                            tmp / "log");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("colmap-mp patch_match_stereo runs MP-MVS (mp_patch_match_stereo); COLMAP's own is `"),
            std::string::npos)
      << r.output;
  // Each reference's sources, once (log_level 2, the default).
  const size_t sources = r.output.find("view_00.png: 1 source image: view_01.png\n");
  EXPECT_NE(sources, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("view_00.png: 1 source image", sources + 1), std::string::npos);
  EXPECT_NE(r.output.find("view_01.png: 1 source image: view_00.png\n"), std::string::npos);
  for (const char* map : {"depth_maps/view_00.png.geometric.bin", "normal_maps/view_01.png.geometric.bin"}) {
    EXPECT_TRUE(fs::exists(tmp / (std::string("stereo/") + map))) << map;
  }
  const CliRun h = ColmapMp("help", tmp / "log2");
  EXPECT_NE(h.output.find("patch_match_stereo"), h.output.find("mp_patch_match_stereo")) << h.output;
}

// COLMAP's general options: a project file (top-level keys and sections, booleans as COLMAP
// writes them), which the command line overrides, and the log options.
TEST(Cli, ProjectFileAndGeneralOptionsLikeColmap) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp / "ws", 48, 36, 2);
  {
    std::ofstream ini(tmp / "project.ini");
    ini << "# written by hand\nworkspace_path = " << (tmp / "ws") << "\nlog_to_stderr = false\nrandom_seed = 0\n"
        << "[PatchMatchStereo]\nmax_image_size = 40\ngeom_consistency = no\nwindow_radius = 5\n";
  }
  const int code = test::RunCommand("'" + test::ColmapMpExecutable() + "' mp_patch_match_stereo --project_path " +
                                        (tmp / "project.ini") +
                                        " --PatchMatchStereo.max_image_size 32 --log_to_stderr 1 2>'" +
                                        (tmp / "stderr") + "' >'" + (tmp / "stdout") + "'",
                                    "");
  ASSERT_EQ(code, 0) << test::ReadTextFile(tmp / "stderr");
  EXPECT_EQ(test::ReadTextFile(tmp / "stdout"), "");  // every line went to stderr
  EXPECT_NE(test::ReadTextFile(tmp / "stderr").find("mp_patch_match_stereo finished"), std::string::npos);
  // The command line's max_image_size (32 x 24), the file's geom_consistency (photometric only).
  EXPECT_EQ(ReadFloatMap(tmp / "ws/stereo/depth_maps/view_00.png.photometric.bin", 1).width, 32);
  EXPECT_FALSE(fs::exists(tmp / "ws/stereo/depth_maps/view_00.png.geometric.bin"));

  CliRun r = ColmapMp("mp_patch_match_stereo --project_path " + (tmp / "project.ini") + " --log_level 0 "
                      "--MPMVS.overwrite 1",
                      tmp / "log2");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("window_radius is accepted for COLMAP compatibility but ignored"), std::string::npos);
  EXPECT_EQ(r.output.find("stage photometric: 1/"), std::string::npos) << r.output;  // no progress lines at 0
  EXPECT_EQ(r.output.find("1 source image:"), std::string::npos) << r.output;

  { std::ofstream(tmp / "bad.ini") << "workspace_path = " << (tmp / "ws") << "\n[PatchMatchStereo]\nbogus = 1\n"; }
  r = ColmapMp("mp_patch_match_stereo --project_path " + (tmp / "bad.ini"), tmp / "log3");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("unknown option --PatchMatchStereo.bogus in " + (tmp / "bad.ini")), std::string::npos)
      << r.output;
  r = ColmapMp("mp_patch_match_stereo --project_path " + (tmp / "missing.ini"), tmp / "log4");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("cannot read the project file " + (tmp / "missing.ini")), std::string::npos) << r.output;
}

TEST(Cli, FailedRunLeavesEarlierOutputsUntouched) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  CliRun r = ColmapMp("mp_patch_match_stereo --workspace_path " + tmp.path() + " --PatchMatchStereo.window_radius 7",
                   tmp / "log");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("window_radius is accepted for COLMAP compatibility but ignored"), std::string::npos);
  const std::string depth = tmp / "stereo/depth_maps/view_00.png.geometric.bin";
  const std::string before = test::ReadTextFile(depth);
  ASSERT_FALSE(before.empty());
  const auto mtime = fs::last_write_time(depth);

  // Corrupt a source image, then ask for a full recomputation.
  { std::ofstream(tmp / "images/view_02.png", std::ios::binary) << "not a png"; }
  r = ColmapMp("mp_patch_match_stereo --workspace_path " + tmp.path() + " --MPMVS.overwrite 1", tmp / "log2");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("view_02.png"), std::string::npos) << r.output;
  EXPECT_EQ(test::ReadTextFile(depth), before);
  EXPECT_EQ(fs::last_write_time(depth), mtime);
  for (const auto& e : fs::recursive_directory_iterator(tmp / "stereo")) {
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  }
}

// Issue 35, defect 3: generate_scene into a folder that holds a workspace wrote the new scene
// beside the old maps, which the next run trusted. It refuses a non-empty folder; with
// --overwrite 1 it replaces an earlier generated scene (maps included), never anything else.
TEST(Cli, GenerateSceneRefusesAFolderInUseUnlessToldToOverwrite) {
  test::TempDir tmp;
  const std::string ws = tmp / "ws";
  const std::string small = " --scene plane --width 48 --height 36 --num_views 2";
  ASSERT_EQ(ColmapMp("generate_scene" + small + " --output_path " + ws, tmp / "gen.log").code, 0);
  const std::string old_map = ws + "/stereo/depth_maps/view_00.png.geometric.bin";
  test::RunCommand("echo old > '" + old_map + "'");

  CliRun r = ColmapMp("generate_scene" + small + " --seed 9 --output_path " + ws, tmp / "again.log");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("--overwrite 1"), std::string::npos) << r.output;
  EXPECT_EQ(test::ReadTextFile(old_map), "old\n");  // nothing touched

  r = ColmapMp("generate_scene" + small + " --seed 9 --overwrite 1 --output_path " + ws, tmp / "over.log");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(old_map)) << r.output;  // the old scene's maps went with it
  EXPECT_TRUE(fs::exists(ws + "/gt/scene_info.json"));

  // A folder that is not a generated scene is never replaced.
  const std::string other = tmp / "other";
  fs::create_directories(other + "/stereo");
  r = ColmapMp("generate_scene" + small + " --overwrite 1 --output_path " + other, tmp / "other.log");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(fs::exists(other + "/stereo"));
  EXPECT_FALSE(fs::exists(other + "/images"));
}

// Issue 35, defect 8: compare with a folder that does not exist exited 0 with 0.0 figures.
TEST(Cli, CompareRefusesAFolderThatIsNoWorkspace) {
  test::TempDir tmp;
  const std::string ws = tmp / "ws";
  ASSERT_EQ(ColmapMp("generate_scene --scene plane --width 48 --height 36 --num_views 2 --output_path " + ws,
                     tmp / "gen.log").code, 0);
  const CliRun r = ColmapMp("compare --workspace_paths " + ws + "," + tmp / "typo", tmp / "compare.log");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find(tmp / "typo"), std::string::npos) << r.output;
}

TEST(Cli, DemoRunsEndToEnd) {
  test::TempDir tmp;
  const std::string out = tmp / "demo";
  const CliRun r = ColmapMp("demo --output_path " + out + " --width 320 --height 240 --num_views 4", tmp / "log");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("all pixels (pooled)"), std::string::npos);
  EXPECT_TRUE(fs::exists(out + "/evaluation/evaluation.json"));
  EXPECT_TRUE(fs::exists(out + "/evaluation/view_00_eval.png"));
  EXPECT_TRUE(fs::exists(out + "/stereo/depth_maps/view_00.png.geometric.bin"));
  if (!test::ColmapExecutable().empty()) {
    EXPECT_TRUE(fs::exists(out + "/fused.ply"));
    EXPECT_NE(r.output.find("Point cloud"), std::string::npos);
  }
  // A folder that is not a demo is never overwritten.
  fs::create_directories(tmp / "mine");
  { std::ofstream(tmp / "mine/important.txt") << "data"; }
  const CliRun refused = ColmapMp("demo --output_path " + (tmp / "mine"), tmp / "log2");
  EXPECT_EQ(refused.code, 1);
  EXPECT_NE(refused.output.find("not an mp-mvs demo folder"), std::string::npos);
  EXPECT_EQ(test::ReadTextFile(tmp / "mine/important.txt"), "data");
}

}  // namespace
}  // namespace mpmvs

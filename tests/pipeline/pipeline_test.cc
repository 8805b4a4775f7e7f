// mp_patch_match_stereo end to end on synthetic scenes with exact ground truth: accuracy of
// the default pipeline, stage outputs, resume/skip behaviour and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/error.h"
#include "tests/io_test_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

namespace fs = std::filesystem;

struct PlaneAccuracy {
  int considered = 0;
  double depth_within = 0;   // share within 0.5 % depth
  double normal_within = 0;  // share within 5 degrees
};

// Pixels of each view whose GT point is seen by at least one other view (inside it and not
// occluded per that view's GT depth).
PlaneAccuracy MeasurePlaneAccuracy(const std::string& dir) {
  const DenseWorkspace ws = LoadDenseWorkspace(dir, -1);
  PlaneAccuracy acc;
  int good_depth = 0, good_normal = 0;
  std::vector<FloatMap> gt_depth;
  for (const DenseView& v : ws.views) gt_depth.push_back(ReadFloatMap(dir + "/gt/depth_maps/" + v.name + ".bin", 1));
  for (size_t r = 0; r < ws.views.size(); ++r) {
    const DenseView& ref = ws.views[r];
    const FloatMap depth = ReadFloatMap(ws.DepthMapPath(r, "geometric"), 1);
    const FloatMap normal = ReadFloatMap(ws.NormalMapPath(r, "geometric"), 3);
    const FloatMap gt_normal = ReadFloatMap(dir + "/gt/normal_maps/" + ref.name + ".bin", 3);
    for (int row = 0; row < ref.height; ++row) {
      for (int col = 0; col < ref.width; ++col) {
        const double z = gt_depth[r].At(row, col);
        if (!(z > 0)) continue;
        const double Xc[3] = {z * (col - ref.K[2]) / ref.K[0], z * (row - ref.K[5]) / ref.K[4], z};
        double Xw[3];
        for (int i = 0; i < 3; ++i) {
          Xw[i] = ref.R[0 + i] * (Xc[0] - ref.T[0]) + ref.R[3 + i] * (Xc[1] - ref.T[1]) +
                  ref.R[6 + i] * (Xc[2] - ref.T[2]);
        }
        bool seen = false;
        for (size_t s = 0; s < ws.views.size() && !seen; ++s) {
          if (s == r) continue;
          const DenseView& src = ws.views[s];
          double Xs[3];
          for (int i = 0; i < 3; ++i) {
            Xs[i] = src.R[3 * i] * Xw[0] + src.R[3 * i + 1] * Xw[1] + src.R[3 * i + 2] * Xw[2] + src.T[i];
          }
          if (Xs[2] <= 0) continue;
          const double x = src.K[0] * Xs[0] / Xs[2] + src.K[2], y = src.K[4] * Xs[1] / Xs[2] + src.K[5];
          const int c = static_cast<int>(std::lround(x)), rr = static_cast<int>(std::lround(y));
          if (c < 5 || rr < 5 || c >= src.width - 5 || rr >= src.height - 5) continue;
          const double zs = gt_depth[s].At(rr, c);
          if (zs > 0 && std::abs(zs - Xs[2]) < 0.01 * Xs[2]) seen = true;
        }
        if (!seen) continue;
        ++acc.considered;
        if (std::abs(depth.At(row, col) - z) < 0.005 * z) ++good_depth;
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += normal.At(row, col, k) * gt_normal.At(row, col, k);
        if (dot > std::cos(5.0 * M_PI / 180.0)) ++good_normal;
      }
    }
  }
  acc.depth_within = double(good_depth) / std::max(acc.considered, 1);
  acc.normal_within = double(good_normal) / std::max(acc.considered, 1);
  return acc;
}

TEST(Pipeline, TiltedPlaneSceneMeetsAccuracyTarget) {
  test::TempDir tmp;
  SyntheticSceneOptions scene;
  scene.scene = "plane";
  scene.width = 200;
  scene.height = 150;
  scene.num_views = 4;
  scene.plane_tilt_deg = 40;
  scene.noise_sigma = 2.0;
  const SyntheticScene generated = GenerateSyntheticScene(scene, tmp.path());
  for (double angle : generated.plane_view_angles_deg) EXPECT_GE(angle, 30.0);

  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  const MpPatchMatchSummary summary = RunMpPatchMatchStereo(run);
  EXPECT_EQ(summary.num_written, 4);
  ASSERT_EQ(summary.stages.size(), 7u);  // two prior rounds, then the depth check
  EXPECT_EQ(summary.stages[0].name, "photometric");
  EXPECT_EQ(summary.stages[2].name, "prior");
  EXPECT_EQ(summary.stages[4].name, "prior2");

  const PlaneAccuracy acc = MeasurePlaneAccuracy(tmp.path());
  std::printf("plane scene: %d px seen by a source, %.2f%% within 0.5%% depth, %.2f%% normals within 5 deg\n",
              acc.considered, 100 * acc.depth_within, 100 * acc.normal_within);
  EXPECT_GT(acc.considered, 4 * 200 * 150 / 3);
  EXPECT_GE(acc.depth_within, 0.98);
  // Issue #4: 98 % of normals within 5 degrees (measured 98.8 %; 96.3 % before the per-run
  // median filter of kernels/DESIGN.md, which this bar would catch).
  EXPECT_GE(acc.normal_within, 0.98);
}

TEST(Pipeline, RerunSkipsFinishedOutputsAndResumesStages) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 96, 72, 3);
  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  run.options.write_pictures = "all";
  run.options.keep_states = true;  // below, every stage resumes from its state
  const MpPatchMatchSummary first = RunMpPatchMatchStereo(run);
  EXPECT_EQ(first.num_written, 3);
  const std::string depth_path = tmp.path() + "/stereo/depth_maps/view_00.png.geometric.bin";
  ASSERT_TRUE(fs::exists(depth_path));
  EXPECT_TRUE(fs::exists(tmp.path() + "/stereo/normal_maps/view_00.png.geometric.bin"));
  EXPECT_TRUE(fs::exists(tmp.path() + "/stereo/depth_maps/view_00.png.photometric.bin"));
  EXPECT_TRUE(fs::exists(tmp.path() + "/stereo/mpmvs/pictures/view_00.png.geometric.depth.png"));
  const auto mtime = fs::last_write_time(depth_path);
  const FloatMap before = ReadFloatMap(depth_path, 1);

  // A rerun finds everything done and touches nothing.
  const MpPatchMatchSummary second = RunMpPatchMatchStereo(run);
  EXPECT_EQ(second.num_already_done, 3);
  EXPECT_EQ(second.num_written, 0);
  EXPECT_EQ(fs::last_write_time(depth_path), mtime);

  // Final maps deleted, intermediates kept: every stage resumes from stereo/mpmvs and the
  // same maps come back.
  for (const auto& entry : fs::directory_iterator(tmp.path() + "/stereo/depth_maps")) fs::remove(entry.path());
  const MpPatchMatchSummary third = RunMpPatchMatchStereo(run);
  EXPECT_EQ(third.num_written, 3);
  for (const StageSummary& s : third.stages) {
    EXPECT_EQ(s.images_computed, 0) << s.name;
    EXPECT_EQ(s.images_resumed, 3) << s.name;
  }
  EXPECT_EQ(ReadFloatMap(depth_path, 1).data, before.data);

  // Same seed, fresh run: identical maps (deterministic).
  run.options.overwrite = true;
  RunMpPatchMatchStereo(run);
  EXPECT_EQ(ReadFloatMap(depth_path, 1).data, before.data);
}

// The depth check confirms within the tolerance of the sparse model's reprojection error
// (colmap_ext/plan/depth_check_tolerance.h): a model that says the poses are off keeps more
// depths. A rerun after the model changed computes the depth check again and resumes the
// stages before it.
TEST(Pipeline, DepthCheckWidensWithTheSparseModelsReprojectionError) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 96, 72, 3);
  const std::string sparse = tmp.path() + "/sparse";
  auto set_errors = [&](double error_px) { test::SetSparsePointErrors(sparse, [=](size_t) { return error_px; }); };
  auto written_depths = [&]() {
    const DenseWorkspace ws = LoadDenseWorkspace(tmp.path(), -1);
    size_t n = 0;
    for (size_t v = 0; v < ws.views.size(); ++v) {
      for (float z : ReadFloatMap(ws.DepthMapPath(v, "geometric"), 1).data) n += z > 0;
    }
    return n;
  };
  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  run.options.keep_states = true;
  set_errors(0.01);  // 1 %
  RunMpPatchMatchStereo(run);
  const size_t exact = written_depths();
  set_errors(1000);  // the widest tolerance, 100 %: a source's depth is enough
  const MpPatchMatchSummary wide = RunMpPatchMatchStereo(run);
  EXPECT_EQ(wide.num_written, 3);
  for (const StageSummary& s : wide.stages) {
    EXPECT_EQ(s.images_computed, s.name == "depth_check" ? 3 : 0) << s.name;
  }
  EXPECT_GT(written_depths(), exact);
}

// write_consistency_graph: every pixel with a depth has a record naming source views (the
// geometric graph: those whose results confirm its depth, so at least depth_check_views),
// also when the maps are written again from the states of a finished run.
TEST(Pipeline, ConsistencyGraphsListTheViewsOfEveryWrittenDepth) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 96, 72, 3);
  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  run.colmap_options.write_consistency_graph = true;
  RunMpPatchMatchStereo(run);
  const DenseWorkspace ws = LoadDenseWorkspace(tmp.path(), -1);
  std::map<std::string, std::string> graphs;
  for (const char* type : {"photometric", "geometric"}) {
    for (int view = 0; view < 3; ++view) {
      const FloatMap depth = ReadFloatMap(ws.DepthMapPath(view, type), 1);
      const ConsistencyGraph graph = ReadConsistencyGraph(ws.ConsistencyGraphPath(view, type));
      std::vector<int> entries(depth.data.size(), 0);  // source views listed per pixel
      for (size_t k = 0; k < graph.data.size(); k += 3 + graph.data[k + 2]) {
        const int col = graph.data[k], row = graph.data[k + 1], n = graph.data[k + 2];
        for (int j = 0; j < n; ++j) {
          const int src = graph.data[k + 3 + j];
          EXPECT_TRUE(src >= 0 && src < 3 && src != view) << type << " " << view << ": " << src;
        }
        entries[static_cast<size_t>(row) * depth.width + col] = n;
      }
      size_t with_depth = 0, listed = 0;
      for (size_t i = 0; i < entries.size(); ++i) {
        with_depth += depth.data[i] > 0;
        listed += depth.data[i] > 0 && entries[i] > 0;
        EXPECT_FALSE(entries[i] > 0 && !(depth.data[i] > 0)) << "a record without a depth";
      }
      ASSERT_GT(with_depth, entries.size() / 2) << type << " " << view;
      if (std::string(type) == "geometric") {
        EXPECT_EQ(listed, with_depth) << view;  // the depth check keeps only confirmed depths
      } else {
        EXPECT_GT(listed, with_depth * 9 / 10) << view;
      }
      graphs[ws.ConsistencyGraphPath(view, type)] = test::ReadTextFile(ws.ConsistencyGraphPath(view, type));
    }
  }
  // Maps written again from the states: the same graphs.
  for (const auto& entry : fs::directory_iterator(tmp.path() + "/stereo/depth_maps")) fs::remove(entry.path());
  for (const auto& entry : fs::directory_iterator(tmp.path() + "/stereo/consistency_graphs")) fs::remove(entry.path());
  RunMpPatchMatchStereo(run);
  for (const auto& [path, bytes] : graphs) EXPECT_EQ(test::ReadTextFile(path), bytes) << path;
}

// The pictures a user looks at by default: the depth and normal maps fusion reads; every
// stage's with "all", none with "none".
TEST(Pipeline, PicturesOfTheFinalMapsByDefaultAllStagesOrNone) {
  const auto pictures = [](const std::string& write_pictures) {
    test::TempDir tmp;
    test::WriteSmallPlaneScene(tmp.path(), 48, 36, 2);
    MpPatchMatchRun run;
    run.workspace_path = tmp.path();
    if (!write_pictures.empty()) run.options.write_pictures = write_pictures;
    RunMpPatchMatchStereo(run);
    std::set<std::string> names;
    const std::string dir = tmp.path() + "/stereo/mpmvs/pictures";
    if (fs::exists(dir)) {
      for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    }
    return names;
  };
  EXPECT_EQ(pictures(""), (std::set<std::string>{"view_00.png.geometric.depth.png", "view_00.png.geometric.normal.png",
                                                 "view_01.png.geometric.depth.png", "view_01.png.geometric.normal.png"}));
  const std::set<std::string> all = pictures("all");
  for (const char* name : {"view_00.png.geometric.depth.png", "view_00.png.photometric.normal.png",
                           "view_01.png.geometric1.depth.png", "view_01.png.prior.prior_model.png",
                           "view_01.png.depth_check.depth.png"}) {
    EXPECT_TRUE(all.count(name)) << name;
  }
  EXPECT_EQ(all.size(), 2u * 14);
  EXPECT_TRUE(pictures("none").empty());
}

TEST(Pipeline, ImageWithoutSourcesIsSkippedAndCounted) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 64, 48, 3);
  // view_02 lists only itself as source, which leaves it without sources.
  {
    std::ofstream cfg(tmp.path() + "/stereo/patch-match.cfg");
    cfg << "view_00.png\n__all__\nview_01.png\nview_00.png, view_02.png\nview_02.png\nview_02.png\n";
  }
  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  run.colmap_options.geom_consistency = false;
  const MpPatchMatchSummary summary = RunMpPatchMatchStereo(run);
  EXPECT_EQ(summary.num_references, 3);
  EXPECT_EQ(summary.num_skipped_no_sources, 1);
  EXPECT_EQ(summary.num_written, 2);
  EXPECT_FALSE(fs::exists(tmp.path() + "/stereo/depth_maps/view_02.png.photometric.bin"));
  EXPECT_TRUE(fs::exists(tmp.path() + "/stereo/depth_maps/view_00.png.photometric.bin"));
}

TEST(Pipeline, InvalidOptionsAreRejectedBeforeAnyWork) {
  test::TempDir tmp;
  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  run.options.planar_prior = "sometimes";
  try {
    RunMpPatchMatchStereo(run);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("planar_prior"), std::string::npos) << e.what();
  }
  run.options.planar_prior = "geometric";
  run.colmap_options.depth_min = 5;
  run.colmap_options.depth_max = 1;
  EXPECT_THROW(RunMpPatchMatchStereo(run), Error);
}

}  // namespace
}  // namespace mpmvs

namespace mpmvs {
namespace {

TEST(Pipeline, ColmapStyleFilterKeepsASubsetOfPixels) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp / "a", 96, 72, 3);
  test::WriteSmallPlaneScene(tmp / "b", 96, 72, 3);
  MpPatchMatchRun run;
  run.options.write_pictures = "none";
  run.workspace_path = tmp / "a";
  RunMpPatchMatchStereo(run);
  run.workspace_path = tmp / "b";
  run.colmap_options.filter = true;
  run.colmap_options.filter_min_num_consistent = 2;
  RunMpPatchMatchStereo(run);
  int kept = 0, removed = 0;
  for (const std::string name : {"view_00.png", "view_01.png", "view_02.png"}) {
    const FloatMap a = ReadFloatMap(tmp / ("a/stereo/depth_maps/" + name + ".geometric.bin"), 1);
    const FloatMap b = ReadFloatMap(tmp / ("b/stereo/depth_maps/" + name + ".geometric.bin"), 1);
    const FloatMap nb = ReadFloatMap(tmp / ("b/stereo/normal_maps/" + name + ".geometric.bin"), 3);
    ASSERT_EQ(a.data.size(), b.data.size());
    for (size_t i = 0; i < a.data.size(); ++i) {
      if (b.data[i] > 0) {
        EXPECT_EQ(a.data[i], b.data[i]);  // same seed: kept pixels are unchanged
        ++kept;
      } else if (a.data[i] > 0) {
        EXPECT_EQ(nb.data[i], 0.f);  // filtered pixels have no normal either
        ++removed;
      }
    }
  }
  // Both sources must agree: pixels seen by only one other view (image borders) go.
  EXPECT_GT(removed, 0);
  EXPECT_GT(kept, 3 * 96 * 72 / 2);
}

}  // namespace
}  // namespace mpmvs

#include "colmap_ext/evaluation/evaluation.h"

namespace mpmvs {
namespace {

// Issue #4: on the indoor scene the geometric stages must add at least 2 points of depth
// F1 at 1 % over the photometric stage.
TEST(Pipeline, IndoorGeometricBeatsPhotometricAndHoldsItsWalls) {
  test::TempDir tmp;
  SyntheticSceneOptions scene;  // indoor, 320x240, 5 views
  GenerateSyntheticScene(scene, tmp.path());
  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  run.options.write_pictures = "none";
  RunMpPatchMatchStereo(run);
  EvaluationOptions eval;
  eval.input_type = "photometric";
  const DepthEvaluation photometric = EvaluateDepthMaps(tmp.path(), tmp / "gt", eval);
  eval.input_type = "geometric";
  const DepthEvaluation geometric = EvaluateDepthMaps(tmp.path(), tmp / "gt", eval);
  const double f1_photo = photometric.pooled.at[0].f1, f1_geo = geometric.pooled.at[0].f1;
  std::printf("indoor depth F1@1%%: photometric %.1f, geometric %.1f\n", 100 * f1_photo, 100 * f1_geo);
  EXPECT_GE(f1_geo, f1_photo + 0.02);
  // Issue 13: the untextured walls and floor (75 % of the GT pixels; 8e1402a: 35.2 %,
  // kernels/DESIGN.md item 14: 56.1 %, item 15 (voted prior planes, two rounds): 66.5 %).
  const double f1_untextured = geometric.pooled_untextured.at[0].f1;
  std::printf("indoor untextured depth F1@1%%: %.1f\n", 100 * f1_untextured);
  EXPECT_GE(f1_untextured, 0.62);
}

// A plain wall inside a frame of textured posters (plain_wall scene): the pixels the frame
// encloses must follow the wall plane (8e1402a: 72.0 % within 1 %; the paper's options
// 74.8 %; kernels/DESIGN.md item 14: 98.4 %; item 15: 100.0 %).
TEST(Pipeline, PlainWallInsideATexturedFrameFollowsThePlane) {
  test::TempDir tmp;
  SyntheticSceneOptions scene;
  scene.scene = "plain_wall";
  scene.width = 240;
  scene.height = 180;
  scene.num_views = 5;
  const SyntheticScene generated = GenerateSyntheticScene(scene, tmp.path());
  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  run.options.write_pictures = "none";
  RunMpPatchMatchStereo(run);
  const std::vector<GtView> views = LoadGtViews(ReadSparseModel(tmp / "sparse"), tmp / "gt");
  ASSERT_EQ(views.size(), 5u);
  int64_t enclosed = 0, good = 0;
  for (const GtView& view : views) {
    const int W = view.depth.width, H = view.depth.height;
    ASSERT_EQ(view.untextured.size(), static_cast<size_t>(W) * H);
    const FloatMap depth = ReadFloatMap(tmp / ("stereo/depth_maps/" + view.name + ".geometric.bin"), 1);
    ASSERT_EQ(depth.width, W);
    auto textured = [&](int r, int c) { return view.depth.data[r * W + c] > 0 && !view.untextured[r * W + c]; };
    for (int r = 0; r < H; ++r) {
      for (int c = 0; c < W; ++c) {
        const float g = view.depth.data[r * W + c];
        if (!view.untextured[r * W + c] || !(g > 0)) continue;
        // Enclosed: textured pixels to its left, right, above and below.
        bool left = false, right = false, up = false, down = false;
        for (int k = 0; k < c && !left; ++k) left = textured(r, k);
        for (int k = c + 1; k < W && !right; ++k) right = textured(r, k);
        for (int k = 0; k < r && !up; ++k) up = textured(k, c);
        for (int k = r + 1; k < H && !down; ++k) down = textured(k, c);
        if (!(left && right && up && down)) continue;
        ++enclosed;
        const float z = depth.data[r * W + c];
        good += z > 0 && std::abs(z - g) < 0.01f * g;
      }
    }
  }
  const double share = static_cast<double>(good) / std::max<int64_t>(enclosed, 1);
  std::printf("plain wall: %lld enclosed untextured px, %.1f%% within 1%% depth\n",
              static_cast<long long>(enclosed), 100 * share);
  EXPECT_GT(enclosed, 5 * 240 * 180 / 4);
  EXPECT_GE(share, 0.90);
}

}  // namespace
}  // namespace mpmvs

namespace mpmvs {
namespace {

// Every regular file under dir, by path relative to dir, with its bytes; the maps' records
// without the files' modification times, which differ between any two runs.
std::map<std::string, std::string> ReadTree(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::string text;
    if (entry.path().string().find(".maps.json") != std::string::npos) {
      for (std::string line; std::getline(in, line);) {
        if (line.find("\"mtime_ns\"") == std::string::npos) text += line + "\n";
      }
    } else {
      text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    files[fs::relative(entry.path(), dir).string()] = text;
  }
  return files;
}

void ExpectSameTrees(const std::string& a, const std::string& b) {
  const std::map<std::string, std::string> ta = ReadTree(a), tb = ReadTree(b);
  ASSERT_EQ(ta.size(), tb.size());
  for (const auto& file : ta) {
    auto other = tb.find(file.first);
    ASSERT_NE(other, tb.end()) << file.first;
    EXPECT_TRUE(file.second == other->second) << file.first << " differs";
  }
}

// While a reference image runs, the controller writes the previous image's outputs and
// assembles the next one (images, source depth maps, initial state, planar prior): on the
// CPU on a thread beside the passes (cpu_side_work), with CUDA while its kernels run. It
// must write exactly the files of the serial order, also when a rerun mixes skipped,
// resumed and computed reference images.
TEST(Pipeline, LookAheadAssemblyWritesIdenticalFiles) {
  test::TempDir tmp;
  for (const char* name : {"plain", "ahead"}) test::WriteSmallPlaneScene(tmp / name, 80, 60, 4);
  MpPatchMatchRun run;
  run.options.write_pictures = "none";
  run.options.keep_states = true;  // a state is removed below
  std::string last_stage;
  for (const char* name : {"plain", "ahead"}) {
    run.workspace_path = tmp / name;
    run.cpu_side_work = std::string(name) == "ahead";
    const MpPatchMatchSummary summary = RunMpPatchMatchStereo(run);
    EXPECT_EQ(summary.num_written, 4);
    EXPECT_GT(summary.cpu_seconds, 0);
    EXPECT_GE(summary.serial_seconds, 0);
    EXPECT_LT(summary.serial_seconds, summary.seconds);
    ASSERT_GE(summary.stages.size(), 3u);
    last_stage = summary.stages.back().name;
  }
  ExpectSameTrees(tmp / "plain", tmp / "ahead");

  // view_01 loses its final maps and its last stage; view_02 its final maps only.
  for (const char* name : {"plain", "ahead"}) {
    const std::string ws = tmp / name;
    for (const std::string view : {"view_01.png", "view_02.png"}) {
      for (const char* dir : {"depth_maps", "normal_maps"}) {
        for (const char* type : {"photometric", "geometric"}) {
          fs::remove(ws + "/stereo/" + dir + "/" + view + "." + type + ".bin");
        }
      }
    }
    ASSERT_TRUE(fs::remove(ws + "/stereo/mpmvs/view_01.png." + last_stage + ".state.bin"));
    run.workspace_path = ws;
    run.cpu_side_work = std::string(name) == "ahead";
    const MpPatchMatchSummary summary = RunMpPatchMatchStereo(run);
    EXPECT_EQ(summary.num_written, 2);
    EXPECT_EQ(summary.stages.back().images_computed, 1);
  }
  ExpectSameTrees(tmp / "plain", tmp / "ahead");
}

// Stage states in stereo/mpmvs go once no stage reads them: at most two stages' states at a
// time, none at the end; the maps are those of a run that keeps every state.
TEST(Pipeline, StageStatesGoOnceNoStageReadsThem) {
  test::TempDir tmp;
  for (const char* name : {"keep", "remove"}) test::WriteSmallPlaneScene(tmp / name, 96, 72, 3);
  MpPatchMatchRun run;
  run.options.write_pictures = "none";
  run.workspace_path = tmp / "keep";
  run.options.keep_states = true;
  const MpPatchMatchSummary kept = RunMpPatchMatchStereo(run);
  run.workspace_path = tmp / "remove";
  run.options.keep_states = false;
  const MpPatchMatchSummary removed = RunMpPatchMatchStereo(run);
  const auto states = [&](const std::string& ws) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(ws + "/stereo/mpmvs")) n += e.path().extension() == ".bin";
    return n;
  };
  const size_t num_stages = kept.stages.size();
  EXPECT_EQ(states(tmp / "keep"), static_cast<int>(3 * num_stages));
  EXPECT_EQ(states(tmp / "remove"), 0);
  const uint64_t state_bytes = fs::file_size(tmp / "keep/stereo/mpmvs/view_00.png.photometric.state.bin");
  EXPECT_GE(kept.intermediate_final_bytes, 3 * num_stages * state_bytes);
  EXPECT_LT(removed.intermediate_peak_bytes, 3 * 3 * state_bytes);  // two stages at a time
  EXPECT_GE(removed.intermediate_peak_bytes, 3 * 2 * state_bytes);
  EXPECT_LT(removed.intermediate_final_bytes, state_bytes);  // the claims folder only
  ExpectSameTrees(tmp / "keep/stereo/depth_maps", tmp / "remove/stereo/depth_maps");
  ExpectSameTrees(tmp / "keep/stereo/normal_maps", tmp / "remove/stereo/normal_maps");

  // Maps lost after the states went: computed again, the same.
  fs::remove(tmp / "remove/stereo/depth_maps/view_01.png.geometric.bin");
  fs::remove(tmp / "remove/stereo/normal_maps/view_02.png.photometric.bin");
  const MpPatchMatchSummary again = RunMpPatchMatchStereo(run);
  EXPECT_EQ(again.num_written, 2);
  EXPECT_EQ(states(tmp / "remove"), 0);
  ExpectSameTrees(tmp / "keep/stereo/depth_maps", tmp / "remove/stereo/depth_maps");
  ExpectSameTrees(tmp / "keep/stereo/normal_maps", tmp / "remove/stereo/normal_maps");
}

// A run split by stage (as Slurm's job arrays run it), one stage done for one image only (a
// shard, or a run killed within the stage) and then resumed, removing states as it goes: the
// maps of one run, and no image computed twice in a stage.
TEST(Pipeline, StageByStageRunWithRemovedStatesResumesExactly) {
  test::TempDir tmp;
  for (const char* name : {"one", "split"}) test::WriteSmallPlaneScene(tmp / name, 96, 72, 3);
  MpPatchMatchRun run;
  run.options.write_pictures = "none";
  run.workspace_path = tmp / "one";
  const MpPatchMatchSummary one = RunMpPatchMatchStereo(run);
  run.workspace_path = tmp / "split";
  for (const StageSummary& stage : one.stages) {
    run.options.stage = stage.name;
    if (stage.name == "prior") {
      test::WriteText(tmp / "list.txt", "view_00.png\n");
      run.options.image_list_path = tmp / "list.txt";
      EXPECT_EQ(RunMpPatchMatchStereo(run).stages[0].images_computed, 1);
      EXPECT_FALSE(fs::exists(tmp / "split/stereo/mpmvs/view_01.png.photometric.state.bin"));
      EXPECT_TRUE(fs::exists(tmp / "split/stereo/mpmvs/view_01.png.geometric1.state.bin"));
      run.options.stage = "all";
      run.options.image_list_path = "";
      const MpPatchMatchSummary resumed = RunMpPatchMatchStereo(run);
      EXPECT_EQ(resumed.stages[0].images_computed, 0);  // photometric: not needed again
      EXPECT_EQ(resumed.stages[1].images_computed, 0);  // geometric1: resumed by the prior stage
      EXPECT_EQ(resumed.stages[2].images_computed, 2);  // prior: the two left
      EXPECT_EQ(resumed.stages[3].images_computed, 3);
      break;
    }
    const MpPatchMatchSummary part = RunMpPatchMatchStereo(run);
    ASSERT_EQ(part.stages.size(), 1u);
    EXPECT_EQ(part.stages[0].images_computed, 3) << stage.name;
  }
  ExpectSameTrees(tmp / "one/stereo/depth_maps", tmp / "split/stereo/depth_maps");
  ExpectSameTrees(tmp / "one/stereo/normal_maps", tmp / "split/stereo/normal_maps");
}

// A depth map write that fails while the next image runs (the CPU's side work, on its own
// thread) is the run's error, naming the file, as it was in the serial order; the images
// written before it keep their maps.
class FailingDepthWriteIo : public MpMvsWorkspaceIo {
 public:
  explicit FailingDepthWriteIo(std::string failing_name) : failing_name_(std::move(failing_name)) {}
  void WriteDepthMap(const std::string& path, const FloatMap& depth, float depth_min, float depth_max) override {
    if (path.find(failing_name_) != std::string::npos) throw Error("cannot write " + path + ": disk full");
    MpMvsWorkspaceIo::WriteDepthMap(path, depth, depth_min, depth_max);
  }

 private:
  std::string failing_name_;
};

TEST(Pipeline, WriteErrorDuringTheNextImageIsTheRunsError) {
  test::TempDir tmp;
  test::WriteSmallPlaneScene(tmp.path(), 80, 60, 4);
  MpPatchMatchRun run;
  run.workspace_path = tmp.path();
  run.options.write_pictures = "none";
  run.colmap_options.geom_consistency = false;  // one stage: view_01's maps are written while view_02 runs
  FailingDepthWriteIo io("view_01.png.photometric");
  try {
    RunMpPatchMatchStereo(run, &io);
    FAIL() << "the failed write was not reported";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("view_01.png.photometric.bin: disk full"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(tmp.path() + "/stereo/depth_maps/view_00.png.photometric.bin"));
  EXPECT_FALSE(fs::exists(tmp.path() + "/stereo/depth_maps/view_01.png.photometric.bin"));
}

}  // namespace
}  // namespace mpmvs

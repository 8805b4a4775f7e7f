// Splitting a run over processes: the shard rule, and that any split (shards x stages, run
// one after another or concurrently) writes the same maps, byte for byte, as one process.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>

#include "colmap_ext/plan/shard.h"
#include "colmap_ext/util/error.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

DenseWorkspace FakeWorkspace(const std::vector<std::pair<int, int>>& sizes) {
  DenseWorkspace ws;
  for (size_t i = 0; i < sizes.size(); ++i) {
    DenseView v;
    v.name = "img" + std::to_string(i) + ".png";
    v.width = sizes[i].first;
    v.height = sizes[i].second;
    ws.views.push_back(v);
  }
  return ws;
}

std::vector<ReferenceProblem> Problems(int n, int sources) {
  std::vector<ReferenceProblem> problems;
  for (int i = 0; i < n; ++i) {
    ReferenceProblem p;
    p.ref = i;
    for (int s = 0; s < sources; ++s) p.src.push_back((i + s + 1) % n);
    problems.push_back(p);
  }
  return problems;
}

TEST(Shard, ParsesAndRejects) {
  EXPECT_EQ(ParseShard("").count, 1);
  const ShardSpec s = ParseShard("2/5");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 5);
  for (const char* bad : {"5/5", "1", "a/3", "-1/3", "1/0", "1/3/4", "/3"}) {
    EXPECT_THROW(ParseShard(bad), Error) << bad;
  }
}

TEST(Shard, SplitCoversEveryImageOnceAndBalancesWork) {
  // One big image and five small ones: the big one alone in a shard, the rest balanced.
  const DenseWorkspace ws = FakeWorkspace({{100, 100}, {400, 300}, {100, 100}, {100, 100}, {100, 100}, {100, 100}});
  const auto problems = Problems(6, 2);
  const auto shards = SplitIntoShards(ws, problems, {}, 3);
  ASSERT_EQ(shards.size(), 3u);
  std::multiset<size_t> all;
  for (const auto& s : shards) {
    EXPECT_TRUE(std::is_sorted(s.begin(), s.end()));  // patch-match.cfg order within a shard
    all.insert(s.begin(), s.end());
  }
  EXPECT_EQ(all, (std::multiset<size_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(shards[0], (std::vector<size_t>{1}));  // the largest goes first, to shard 0
  EXPECT_EQ(shards[1].size(), 3u);                 // 0, 3, 5 and 2, 4 by the tie rules
  EXPECT_EQ(shards[2].size(), 2u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(SelectShard(ws, problems, {}, {k, 3}), shards[k]);
  // More shards than images: the extra shards are empty.
  const auto many = SplitIntoShards(ws, problems, {}, 8);
  EXPECT_TRUE(many[7].empty());
}

TEST(Shard, ImageListRestrictsAndNamesUnknownImages) {
  const DenseWorkspace ws = FakeWorkspace({{10, 10}, {10, 10}, {10, 10}});
  const auto problems = Problems(3, 1);
  EXPECT_EQ(SelectShard(ws, problems, {"img2.png", "img0.png"}, {}), (std::vector<size_t>{0, 2}));
  try {
    SelectShard(ws, problems, {"nope.png"}, {});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nope.png"), std::string::npos);
  }
  test::TempDir tmp;
  std::ofstream(tmp / "list.txt") << "# comment\n img1.png \n\nimg2.png\n";
  EXPECT_EQ(ReadImageList(tmp / "list.txt"), (std::vector<std::string>{"img1.png", "img2.png"}));
}

// sha256 of every map and stage file (not claims) of a workspace.
std::string Sums(const std::string& ws, const std::string& log) {
  test::RunCommand("cd '" + ws + "' && find stereo -name '*.bin' -not -path '*/claims/*' | sort | xargs sha256sum",
                   log);
  return test::ReadTextFile(log);
}

TEST(Shard, AnySplitGivesTheMapsOfOneProcess) {
  test::TempDir tmp;
  const std::string exe = "'" + test::ColmapMpExecutable() + "'";
  ASSERT_EQ(test::RunCommand(exe + " generate_scene --scene indoor --width 96 --height 72 --num_views 4 --output_path " +
                                 tmp / "base",
                             tmp / "gen.log"),
            0);
  auto run = [&](const std::string& ws, const std::string& extra, const std::string& log) {
    return test::RunCommand(exe + " mp_patch_match_stereo --workspace_path " + ws +
                                " --PatchMatchStereo.num_threads 1 --MPMVS.write_pictures none " + extra,
                            log);
  };
  test::RunCommand("cp -r " + tmp / "base" + " " + tmp / "one" + " && cp -r " + tmp / "base" + " " + tmp / "split" +
                   " && cp -r " + tmp / "base" + " " + tmp / "together");
  ASSERT_EQ(run(tmp / "one", "", tmp / "one.log"), 0);
  const std::string expected = Sums(tmp / "one", tmp / "one.sums");
  ASSERT_FALSE(expected.empty());

  // Stage by stage, shard by shard, in reverse order; a stage before its inputs is an error.
  EXPECT_NE(run(tmp / "split", "--MPMVS.stage geometric1", tmp / "early.log"), 0);
  EXPECT_NE(test::ReadTextFile(tmp / "early.log").find("photometric.state.bin"), std::string::npos);
  for (const char* stage : {"photometric", "geometric1", "prior", "geometric2", "prior2", "geometric3", "depth_check"}) {
    for (int k = 2; k >= 0; --k) {
      ASSERT_EQ(run(tmp / "split", std::string("--MPMVS.stage ") + stage + " --MPMVS.shard " + std::to_string(k) + "/3",
                    tmp / "split.log"),
                0)
          << test::ReadTextFile(tmp / "split.log");
    }
  }
  EXPECT_EQ(Sums(tmp / "split", tmp / "split.sums"), expected);

  // Two shards of whole runs at once: each waits for the other's inputs.
  ASSERT_EQ(test::RunCommand("(" + exe + " mp_patch_match_stereo --workspace_path " + tmp / "together" +
                                 " --PatchMatchStereo.num_threads 1 --MPMVS.write_pictures none --MPMVS.shard 0/2 & " +
                                 exe + " mp_patch_match_stereo --workspace_path " + tmp / "together" +
                                 " --PatchMatchStereo.num_threads 1 --MPMVS.write_pictures none --MPMVS.shard 1/2;"
                                 " r=$?; wait $! && exit $r)",
                             tmp / "together.log"),
            0);
  EXPECT_EQ(Sums(tmp / "together", tmp / "together.sums"), expected);

  // A shard without images exits 0 and says so.
  ASSERT_EQ(run(tmp / "one", "--MPMVS.shard 7/8", tmp / "empty.log"), 0);
  EXPECT_NE(test::ReadTextFile(tmp / "empty.log").find("no reference images"), std::string::npos);
}

}  // namespace
}  // namespace mpmvs

// mp-mvs on a real one-node Slurm cluster (Debian's slurm-wlm and munge, started by
// tests/slurm/one_node_cluster.sh under a temporary folder, on its own ports, stopped by pid):
// slurm_submit's job arrays give the maps of one process, byte for byte, also after a task
// is cancelled mid-run and the submission repeated. Built as its own executable so that
// ctest can give it RESOURCE_LOCK slurm. On Debian as root a missing Slurm is a failure
// (CI must run this); elsewhere the tests skip.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <sstream>
#include <thread>

#include "colmap_ext/util/file_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

const std::string kClusterScript = std::string(MPMVS_SOURCE_DIR) + "/tests/slurm/one_node_cluster.sh";

bool HaveSlurm() {
  return test::RunCommand("(command -v sbatch && command -v squeue && command -v scancel && "
                          "PATH=$PATH:/usr/sbin command -v slurmctld && PATH=$PATH:/usr/sbin command -v slurmd && "
                          "PATH=$PATH:/usr/sbin command -v munged && PATH=$PATH:/usr/sbin command -v mungekey) >/dev/null 2>&1") == 0;
}

class Slurm : public ::testing::Test {
 protected:
  void SetUp() override {
    const bool debian_root = ::geteuid() == 0 && FileExists("/etc/debian_version");
    if (!HaveSlurm()) {
      if (debian_root) FAIL() << "Slurm is not installed: apt-get install slurm-wlm munge (CI must run this test)";
      GTEST_SKIP() << "Slurm (slurm-wlm, munge) not installed; the one-node cluster test needs them";
    }
    if (::geteuid() != 0) GTEST_SKIP() << "the one-node Slurm cluster runs its daemons as root";
    ASSERT_TRUE(!test::ColmapExecutable().empty()) << "colmap is needed for stereo_fusion";
    cluster_ = tmp_ / "cluster";
    const int code = test::RunCommand("'" + kClusterScript + "' start " + cluster_, tmp_ / "cluster.log");
    started_ = true;
    ASSERT_EQ(code, 0) << test::ReadTextFile(tmp_ / "cluster.log");
    ::setenv("SLURM_CONF", (cluster_ + "/slurm.conf").c_str(), 1);
  }
  void TearDown() override {
    if (started_) test::RunCommand("'" + kClusterScript + "' stop " + cluster_, tmp_ / "stop.log");
  }

  std::string Exe() const { return "'" + test::ColmapMpExecutable() + "'"; }

  // "id state reason" of every queued job of the given ids.
  std::string Queue(const std::string& ids) {
    test::RunCommand("squeue -h -j " + ids + " -o '%i %T %r'", tmp_ / "queue.txt");
    return test::ReadTextFile(tmp_ / "queue.txt");
  }
  std::string JobIds(const std::string& ws) {
    std::istringstream in(test::ReadTextFile(ws + "/stereo/mpmvs/slurm/jobs.txt"));
    std::string ids;
    for (std::string stage, id; in >> stage >> id;) ids += (ids.empty() ? "" : ",") + id;
    return ids;
  }
  // Waits until no job of ids is queued, or (stuck_ok) until nothing runs and the rest waits
  // on a dependency that can never be met; returns what is left in the queue.
  std::string WaitForJobs(const std::string& ids, bool stuck_ok = false, int timeout_seconds = 900) {
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      const std::string q = Queue(ids);
      if (q.empty()) return q;
      if (stuck_ok && q.find("RUNNING") == std::string::npos && q.find("DependencyNeverSatisfied") != std::string::npos) {
        return q;
      }
      if (std::chrono::steady_clock::now() - start > std::chrono::seconds(timeout_seconds)) {
        ADD_FAILURE() << "jobs still queued after " << timeout_seconds << " s:\n" << q;
        return q;
      }
      std::this_thread::sleep_for(std::chrono::seconds(1));
    }
  }
  std::string JobStates(const std::string& ids) {
    std::string all;
    std::istringstream in(ids);
    for (std::string id; std::getline(in, id, ',');) {
      test::RunCommand("scontrol show job " + id + " | grep -o 'JobState=[A-Z_]*'", tmp_ / "states.txt");
      all += test::ReadTextFile(tmp_ / "states.txt");
    }
    return all;
  }
  std::string Sums(const std::string& ws) {
    test::RunCommand("cd '" + ws + "' && find stereo -name '*.bin' -not -path '*/claims/*' | sort | xargs sha256sum",
                     tmp_ / "sums.txt");
    return test::ReadTextFile(tmp_ / "sums.txt");
  }
  // The scene and its one-process maps (and fusion, as the Slurm fusion job runs it).
  void MakeScene(const std::string& options, int width, int height) {
    ASSERT_EQ(test::RunCommand(Exe() + " generate_scene --scene indoor --width " + std::to_string(width) +
                                   " --height " + std::to_string(height) + " --num_views 4 --output_path " +
                                   tmp_ / "base",
                               tmp_ / "gen.log"),
              0);
    test::RunCommand("cp -r " + tmp_ / "base" + " " + tmp_ / "one" + " && cp -r " + tmp_ / "base" + " " + tmp_ / "ws");
    ASSERT_EQ(test::RunCommand(Exe() + " mp_patch_match_stereo --workspace_path " + tmp_ / "one" + " " + options,
                               tmp_ / "one.log"),
              0);
    ASSERT_EQ(test::RunCommand(Exe() + " stereo_fusion --workspace_path " + tmp_ / "one" +
                                   " --workspace_format COLMAP --input_type geometric --output_path " +
                                   tmp_ / "one/fused.ply --StereoFusion.num_threads 1",
                               tmp_ / "one_fusion.log"),
              0);
  }
  int Submit(const std::string& options, const std::string& log) {
    return test::RunCommand(Exe() + " slurm_submit --workspace_path " + tmp_ / "ws" + " --shards 3 --fuse 1 " + options,
                            log);
  }

  test::TempDir tmp_;
  std::string cluster_;
  bool started_ = false;
};

TEST_F(Slurm, ThreeShardsGiveTheMapsOfOneProcess) {
  const std::string options = "--PatchMatchStereo.num_threads 1";
  MakeScene(options, 160, 120);
  ASSERT_EQ(Submit(options, tmp_ / "submit.log"), 0) << test::ReadTextFile(tmp_ / "submit.log");
  const std::string ids = JobIds(tmp_ / "ws");
  ASSERT_FALSE(ids.empty());
  EXPECT_EQ(WaitForJobs(ids), "");
  const std::string states = JobStates(ids);
  EXPECT_EQ(states.find("FAILED"), std::string::npos) << states;
  EXPECT_NE(states.find("COMPLETED"), std::string::npos) << states;
  EXPECT_EQ(Sums(tmp_ / "ws"), Sums(tmp_ / "one"));
  ASSERT_TRUE(FileExists(tmp_ / "ws/fused.ply"));
  EXPECT_EQ(test::ReadTextFile(tmp_ / "ws/fused.ply"), test::ReadTextFile(tmp_ / "one/fused.ply"));
  // A task logs its images, stage and progress with an ETA.
  test::RunCommand("cat " + tmp_ / "ws/stereo/mpmvs/slurm/logs/geometric2_*_0.out", tmp_ / "task.log");
  const std::string task = test::ReadTextFile(tmp_ / "task.log");
  EXPECT_NE(task.find("Shard 0/3"), std::string::npos) << task;
  EXPECT_NE(task.find("ETA"), std::string::npos) << task;
  // A finished workspace: a second submit does nothing.
  ASSERT_EQ(Submit(options, tmp_ / "again.log"), 0);
  EXPECT_NE(test::ReadTextFile(tmp_ / "again.log").find("Nothing to do"), std::string::npos)
      << test::ReadTextFile(tmp_ / "again.log");
}

TEST_F(Slurm, CancelledTaskIsRedoneByResubmitting) {
  // A slower photometric stage (more iterations, a larger scene: about 1.5 s per image on
  // one core), so that the task is caught while it runs; at 160 x 120 a task could finish
  // between the check and the cancel.
  const std::string options = "--PatchMatchStereo.num_threads 1 --MPMVS.iterations_per_scale 10";
  MakeScene(options, 240, 180);
  ASSERT_EQ(Submit(options, tmp_ / "submit.log"), 0) << test::ReadTextFile(tmp_ / "submit.log");
  const std::string ids = JobIds(tmp_ / "ws");
  const std::string first = ids.substr(0, ids.find(','));
  // Cancel task 1 of the photometric array once it runs.
  bool cancelled = false;
  for (int i = 0; i < 600 && !cancelled; ++i) {
    if (Queue(first + "_1").find("RUNNING") != std::string::npos) {
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      cancelled = test::RunCommand("scancel " + first + "_1", tmp_ / "scancel.log") == 0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(cancelled);
  const std::string left = WaitForJobs(ids, true);
  EXPECT_NE(left.find("DependencyNeverSatisfied"), std::string::npos) << left;  // the chain is stuck
  EXPECT_NE(JobStates(first).find("CANCELLED"), std::string::npos) << JobStates(first);
  EXPECT_NE(Sums(tmp_ / "ws"), Sums(tmp_ / "one"));

  // Resubmit: the stuck jobs are cancelled, the unfinished stages resubmitted.
  ASSERT_EQ(Submit(options, tmp_ / "resubmit.log"), 0) << test::ReadTextFile(tmp_ / "resubmit.log");
  const std::string resubmit = test::ReadTextFile(tmp_ / "resubmit.log");
  EXPECT_NE(resubmit.find("cancelling pending jobs"), std::string::npos) << resubmit;
  const std::string ids2 = JobIds(tmp_ / "ws");
  EXPECT_EQ(WaitForJobs(ids2), "");
  EXPECT_EQ(Queue(ids), "");
  EXPECT_EQ(JobStates(ids2).find("FAILED"), std::string::npos) << JobStates(ids2);
  EXPECT_EQ(Sums(tmp_ / "ws"), Sums(tmp_ / "one"));
  EXPECT_EQ(test::ReadTextFile(tmp_ / "ws/fused.ply"), test::ReadTextFile(tmp_ / "one/fused.ply"));
}

}  // namespace
}  // namespace mpmvs

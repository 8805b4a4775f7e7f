// `colmap-mp slurm_submit`: runs mp_patch_match_stereo on a Slurm cluster. One sbatch script
// per stage in WS/stereo/mpmvs/slurm/, each submitted as a job array of --shards tasks
// (task i runs --MPMVS.shard i/N --MPMVS.stage STAGE), chained with afterok; optionally a
// `colmap stereo_fusion` job after the last. Resubmitting submits only the unfinished
// stages and shards (pipeline/work_status.h) and cancels the pending jobs of the previous
// submission, which would otherwise wait forever on a failed task.
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include "colmap_ext/cli/command_util.h"
#include "colmap_ext/cli/commands.h"
#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/cli/patch_match_flags.h"
#include "colmap_ext/cli/slurm_client.h"
#include "colmap_ext/pipeline/work_status.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

struct SlurmSubmitOptions {
  int shards = 0;
  std::string partition, time, mem, account, extra;
  int cpus_per_task = 0;  // 0: Slurm's default (1)
  bool dry_run = false;
  bool fuse = false;
  std::string fused_path;  // "": WS/fused.ply
  std::string fusion_options;
};

const std::set<std::string> kOwnOptions = {"shards", "partition", "time", "cpus_per_task", "mem", "account",
                                           "extra", "dry_run", "fuse", "fused_path", "fusion_options"};

void AddSlurmOptions(OptionParser* parser, SlurmSubmitOptions* o) {
  parser->Add("shards", &o->shards, "array tasks per stage (required)");
  parser->Add("partition", &o->partition, "sbatch --partition ('': the cluster's default)");
  parser->Add("time", &o->time, "sbatch --time per task, e.g. 2:00:00");
  parser->Add("cpus_per_task", &o->cpus_per_task, "sbatch --cpus-per-task (also the threads of each task)");
  parser->Add("mem", &o->mem, "sbatch --mem, e.g. 8G");
  parser->Add("account", &o->account, "sbatch --account");
  parser->Add("extra", &o->extra, "more sbatch options, separated by blanks");
  parser->Add("dry_run", &o->dry_run, "only write the scripts and print the sbatch commands");
  parser->Add("fuse", &o->fuse, "submit `colmap stereo_fusion` after the last stage");
  parser->Add("fused_path", &o->fused_path, "fusion output (default WS/fused.ply)");
  parser->Add("fusion_options", &o->fusion_options, "more stereo_fusion options, separated by blanks");
}

std::vector<std::string> SplitWords(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

std::string AbsolutePath(const std::string& path) {
  if (!path.empty() && path[0] == '/') return path;
  char cwd[4096];
  return JoinPaths(::getcwd(cwd, sizeof(cwd)) ? cwd : ".", path);
}

std::string SelfExecutable() {
  char path[4096];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof(path) - 1);
  if (n <= 0) throw Error("slurm_submit: cannot find the path of this executable (/proc/self/exe)");
  return std::string(path, n);
}

std::string ScriptHeader(const SlurmSubmitOptions& o, const std::string& job_name, const std::string& log) {
  char cwd[4096];
  std::string h = "#!/bin/bash\n#SBATCH --job-name=" + job_name + "\n#SBATCH --output=" + log +
                  "\n#SBATCH --ntasks=1\n#SBATCH --chdir=" + std::string(::getcwd(cwd, sizeof(cwd)) ? cwd : ".") + "\n";
  if (!o.partition.empty()) h += "#SBATCH --partition=" + o.partition + "\n";
  if (!o.time.empty()) h += "#SBATCH --time=" + o.time + "\n";
  if (o.cpus_per_task > 0) h += "#SBATCH --cpus-per-task=" + std::to_string(o.cpus_per_task) + "\n";
  if (!o.mem.empty()) h += "#SBATCH --mem=" + o.mem + "\n";
  if (!o.account.empty()) h += "#SBATCH --account=" + o.account + "\n";
  return h + "set -eu\n";
}

void WriteScript(const std::string& path, const std::string& text) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << text; });
  ::chmod(path.c_str(), 0755);
}

// The previous submission's jobs (WS/stereo/mpmvs/slurm/jobs.txt: "stage job_id" lines).
std::vector<std::pair<std::string, std::string>> ReadJobs(const std::string& path) {
  std::vector<std::pair<std::string, std::string>> jobs;
  std::ifstream in(path);
  for (std::string stage, id; in >> stage >> id;) jobs.emplace_back(stage, id);
  return jobs;
}

// Cancels what is left pending of the previous submission (after a failed task its
// afterok dependents never start); running tasks go on, their images claimed.
void CancelPrevious(const std::string& jobs_path, bool dry_run) {
  const auto previous = ReadJobs(jobs_path);
  std::vector<std::string> ids;
  for (const auto& j : previous) ids.push_back(j.second);
  std::set<std::string> pending;
  for (const auto& q : QueuedJobs(ids)) {
    const std::string job = q.first.substr(0, q.first.find('_'));
    if (q.second == "PENDING") {
      pending.insert(job);
    } else {
      LogInfo("job " + q.first + " of the previous submission is " + q.second +
              "; it goes on (new tasks wait for the images it holds)");
    }
  }
  if (pending.empty()) return;
  std::vector<std::string> cancel(pending.begin(), pending.end());
  std::string list;
  for (const std::string& id : cancel) list += " " + id;
  LogInfo(std::string(dry_run ? "would cancel" : "cancelling") + " pending jobs of the previous submission:" + list);
  if (!dry_run) Scancel(cancel);
}

std::string JoinInts(const std::vector<int>& v) {
  std::string s;
  for (int i : v) s += (s.empty() ? "" : ",") + std::to_string(i);
  return s;
}

}  // namespace

int RunSlurmSubmitCommand(const std::vector<std::string>& args) {
  SlurmSubmitOptions o;
  OptionParser own;
  AddSlurmOptions(&own, &o);
  MpPatchMatchRun run;
  std::string pmvs_option_name;
  OptionParser mp;
  AddMpPatchMatchRunOptions(&mp, &run, &pmvs_option_name);
  // Our options here; everything else is mp_patch_match_stereo's, passed on word for word.
  std::vector<std::string> own_args, mp_args;
  bool help = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") help = true;
    const std::string name = a.rfind("--", 0) == 0 ? a.substr(2, a.find('=') - 2) : "";
    const bool ours = kOwnOptions.count(name) > 0;
    if (!ours) {
      mp_args.push_back(a);
    } else {
      own_args.push_back(a);
      if (a.find('=') == std::string::npos && i + 1 < args.size()) own_args.push_back(args[++i]);
    }
  }
  if (help) {
    std::cout << "Usage: colmap-mp slurm_submit --workspace_path WS --shards N [slurm options]\n"
                 "                              [mp_patch_match_stereo options]\n\n"
                 "Writes one sbatch script per stage into WS/stereo/mpmvs/slurm/ and submits each as\n"
                 "a job array of N tasks, chained with afterok. A second submit submits only what is\n"
                 "unfinished (nothing for a finished workspace). Slurm options:\n"
              << own.Help() << "\nmp_patch_match_stereo options (passed to every task):\n" << mp.Help();
    return 0;
  }
  own.Parse(own_args);
  mp.Parse(mp_args);
  for (const std::string& w : mp.Warnings()) LogWarning(w);
  if (o.shards < 1) throw Error("--shards must be given and >= 1");
  if (!run.options.shard.empty() || run.options.stage != "all" || !run.options.image_list_path.empty()) {
    throw Error("slurm_submit sets --MPMVS.shard and --MPMVS.stage of each task itself and runs every image; "
                "leave out --MPMVS.shard, --MPMVS.stage and --MPMVS.image_list_path");
  }
  const bool threads_given = mp.Given("PatchMatchStereo.num_threads");  // on the command line or in --project_path

  const std::string ws = AbsolutePath(run.workspace_path);
  const std::string dir = JoinPaths(ws, "stereo/mpmvs/slurm");
  CreateDirectories(JoinPaths(dir, "logs"));
  const std::string exe = SelfExecutable();
  const std::vector<StageStatus> status = ComputeWorkStatus(run, o.shards);

  // One script per stage: task i of the array runs shard i.
  std::vector<std::string> scripts;
  for (size_t s = 0; s < status.size(); ++s) {
    const std::string& stage = status[s].name;
    std::string text = ScriptHeader(o, "mpmvs-" + stage, JoinPaths(dir, "logs/" + stage + "_%A_%a.out"));
    text += "echo \"mp-mvs stage " + stage + ", shard ${SLURM_ARRAY_TASK_ID}/" + std::to_string(o.shards) +
            ", job ${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID} on $(hostname) at $(date)\"\n";
    text += "exec " + ShellQuote(exe) + " mp_patch_match_stereo";
    for (const std::string& a : mp_args) text += " " + ShellQuote(a);
    if (!threads_given) text += " --PatchMatchStereo.num_threads \"${SLURM_CPUS_PER_TASK:-1}\"";
    text += " --MPMVS.shard \"${SLURM_ARRAY_TASK_ID}/" + std::to_string(o.shards) + "\" --MPMVS.stage " + stage + "\n";
    scripts.push_back(JoinPaths(dir, std::to_string(s + 1) + "_" + stage + ".sbatch"));
    WriteScript(scripts.back(), text);
  }
  const std::string fused = o.fused_path.empty() ? JoinPaths(ws, "fused.ply") : AbsolutePath(o.fused_path);
  const std::string fusion_script = JoinPaths(dir, "fusion.sbatch");
  if (o.fuse) {
    std::string text = ScriptHeader(o, "mpmvs-fusion", JoinPaths(dir, "logs/fusion_%j.out"));
    text += "exec " + ShellQuote(exe) + " stereo_fusion --workspace_path " + ShellQuote(ws) +
            " --workspace_format COLMAP --input_type " +
            (run.colmap_options.geom_consistency ? "geometric" : "photometric") + " --output_path " +
            ShellQuote(fused) + " --StereoFusion.num_threads \"${SLURM_CPUS_PER_TASK:-1}\"";
    for (const std::string& w : SplitWords(o.fusion_options)) text += " " + ShellQuote(w);
    WriteScript(fusion_script, text + "\n");
  }

  const std::string jobs_path = JoinPaths(dir, "jobs.txt");
  CancelPrevious(jobs_path, o.dry_run);
  std::vector<std::pair<std::string, std::string>> jobs;
  std::string previous_id;
  for (size_t s = 0; s < status.size(); ++s) {
    if (status[s].unfinished_shards.empty()) {
      LogInfo("stage " + status[s].name + ": finished");
      continue;
    }
    std::vector<std::string> sbatch_args = {"--array=" + JoinInts(status[s].unfinished_shards)};
    if (!previous_id.empty()) sbatch_args.push_back("--dependency=afterok:" + previous_id);
    for (const std::string& w : SplitWords(o.extra)) sbatch_args.push_back(w);
    std::string line = "sbatch";
    for (const std::string& a : sbatch_args) line += " " + a;
    line += " " + scripts[s];
    LogInfo("stage " + status[s].name + ": " + std::to_string(status[s].unfinished_images) + " images to do in " +
            std::to_string(status[s].unfinished_shards.size()) + " shards");
    if (o.dry_run) {
      std::cout << line << "\n";
      previous_id = "<" + status[s].name + ">";
      continue;
    }
    previous_id = Sbatch(sbatch_args, scripts[s]);
    jobs.emplace_back(status[s].name, previous_id);
    LogInfo("submitted " + line + " -> job " + previous_id);
  }
  if (o.fuse && (!previous_id.empty() || !FileExists(fused))) {
    std::vector<std::string> sbatch_args;
    if (!previous_id.empty()) sbatch_args.push_back("--dependency=afterok:" + previous_id);
    for (const std::string& w : SplitWords(o.extra)) sbatch_args.push_back(w);
    if (o.dry_run) {
      std::cout << "sbatch " << (sbatch_args.empty() ? "" : sbatch_args[0] + " ") << fusion_script << "\n";
    } else {
      jobs.emplace_back("fusion", Sbatch(sbatch_args, fusion_script));
      LogInfo("submitted fusion -> job " + jobs.back().second + " (writes " + fused + ")");
    }
  }
  if (o.dry_run) {
    LogInfo("dry run: scripts written to " + dir + "; nothing submitted");
    return 0;
  }
  if (jobs.empty()) {
    LogInfo("Nothing to do: every stage of " + ws + " is finished" + (o.fuse ? " and fused" : "") + ".");
    return 0;
  }
  WriteFileAtomically(jobs_path, [&](std::ostream& out) {
    for (const auto& j : jobs) out << j.first << " " << j.second << "\n";
  });
  std::string ids;
  for (const auto& j : jobs) ids += (ids.empty() ? "" : ",") + j.second;
  std::cout << "Submitted jobs " << ids << " (stage and job id in " << jobs_path << ").\nWatch them with:\n"
            << "  squeue -j " << ids << "\n"
            << "  sacct -j " << ids << " --format=JobID,JobName,State,Elapsed,ExitCode\n"
            << "Task logs: " << dir << "/logs/STAGE_JOB_TASK.out\n"
            << "After a failure, run the same slurm_submit command again: it cancels the jobs left\n"
            << "waiting and submits only the unfinished stages and shards.\n";
  return 0;
}

}  // namespace mpmvs

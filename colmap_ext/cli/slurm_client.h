#pragma once
// The few Slurm client commands slurm_submit needs (sbatch, squeue, scancel), run as child
// processes with their output captured. Slurm finds its cluster as usual ($SLURM_CONF or
// /etc/slurm/slurm.conf).
#include <map>
#include <string>
#include <vector>

namespace mpmvs {

// Runs argv (argv[0] looked up on PATH), returns the exit code (127: could not start);
// *output gets stdout and stderr.
int RunCapture(const std::vector<std::string>& argv, std::string* output);

// sbatch --parsable ARGS SCRIPT; returns the job id. Throws Error with sbatch's message.
std::string Sbatch(const std::vector<std::string>& args, const std::string& script);

// State (PENDING, RUNNING, ...) of every job or array task of these jobs still in the queue,
// keyed by squeue's job id ("123_4", "123_[5-7]").
std::map<std::string, std::string> QueuedJobs(const std::vector<std::string>& job_ids);

// scancel of these jobs (errors are reported, not thrown: the job may have just ended).
void Scancel(const std::vector<std::string>& job_ids);

// Quotes a word for a POSIX shell script.
std::string ShellQuote(const std::string& word);

}  // namespace mpmvs

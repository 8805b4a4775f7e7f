#include "colmap_ext/cli/slurm_client.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <sstream>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {

int RunCapture(const std::vector<std::string>& argv, std::string* output) {
  output->clear();
  int fds[2];
  if (::pipe(fds) != 0) return 127;
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return 127;
  }
  if (pid == 0) {
    ::dup2(fds[1], 1);
    ::dup2(fds[1], 2);
    ::close(fds[0]);
    ::close(fds[1]);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    std::fprintf(stderr, "cannot run %s\n", args[0]);
    ::_exit(127);
  }
  ::close(fds[1]);
  std::array<char, 4096> buffer;
  ssize_t n;
  while ((n = ::read(fds[0], buffer.data(), buffer.size())) > 0) output->append(buffer.data(), n);
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

std::string Sbatch(const std::vector<std::string>& args, const std::string& script) {
  std::vector<std::string> argv = {"sbatch", "--parsable"};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.push_back(script);
  std::string out;
  const int code = RunCapture(argv, &out);
  std::string id = out.substr(0, out.find_first_of(";\n"));  // "id" or "id;cluster"
  if (code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    throw Error("sbatch " + script + " failed (exit code " + std::to_string(code) + "): " + out);
  }
  return id;
}

std::map<std::string, std::string> QueuedJobs(const std::vector<std::string>& job_ids) {
  std::map<std::string, std::string> jobs;
  if (job_ids.empty()) return jobs;
  std::string list;
  for (const std::string& id : job_ids) list += (list.empty() ? "" : ",") + id;
  std::string out;
  if (RunCapture({"squeue", "-h", "-j", list, "-o", "%i %T"}, &out) != 0) return jobs;  // ended jobs: error
  std::istringstream lines(out);
  std::string id, state;
  while (lines >> id >> state) jobs[id] = state;
  return jobs;
}

void Scancel(const std::vector<std::string>& job_ids) {
  if (job_ids.empty()) return;
  std::vector<std::string> argv = {"scancel"};
  argv.insert(argv.end(), job_ids.begin(), job_ids.end());
  std::string out;
  if (RunCapture(argv, &out) != 0) LogWarning("scancel: " + out);
}

std::string ShellQuote(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./:,@%") ==
                           std::string::npos) {
    return word;
  }
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace mpmvs

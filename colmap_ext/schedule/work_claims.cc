#include "colmap_ext/schedule/work_claims.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

// Start time of a process in clock ticks since boot (/proc/PID/stat field 22); -1 if unknown.
long long ProcessStartTime(long pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(in, stat)) return -1;
  const size_t paren = stat.rfind(')');
  if (paren == std::string::npos) return -1;
  std::istringstream fields(stat.substr(paren + 2));
  std::string field;
  for (int i = 3; i <= 22; ++i) {  // fields after the command name start at 3
    if (!(fields >> field)) return -1;
  }
  try {
    return std::stoll(field);
  } catch (const std::exception&) {
    return -1;
  }
}

// Printable text without spaces: what a host name and a tag are.
bool PlainWord(const std::string& word) {
  return !word.empty() && std::all_of(word.begin(), word.end(), [](char c) { return c > ' ' && c < 127; });
}

// False for a file that is no claim (damaged, foreign): it is never printed, only named.
bool ReadHolder(const std::string& path, ClaimHolder* holder) {
  std::ifstream in(path);
  if (!(in >> holder->host >> holder->pid >> holder->start >> holder->lease_seconds)) return false;
  if (!(in >> holder->created_ns >> holder->tag)) {  // a claim without a run tag
    holder->created_ns = 0;
    holder->tag = "-";
  }
  return PlainWord(holder->host) && PlainWord(holder->tag) && holder->pid > 0;
}

bool SameFile(const std::string& path, unsigned long long inode) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && static_cast<unsigned long long>(st.st_ino) == inode;
}

}  // namespace

std::string ClaimHolder::Describe() const { return host + ":" + std::to_string(pid); }

std::string WorkClaims::ThisHost() {
  char name[256] = {0};
  if (::gethostname(name, sizeof(name) - 1) != 0) return "unknown-host";
  return name;
}

WorkClaims::WorkClaims(std::string claims_dir, int lease_seconds)
    : dir_(std::move(claims_dir)), lease_seconds_(lease_seconds) {
  if (lease_seconds_ < 1) throw Error("claim lease must be at least 1 s");
  self_.host = ThisHost();
  self_.pid = static_cast<long>(::getpid());
  self_.start = ProcessStartTime(self_.pid);
  self_.lease_seconds = lease_seconds_;
  heartbeat_ = std::thread([this] { Heartbeat(); });
}

WorkClaims::~WorkClaims() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  heartbeat_.join();
  std::map<std::string, unsigned long long> held;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    held = held_;
  }
  for (const auto& h : held) Release(h.first);
}

std::string WorkClaims::ClaimPath(const std::string& key) const { return JoinPaths(dir_, key + ".claim"); }

bool WorkClaims::Holds(const std::string& key) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return held_.count(key) > 0;
}

WorkClaims::Result WorkClaims::TryClaim(const std::string& key, ClaimHolder* holder) {
  if (Holds(key)) return Result::kClaimed;
  const std::string path = ClaimPath(key);
  CreateDirectories(ParentPath(path));
  static std::atomic<unsigned> counter{0};
  const std::string tag = "." + self_.host + "." + std::to_string(self_.pid) + "." + std::to_string(counter++);
  const std::string tmp = path + ".tmp" + tag;
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << self_.host << " " << self_.pid << " " << self_.start << " " << lease_seconds_ << " " << self_.created_ns
        << " " << self_.tag << "\n";
    out.close();
    if (!out) ThrowFileError(tmp, "cannot write a work claim");
  }
  ClaimHolder other;
  for (int attempt = 0; attempt < 4; ++attempt) {
    if (::link(tmp.c_str(), path.c_str()) == 0) {
      struct stat st;
      if (::stat(path.c_str(), &st) != 0) break;
      ::unlink(tmp.c_str());
      std::lock_guard<std::mutex> lock(mutex_);
      held_[key] = static_cast<unsigned long long>(st.st_ino);
      return Result::kClaimed;
    }
    if (errno != EEXIST) {
      const std::string why = std::strerror(errno);
      ::unlink(tmp.c_str());
      ThrowFileError(path, "cannot create a work claim (" + why + ")");
    }
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) continue;  // released meanwhile: try again
    const bool readable = ReadHolder(path, &other);
    if (!IsStale(st, readable, other)) break;
    LogWarning(readable ? "taking over the claim " + path + " of " + other.Describe() + ", which is no longer running"
                        : "taking over the claim " + path + ", which is unreadable (damaged or not a claim) and " +
                              "has not been refreshed for --MPMVS.claim_lease s");
    // Move the stale claim out of the way; only one process can rename it.
    const std::string dead = path + ".dead" + tag;
    if (::rename(path.c_str(), dead.c_str()) != 0) continue;
    if (!SameFile(dead, static_cast<unsigned long long>(st.st_ino))) {
      // Between our look and the rename someone replaced it with a live claim: put it back.
      if (::link(dead.c_str(), path.c_str()) != 0) LogWarning("could not restore the claim " + path);
    }
    ::unlink(dead.c_str());
  }
  ::unlink(tmp.c_str());
  if (holder) *holder = other;
  return Result::kHeld;
}

bool WorkClaims::IsStale(const struct stat& st, bool readable, const ClaimHolder& holder) const {
  if (readable && holder.host == self_.host) {
    const bool gone = ::kill(static_cast<pid_t>(holder.pid), 0) != 0 && errno == ESRCH;
    const long long start = gone ? -1 : ProcessStartTime(holder.pid);
    return gone || (holder.start >= 0 && start >= 0 && start != holder.start);
  }
  // This process's lease (--MPMVS.claim_lease), not the one the file states: the user's
  // option decides, and runs sharing a workspace are given the same one.
  return std::time(nullptr) - st.st_mtime > lease_seconds_;
}

std::vector<ClaimHolder> WorkClaims::RegisterRun(const std::string& tag) {
  self_.tag = tag;
  self_.created_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  const std::string key = "runs/" + self_.host + "." + std::to_string(self_.pid);
  if (TryClaim(key) != Result::kClaimed) ThrowFileError(ClaimPath(key), "cannot register this run");
  const auto before = [](const ClaimHolder& a, const ClaimHolder& b) {
    return std::tie(a.created_ns, a.host, a.pid) < std::tie(b.created_ns, b.host, b.pid);
  };
  std::vector<ClaimHolder> earlier;
  for (const ClaimHolder& other : OtherLiveRuns()) {
    if (other.tag != tag && before(other, self_)) earlier.push_back(other);
  }
  std::sort(earlier.begin(), earlier.end(), before);
  return earlier;
}

bool WorkClaims::AnotherRunShares() const {
  const std::vector<ClaimHolder> others = OtherLiveRuns();
  return std::any_of(others.begin(), others.end(), [&](const ClaimHolder& other) { return other.tag == self_.tag; });
}

std::vector<ClaimHolder> WorkClaims::OtherLiveRuns() const {
  const std::string own =
      std::filesystem::path(ClaimPath("runs/" + self_.host + "." + std::to_string(self_.pid))).filename().string();
  std::vector<ClaimHolder> runs;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(JoinPaths(dir_, "runs"), ec)) {
    const std::string name = entry.path().filename().string();
    if (name == own || name.size() < 6 || name.compare(name.size() - 6, 6, ".claim") != 0) continue;
    struct stat st;
    ClaimHolder other;
    if (::stat(entry.path().c_str(), &st) != 0 || !ReadHolder(entry.path().string(), &other)) continue;
    if (!IsStale(st, true, other)) runs.push_back(other);
  }
  return runs;
}

void WorkClaims::Release(const std::string& key) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = held_.find(key);
  if (it == held_.end()) return;
  const std::string path = ClaimPath(key);
  if (SameFile(path, it->second)) {
    ::unlink(path.c_str());
  } else {
    LogWarning(path + " was taken over by another process while this one held it (lease too short?)");
  }
  held_.erase(it);
}

void WorkClaims::Heartbeat() {
  const auto period = std::chrono::milliseconds(std::max(250, lease_seconds_ * 1000 / 4));
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, period, [this] { return stop_; });
    if (stop_) break;
    for (const auto& h : held_) ::utimensat(AT_FDCWD, ClaimPath(h.first).c_str(), nullptr, 0);
  }
}

}  // namespace mpmvs

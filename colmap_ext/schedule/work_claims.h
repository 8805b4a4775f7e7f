#pragma once
// Per-(image, stage) claims: the one mechanism that keeps two processes from computing or
// writing the same files, whether they are Slurm array tasks on many nodes or two
// mp_patch_match_stereo runs on one workspace.
//
// A claim is the file stereo/mpmvs/claims/NAME.STAGE.claim holding "host pid start lease".
// It is written completely to a private temporary and then link()ed to its name: link
// fails when the name exists, atomically, also on NFS (v3 and v4), so exactly one process
// gets it and nobody reads a half-written claim. The holder keeps the file's mtime fresh
// (a heartbeat thread, every lease/4) and removes it when the image's stage is done.
//
// A claim is stale, and taken over, when its holder is dead:
//   same host:  the pid does not exist, or belongs to a later process (other start time);
//   other host: the mtime is older than this process's lease (the holder's heartbeat
//               stopped); the lease the file states is not used, so give every process of
//               a workspace the same --MPMVS.claim_lease.
// A file that is no readable claim is named, never printed, and judged by its mtime.
// Takeover renames the stale file to a private name (atomic; only one process wins) and
// checks it renamed the file it judged; then it claims as usual. Across hosts this relies
// on clocks agreeing to well within the lease (mtime comes from the file server's clock,
// "now" from the reader's): keep NTP running and the lease (--MPMVS.claim_lease, seconds)
// much longer than any skew.
//
// Runs whose results would differ (other options) must not share a workspace: each run also
// holds the claim runs/HOST.PID with a tag (store/result_fingerprint.h) and its wall-clock
// start, and stops when a live run with another tag started before it (RegisterRun). Runs
// with one tag, such as the Slurm array tasks of one submit, share a workspace freely.
#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

struct stat;

namespace mpmvs {

struct ClaimHolder {
  std::string host;
  long pid = 0;
  long long start = 0;  // the process's start time (clock ticks since boot; same-host pid reuse)
  int lease_seconds = 0;
  long long created_ns = 0;  // wall clock when the holder registered its run (RegisterRun)
  std::string tag = "-";     // the holder's run tag ("-": none)
  std::string Describe() const;  // "host:pid"
};

class WorkClaims {
 public:
  // claims_dir is created when needed. lease_seconds > 0.
  WorkClaims(std::string claims_dir, int lease_seconds);
  ~WorkClaims();  // releases every claim still held
  WorkClaims(const WorkClaims&) = delete;
  WorkClaims& operator=(const WorkClaims&) = delete;

  enum class Result { kClaimed, kHeld };
  // Claims `key` (a relative file name, may contain '/'): takes over a stale claim; on
  // kHeld fills *holder (if not null) with the live holder.
  Result TryClaim(const std::string& key, ClaimHolder* holder = nullptr);
  // Releases a claim this object holds (no-op otherwise).
  void Release(const std::string& key);
  bool Holds(const std::string& key) const;
  // Registers this process as a run whose results follow `tag` (no spaces; e.g. a hash of
  // the options) and returns the live runs with another tag that registered before it
  // (ordered by created_ns, then host and pid: every process agrees on the order). The
  // caller stops when the list is not empty; the earlier run goes on.
  std::vector<ClaimHolder> RegisterRun(const std::string& tag);
  // Whether another live process has registered a run with this process's tag.
  bool AnotherRunShares() const;

  std::string ClaimPath(const std::string& key) const;
  static std::string ThisHost();

 private:
  void Heartbeat();
  // Whether the claim file at path (stat st; holder read if readable) belongs to a dead holder.
  bool IsStale(const struct stat& st, bool readable, const ClaimHolder& holder) const;
  // The other live processes' run registrations.
  std::vector<ClaimHolder> OtherLiveRuns() const;

  std::string dir_;
  int lease_seconds_;
  ClaimHolder self_;
  mutable std::mutex mutex_;
  std::map<std::string, unsigned long long> held_;  // key -> inode of our claim file
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread heartbeat_;
};

}  // namespace mpmvs

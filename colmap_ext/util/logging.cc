#include "colmap_ext/util/logging.h"

#include <atomic>
#include <cstdio>
#include <ctime>
#include <mutex>
#include <sstream>

namespace mpmvs {
namespace {

std::atomic<bool> log_to_stderr{false};
std::atomic<int> log_level{2};

std::mutex& LogMutex() {
  static std::mutex mutex;
  return mutex;
}

void Log(char level, const std::string& message) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%m%d %H:%M:%S", &tm);
  std::lock_guard<std::mutex> lock(LogMutex());
  FILE* out = level == 'I' && !log_to_stderr ? stdout : stderr;
  std::fprintf(out, "%c%s %s\n", level, stamp, message.c_str());
  std::fflush(out);
}

}  // namespace

void LogInfo(const std::string& message) { Log('I', message); }
void LogDetail(const std::string& message) {
  if (log_level >= 2) Log('I', message);
}
void LogProgress(const std::string& message) {
  if (log_level >= 1) Log('I', message);
}
void LogWarning(const std::string& message) { Log('W', "WARNING: " + message); }
void LogError(const std::string& message) { Log('E', "ERROR: " + message); }

void LogHeading(const std::string& title) {
  std::lock_guard<std::mutex> lock(LogMutex());
  FILE* out = log_to_stderr ? stderr : stdout;
  std::fprintf(out, "\n==============================================================================\n"
              "%s\n"
              "==============================================================================\n",
              title.c_str());
  std::fflush(out);
}

void SetLogToStderr(bool to_stderr) { log_to_stderr = to_stderr; }
void SetLogLevel(int level) { log_level = level; }

std::string FormatNumber(double value) {
  std::ostringstream ss;
  ss << value;
  return ss.str();
}

std::string FormatDuration(double seconds) {
  if (seconds < 0) seconds = 0;
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof(buf), "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  } else {
    std::snprintf(buf, sizeof(buf), "%ld:%02ld", s / 60, s % 60);
  }
  return buf;
}

ProgressReporter::ProgressReporter(std::string label, int total)
    : label_(std::move(label)), total_(total), start_(std::chrono::steady_clock::now()) {}

double ProgressReporter::ElapsedSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressReporter::Step(const std::string& detail, const std::string& suffix) {
  ++done_;
  const double elapsed = ElapsedSeconds();
  const double eta = done_ > 0 ? elapsed / done_ * (total_ - done_) : 0.0;
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%s: %d/%d (%.0f%%) %s, elapsed %s, ETA %s", label_.c_str(),
                done_, total_, total_ > 0 ? 100.0 * done_ / total_ : 100.0, detail.c_str(),
                FormatDuration(elapsed).c_str(), FormatDuration(eta).c_str());
  LogProgress(buf + suffix);
}

}  // namespace mpmvs

#pragma once
// Log lines in COLMAP's spirit ("I1122 01:02:03 message") and a progress line with ETA.
#include <chrono>
#include <string>

namespace mpmvs {

void LogInfo(const std::string& message);
// An information line of detail (each image's sources, planar prior, depth check): shown from
// log level 2 on, like COLMAP's VLOG(2).
void LogDetail(const std::string& message);
// A progress line: shown from log level 1 on.
void LogProgress(const std::string& message);
void LogWarning(const std::string& message);
void LogError(const std::string& message);
// "==== title ====" heading like COLMAP's LOG_HEADING1.
void LogHeading(const std::string& title);

// COLMAP's --log_to_stderr: every line on stderr (default: information and headings on
// stdout, warnings and errors on stderr).
void SetLogToStderr(bool to_stderr);
// COLMAP's --log_level (default 2): below 2 no LogDetail lines, below 1 no progress lines.
void SetLogLevel(int level);

// "1:02:03" / "2:03" style duration.
std::string FormatDuration(double seconds);
// A number as std::ostream prints it by default ("0.2", "1e+06": 6 significant digits).
std::string FormatNumber(double value);

// Reports "label: i/N (pct) elapsed, ETA" after each finished item (from log level 1 on).
class ProgressReporter {
 public:
  ProgressReporter(std::string label, int total);
  // Marks one more item done; detail names it (e.g. the image), suffix follows the ETA.
  void Step(const std::string& detail, const std::string& suffix = "");
  double ElapsedSeconds() const;

 private:
  std::string label_;
  int total_;
  int done_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mpmvs

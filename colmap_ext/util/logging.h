#pragma once
// Log lines in COLMAP's spirit ("I1122 01:02:03 message") and a progress line with ETA.
#include <chrono>
#include <string>

namespace mpmvs {

void LogInfo(const std::string& message);
void LogWarning(const std::string& message);
void LogError(const std::string& message);
// "==== title ====" heading like COLMAP's LOG_HEADING1.
void LogHeading(const std::string& title);

// "1:02:03" / "2:03" style duration.
std::string FormatDuration(double seconds);
// A number as std::ostream prints it by default ("0.2", "1e+06": 6 significant digits).
std::string FormatNumber(double value);

// Reports "label: i/N (pct) elapsed, ETA" after each finished item.
class ProgressReporter {
 public:
  ProgressReporter(std::string label, int total);
  // Marks one more item done; detail names it (e.g. the image).
  void Step(const std::string& detail);
  double ElapsedSeconds() const;

 private:
  std::string label_;
  int total_;
  int done_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mpmvs

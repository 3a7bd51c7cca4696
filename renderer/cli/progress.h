#pragma once
// Progress bar with ETA for pa-render (stderr; drawn only when enabled).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace pa::cli {

/// Formats seconds as "4.2s", "3m05s" or "1h02m".
std::string formatDuration(double seconds);

/// Redraws "[#####.....]  45%  9/20 frames  elapsed 3.1s  ETA 3.8s" on one line.
class ProgressBar {
 public:
  /// `enabled` false makes every call a no-op (non-TTY stderr without --progress).
  ProgressBar(uint32_t totalSteps, bool enabled, std::FILE* out = stderr);
  /// Reports that `done` of the total steps are finished.
  void update(uint32_t done);
  /// Ends the bar's line.
  void finish();
  /// Seconds since construction.
  double elapsedSeconds() const;

 private:
  uint32_t total_;
  bool enabled_;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace pa::cli

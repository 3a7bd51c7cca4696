// Text progress bar: one carriage-return-refreshed line with elapsed time and ETA.
#include "renderer/cli/progress.h"

#include <algorithm>
#include <cmath>

namespace pa::cli {

std::string formatDuration(double seconds) {
  char text[32];
  if (!std::isfinite(seconds) || seconds < 0.0) return "?";
  if (seconds < 60.0) {
    std::snprintf(text, sizeof text, "%.1fs", seconds);
  } else if (seconds < 3600.0) {
    const int whole = static_cast<int>(seconds);
    std::snprintf(text, sizeof text, "%dm%02ds", whole / 60, whole % 60);
  } else {
    const int minutes = static_cast<int>(seconds / 60.0);
    std::snprintf(text, sizeof text, "%dh%02dm", minutes / 60, minutes % 60);
  }
  return text;
}

ProgressBar::ProgressBar(uint32_t totalSteps, bool enabled, std::FILE* out)
    : total_(std::max(totalSteps, 1u)), enabled_(enabled), out_(out), start_(std::chrono::steady_clock::now()) {}

double ProgressBar::elapsedSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressBar::update(uint32_t done) {
  if (!enabled_) return;
  constexpr int kWidth = 30;
  done = std::min(done, total_);
  const double fraction = static_cast<double>(done) / total_;
  const int filled = static_cast<int>(fraction * kWidth);
  const double elapsed = elapsedSeconds();
  const std::string eta = done > 0 ? formatDuration(elapsed / done * (total_ - done)) : "?";
  std::fprintf(out_, "\r[%.*s%.*s] %3d%%  %u/%u frames  elapsed %s  ETA %s   ", filled,
               "##############################", kWidth - filled, "..............................",
               static_cast<int>(fraction * 100.0), done, total_, formatDuration(elapsed).c_str(), eta.c_str());
  std::fflush(out_);
}

void ProgressBar::finish() {
  if (!enabled_) return;
  std::fputc('\n', out_);
  std::fflush(out_);
}

}  // namespace pa::cli

// Image figures: display luma from the PNG, sky coverage from the EXR depth AOV.
#include "tests/all_maps_render/image_stats.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace pa::allmaps {
namespace {

std::string percent(double fraction) {
  char text[16];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
  return text;
}

std::string number(double value) {
  char text[16];
  std::snprintf(text, sizeof text, "%.3f", value);
  return text;
}

}  // namespace

ImageStats computeImageStats(std::span<const uint8_t> rgba8, std::span<const float> depth,
                             const PlausibilityThresholds& thresholds) {
  const size_t pixels = depth.size();
  if (pixels == 0 || rgba8.size() != pixels * 4)
    throw std::invalid_argument("image stats: " + std::to_string(rgba8.size()) + " RGBA bytes for " +
                                std::to_string(pixels) + " depth samples");
  double lumaSum = 0.0;
  size_t black = 0;
  size_t sky = 0;
  for (size_t i = 0; i < pixels; ++i) {
    const uint8_t* p = &rgba8[i * 4];
    const double luma = (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) / 255.0;
    if (!std::isfinite(depth[i])) {   // a night sky is no missing light: judge the world only
      ++sky;
      continue;
    }
    lumaSum += luma;
    if (luma < thresholds.blackLuma) ++black;
  }
  const double world = static_cast<double>(pixels - sky);
  if (world == 0.0) return {0.0, 0.0, 1.0};
  return {lumaSum / world, static_cast<double>(black) / world, static_cast<double>(sky) / static_cast<double>(pixels)};
}

std::vector<std::string> implausibilityReasons(const ImageStats& stats, const PlausibilityThresholds& thresholds,
                                               bool atMaxGain) {
  std::vector<std::string> reasons;
  const std::string clamped = atMaxGain ? " at the largest auto-exposure gain" : "";
  if (stats.meanLuma < thresholds.minMeanLuma)
    reasons.push_back("dark" + clamped + ": world mean luma " + number(stats.meanLuma) + " < " +
                      number(thresholds.minMeanLuma));
  if (stats.blackFraction > thresholds.maxBlackFraction)
    reasons.push_back("black" + clamped + ": " + percent(stats.blackFraction) + " of the world pixels black > " +
                      percent(thresholds.maxBlackFraction));
  if (stats.skyFraction > thresholds.maxSkyFraction)
    reasons.push_back("sky: " + percent(stats.skyFraction) + " sky/void pixels > " + percent(thresholds.maxSkyFraction));
  return reasons;
}

}  // namespace pa::allmaps

#pragma once
// Per-image figures of an offline map render and the "plausible picture" verdict built on them.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pa::allmaps {

/// Figures of one rendered image.
struct ImageStats {
  double meanLuma = 0.0;       ///< Mean display luma of the world pixels (not sky), 0..1 (Rec. 709 weights on sRGB values).
  double blackFraction = 0.0;  ///< Share of the world pixels (not sky) darker than PlausibilityThresholds::blackLuma.
  double skyFraction = 0.0;    ///< Pixels whose first hit is the sky or nothing (EXR depth not finite).
};

/// What "a plausible picture" means; the values are justified in README.md.
struct PlausibilityThresholds {
  double blackLuma = 10.0 / 255.0;   ///< A pixel darker than this counts as black.
  double minMeanLuma = 0.055;        ///< Not black: world mean display luma at least this...
  double maxBlackFraction = 0.7;     ///< ...and at most this share of black world pixels.
  double maxSkyFraction = 0.9;       ///< Not all sky: the world covers more than 10% of the image.
};

/// Computes the figures from the PNG's RGBA8 pixels and the EXR's depth plane (same size,
/// row-major). Luma figures are 0 when every pixel is sky. Throws std::invalid_argument when the sizes disagree or the image is empty.
ImageStats computeImageStats(std::span<const uint8_t> rgba8, std::span<const float> depth,
                             const PlausibilityThresholds& thresholds = {});

/// Why an image is not plausible: one short reason per failed check (empty = plausible).
/// `atMaxGain`: the picture was exposed automatically and the gain hit its upper clamp, so a
/// dark or black verdict means the render is dark beyond what exposure can show (said in the reason).
std::vector<std::string> implausibilityReasons(const ImageStats& stats, const PlausibilityThresholds& thresholds = {},
                                               bool atMaxGain = false);

}  // namespace pa::allmaps

// Noise-aware comparison of two Monte Carlo renders: a per-pixel two-sample Z-test (Welch) on the
// luminance of the means, using each render's variance of the mean, with a Sidak-corrected
// per-pixel significance level; the image passes when enough pixels pass (Mitsuba 3's criterion).
// The same test on sums over square tiles and over the whole image sees changes too small for
// any single pixel (a darker material, a slight bias) that cover many pixels.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace pa::regress {

/// A linear HDR render: mean radiance and the variance of each pixel's mean luminance.
struct HdrImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;        ///< width * height * 3 linear radiance means, rows top to bottom
  std::vector<float> varianceY;  ///< width * height variances of the mean's luminance
};

/// Reads R, G, B and variance.Y from a pa-render OpenEXR; throws std::runtime_error naming the file.
HdrImage loadExr(const std::string& path);

/// Rec. 709 luminance of pixel i.
float luminanceAt(const HdrImage& image, std::size_t i);

/// Settings of the test.
struct NoiseTestSettings {
  double alpha = 0.01;             ///< family-wise false-alarm level over all pixels of one image
  double minPassFraction = 0.9975; ///< the image passes when at least this share of pixels pass
  /// Tile sides of the aggregate scales (0 = the whole image); alpha is split evenly (Bonferroni)
  /// between the pixel scale and these, and every tile of an aggregate scale must pass.
  std::vector<int> tileSizes = {8, 0};
};

/// Outcome at one aggregate scale.
struct TileScaleResult {
  int tileSize = 0;                ///< side in pixels (0 = whole image)
  std::size_t tiles = 0;
  std::size_t failedTiles = 0;
  double zThreshold = 0;           ///< Sidak-corrected over the tiles of this scale
  double maxAbsZ = 0;              ///< largest tile |z|
};

/// Outcome of the test.
struct NoiseTestResult {
  std::size_t pixels = 0;
  std::size_t failedPixels = 0;
  double passFraction = 1.0;       ///< share of pixels whose |z| stays under the threshold
  double pixelAlpha = 0;           ///< Sidak: 1 - (1 - alpha / scales)^(1 / pixels)
  double zThreshold = 0;           ///< two-sided critical |z| for pixelAlpha
  double meanAbsZ = 0;             ///< mean |z| over all pixels (about 0.8 for pure noise)
  std::vector<TileScaleResult> scales;  ///< the aggregate scales, in settings order
  bool pass = true;
  std::vector<float> z;            ///< per-pixel |z| (infinity where means differ with zero variance)
};

/// Two-sided critical value: the z with P(|N(0,1)| > z) = p, for 0 < p < 1.
double twoSidedCriticalZ(double p);

/// Compares `test` against `reference` (same size, else std::invalid_argument).
NoiseTestResult noiseTest(const HdrImage& test, const HdrImage& reference, const NoiseTestSettings& settings);

}  // namespace pa::regress

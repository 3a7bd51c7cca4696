// LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild: "FLIP: A Difference
// Evaluator for Alternating Images", HPG 2020): a per-pixel perceptual error in [0, 1] between a
// reference and a test image as seen at a given number of pixels per degree of visual angle.
// Written from the paper; see tests/fidelity/README.md ("FLIP") for the pipeline and constants.
#pragma once

#include "tests/fidelity/image_metrics.h"

#include <vector>

namespace pa::fidelity {

/// Pixels per degree of visual angle at the screen's centre: a monitor `monitorWidthM` metres
/// wide showing `monitorWidthPx` pixels across, seen from `distanceM` metres (the paper's
/// formula d * (r / w) * pi / 180).
double pixelsPerDegree(double distanceM, double monitorWidthM, double monitorWidthPx);

/// The paper's default viewing conditions: 0.7 m from a 0.7 m wide 3840-pixel monitor (67.02 ppd).
double flipDefaultPixelsPerDegree();

/// A FLIP error map: one value in [0, 1] per pixel, rows top to bottom, and its mean.
struct FlipMap {
  int width = 0;
  int height = 0;
  std::vector<float> error;  ///< width * height values
  double mean = 0;           ///< mean of `error` (the figure one reports)
};

/// LDR-FLIP of `test` against `reference` (8-bit sRGB, same size) at `pixelsPerDegree`.
/// Symmetric in its two images. Image borders are extended by their edge pixels for the filters.
/// Throws std::invalid_argument when the sizes differ, an image is empty or ppd <= 0.
FlipMap flip(const RgbImage& reference, const RgbImage& test, double pixelsPerDegree);

/// The error map as an 8-bit grey image (error x 255, black = no difference).
RgbImage flipErrorImage(const FlipMap& map);

}  // namespace pa::fidelity

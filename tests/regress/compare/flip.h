// LDR-FLIP (Andersson, Nilsson, Akenine-Moller, Oskarsson, Astrom, Fairchild: "FLIP: A Difference
// Evaluator for Alternating Images", HPG 2020): a per-pixel perceptual error in [0, 1] between two
// sRGB images seen at a given number of pixels per degree of visual angle.
#pragma once

#include <cstdint>
#include <vector>

namespace pa::regress {

/// Pixels per degree of the paper's default observer: a 0.7 m wide 3840-pixel monitor seen from 0.7 m.
double defaultPixelsPerDegree();

/// Per-pixel LDR-FLIP error between `reference` and `test`, both width x height x 3 bytes of sRGB
/// (rows top to bottom). Borders replicate the edge pixels. Returns width * height values in [0, 1];
/// throws std::invalid_argument when the buffer sizes do not match width x height x 3.
std::vector<float> flipErrorMap(const std::vector<std::uint8_t>& reference, const std::vector<std::uint8_t>& test,
                                int width, int height, double pixelsPerDegree = defaultPixelsPerDegree());

}  // namespace pa::regress

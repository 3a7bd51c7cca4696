// Error heat maps for the pa-regress report.
#pragma once

#include <vector>

#include "tests/fidelity/image_metrics.h"

namespace pa::regress {

/// Colours each value v / fullScale (clamped to [0, 1]; NaN and infinity count as 1) from black
/// through purple and orange to pale yellow. Throws std::invalid_argument on a size mismatch.
fidelity::RgbImage heatMap(const std::vector<float>& values, int width, int height, float fullScale);

}  // namespace pa::regress

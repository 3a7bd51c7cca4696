#include "tests/regress/compare/heat_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace pa::regress {

fidelity::RgbImage heatMap(const std::vector<float>& values, int width, int height, float fullScale) {
  if (values.size() != static_cast<size_t>(width) * height || !(fullScale > 0))
    throw std::invalid_argument("heatMap: values must be width x height, scale positive");
  // Four stops, evenly spaced: black, purple, orange, pale yellow.
  constexpr std::array<std::array<float, 3>, 4> stops = {{{0, 0, 4}, {120, 28, 109}, {237, 105, 37}, {252, 255, 164}}};
  fidelity::RgbImage out{width, height, std::vector<std::uint8_t>(values.size() * 3)};
  for (size_t i = 0; i < values.size(); ++i) {
    float t = values[i] / fullScale;
    if (!std::isfinite(t)) t = 1.0f;
    t = std::clamp(t, 0.0f, 1.0f) * 3.0f;
    const int k = std::min(static_cast<int>(t), 2);
    const float f = t - static_cast<float>(k);
    for (int c = 0; c < 3; ++c)
      out.pixels[3 * i + c] = static_cast<std::uint8_t>(std::lround(stops[k][c] + f * (stops[k + 1][c] - stops[k][c])));
  }
  return out;
}

}  // namespace pa::regress

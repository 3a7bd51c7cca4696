// Light grid sampling.
#include "port/q3formats/bsp/light_grid.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace q3 {

glm::vec3 lightGridDirection(uint8_t longitude, uint8_t latitude) {
  constexpr float kStep = 2.0f * std::numbers::pi_v<float> / 256.0f;
  const float lat = static_cast<float>(latitude) * kStep;
  const float lng = static_cast<float>(longitude) * kStep;
  return {std::cos(lat) * std::sin(lng), std::sin(lat) * std::sin(lng), std::cos(lng)};
}

LightGridSample sampleLightGrid(const BspLightGrid& grid, const glm::vec3& point) {
  LightGridSample out;
  if (!grid.valid) return out;
  int base[3];
  float frac[3];
  for (int k = 0; k < 3; ++k) {
    const float v = (point[k] - grid.origin[k]) / grid.gridSize[k];
    const float maxIndex = static_cast<float>(grid.dims[k] - 1);
    const float clamped = std::isfinite(v) ? std::clamp(v, 0.0f, maxIndex) : 0.0f;
    base[k] = std::min(static_cast<int>(clamped), grid.dims[k] - 1);
    frac[k] = clamped - static_cast<float>(base[k]);
  }
  float totalWeight = 0;
  glm::vec3 direction(0);
  for (int corner = 0; corner < 8; ++corner) {
    float weight = 1;
    size_t index = 0;
    size_t stride = 1;
    for (int k = 0; k < 3; ++k) {
      const bool upper = (corner >> k) & 1;
      weight *= upper ? frac[k] : 1 - frac[k];
      const int c = std::min(base[k] + (upper ? 1 : 0), grid.dims[k] - 1);
      index += static_cast<size_t>(c) * stride;
      stride *= static_cast<size_t>(grid.dims[k]);
    }
    const uint8_t* p = grid.raw.data() + index * 8;
    if (p[0] + p[1] + p[2] + p[3] + p[4] + p[5] == 0) continue;  // point inside solid
    totalWeight += weight;
    out.ambient += weight * glm::vec3(p[0], p[1], p[2]);
    out.directed += weight * glm::vec3(p[3], p[4], p[5]);
    direction += weight * lightGridDirection(p[6], p[7]);
  }
  if (totalWeight <= 0) return out;
  out.ambient /= totalWeight;
  out.directed /= totalWeight;
  const float len = glm::length(direction);
  if (len > 1e-6f) out.direction = direction / len;
  out.valid = true;
  return out;
}

}  // namespace q3

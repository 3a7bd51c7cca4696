// Light grid sampling.
#include "port/q3formats/bsp/light_grid.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace q3 {
namespace {

constexpr size_t kPointBytes = 8;

/// rgb * 2^shift, scaled back as a whole when a channel overflows.
void shiftColor(uint8_t* rgb, int shift) {
  int r = rgb[0] << shift, g = rgb[1] << shift, b = rgb[2] << shift;
  const int peak = std::max({r, g, b});
  if (peak > 255) {
    r = r * 255 / peak;
    g = g * 255 / peak;
    b = b * 255 / peak;
  }
  rgb[0] = static_cast<uint8_t>(r);
  rgb[1] = static_cast<uint8_t>(g);
  rgb[2] = static_cast<uint8_t>(b);
}

}  // namespace

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
    // Non-finite or huge coordinates: the engine's float -> int is undefined there; use cell 0.
    const float cell = std::isfinite(v) && std::fabs(v) < 1e9f ? std::floor(v) : 0.0f;
    frac[k] = std::isfinite(v) && std::fabs(v) < 1e9f ? v - cell : 0.0f;
    base[k] = static_cast<int>(std::clamp(cell, 0.0f, static_cast<float>(grid.dims[k] - 1)));
  }
  float totalWeight = 0;
  glm::vec3 direction(0);
  for (int corner = 0; corner < 8; ++corner) {
    float weight = 1;
    size_t index = 0;
    size_t stride = 1;
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
      const bool upper = (corner >> k) & 1;
      if (upper && base[k] + 1 > grid.dims[k] - 1) {
        inside = false;  // past the last grid point: left out
        break;
      }
      weight *= upper ? frac[k] : 1 - frac[k];
      index += static_cast<size_t>(base[k] + (upper ? 1 : 0)) * stride;
      stride *= static_cast<size_t>(grid.dims[k]);
    }
    if (!inside) continue;
    const uint8_t* p = grid.raw.data() + index * kPointBytes;
    if (p[0] + p[1] + p[2] == 0) continue;  // black ambient: a point inside solid
    totalWeight += weight;
    out.ambient += weight * glm::vec3(p[0], p[1], p[2]);
    out.directed += weight * glm::vec3(p[3], p[4], p[5]);
    direction += weight * lightGridDirection(p[6], p[7]);
  }
  if (totalWeight > 0 && totalWeight < 0.99f) {
    out.ambient /= totalWeight;
    out.directed /= totalWeight;
  }
  const float len = glm::length(direction);
  if (len > 1e-6f) out.direction = direction / len;
  out.valid = totalWeight > 0;
  return out;
}

BspLightGrid shiftLightGridColors(const BspLightGrid& grid, int shift) {
  BspLightGrid out = grid;
  if (shift <= 0 || shift > 8) return out;
  for (size_t i = 0; i + kPointBytes <= out.raw.size(); i += kPointBytes) {
    shiftColor(&out.raw[i], shift);
    shiftColor(&out.raw[i + 3], shift);
  }
  return out;
}

}  // namespace q3

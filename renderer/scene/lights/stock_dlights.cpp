#include "renderer/scene/lights/stock_dlights.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace pa {

namespace {

constexpr int kBlobSize = 16;   // the stock DLIGHT_SIZE

/// The stock falloff image: 4000 / d^2 (d in texels from the centre), cut below 75, max 255.
constexpr std::array<float, kBlobSize * kBlobSize> makeBlob() {
  std::array<float, kBlobSize * kBlobSize> texels{};
  for (int y = 0; y < kBlobSize; ++y)
    for (int x = 0; x < kBlobSize; ++x) {
      const float dx = kBlobSize / 2 - 0.5f - x, dy = kBlobSize / 2 - 0.5f - y;
      const float b = 4000.0f / (dx * dx + dy * dy);
      // floor of a positive value below 2^23: its integer part
      texels[size_t(y) * kBlobSize + x] = (b > 255.0f ? 255.0f : (b < 75.0f ? 0.0f : float(int(b)))) / 255.0f;
    }
  return texels;
}

constexpr std::array<float, kBlobSize * kBlobSize> kBlob = makeBlob();

}  // namespace

float stockDlightBlob(glm::vec2 st) {
  float x = st.x * kBlobSize - 0.5f, y = st.y * kBlobSize - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) return 0.0f;
  x = std::clamp(x, 0.0f, float(kBlobSize - 1));
  y = std::clamp(y, 0.0f, float(kBlobSize - 1));
  const int x0 = int(x), y0 = int(y);
  const int x1 = std::min(x0 + 1, kBlobSize - 1), y1 = std::min(y0 + 1, kBlobSize - 1);
  const float ax = x - float(x0), ay = y - float(y0);
  const auto at = [](int px, int py) { return kBlob[size_t(py) * kBlobSize + size_t(px)]; };
  return (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) + (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
}

glm::vec3 stockDlightAt(const StockDynamicLight& light, const glm::vec3& position, const glm::vec3& normal) {
  if (!(light.radius > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 toLight = light.origin - position;
  if (glm::dot(toLight, normal) < 0.0f) return glm::vec3(0.0f);   // lights only the front
  const float height = std::fabs(toLight.z);
  if (!(height <= light.radius)) return glm::vec3(0.0f);
  const float modulate = height < light.radius * 0.5f ? 1.0f : 2.0f * (light.radius - height) / light.radius;
  const glm::vec2 st = glm::vec2(0.5f) + glm::vec2(toLight.x, toLight.y) / light.radius;
  // The pass's vertex colour: colour x modulation in 8-bit steps, as stock writes its bytes.
  const glm::vec3 color = glm::floor(glm::clamp(light.color, 0.0f, 1.0f) * 255.0f * modulate) / 255.0f;
  return color * stockDlightBlob(st);
}

glm::vec3 stockDlightsOver(std::span<const StockDynamicLight> lights, const glm::vec3& position,
                           const glm::vec3& normal, glm::vec3 display) {
  for (const StockDynamicLight& light : lights) {
    const glm::vec3 added = stockDlightAt(light, position, normal);
    if (added != glm::vec3(0.0f)) display = glm::clamp(display * (1.0f + added), 0.0f, 1.0f);
  }
  return display;
}

}  // namespace pa

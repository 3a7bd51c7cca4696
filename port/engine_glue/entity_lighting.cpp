#include "port/engine_glue/entity_lighting.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "port/engine_glue/scene.h"

namespace glue {
namespace {

constexpr float kTwoPi = 6.28318530717958f;
constexpr float kAmbientScale = 0.6f;     // r_ambientScale default
constexpr float kDirectedScale = 1.0f;    // r_directedScale default
constexpr float kMinimumAmbient = 32.0f;  // "give everything a minimum light add"
constexpr float kNoWorldLight = 150.0f;
constexpr float kDlightAtRadius = 16.0f;
constexpr float kDlightMinimumDistance = 16.0f;

}  // namespace

glm::vec3 colorShiftLight(const glm::vec3& bytes, int shift) {
  glm::vec3 shifted = glm::floor(glm::max(bytes, glm::vec3(0.0f))) * float(1 << std::clamp(shift, 0, 8));
  const float peak = std::max({shifted.r, shifted.g, shifted.b});
  if (peak > 255.0f) shifted = glm::floor(shifted * 255.0f / peak);
  return shifted;
}

bool lightGridAt(const q3::WorldLightGrid& grid, const glm::vec3& point, EntityLight& out, int shift) {
  const auto& counts = grid.counts;
  if (counts[0] <= 0 || counts[1] <= 0 || counts[2] <= 0) return false;
  const size_t total = size_t(counts[0]) * size_t(counts[1]) * size_t(counts[2]);
  if (grid.samples.size() < total) return false;

  int cell[3];
  float frac[3];
  for (int k = 0; k < 3; ++k) {
    const float size = grid.cellSize[k] > 0.0f ? grid.cellSize[k] : 1.0f;
    float v = (point[k] - grid.origin[k]) / size;
    if (!std::isfinite(v)) v = 0.0f;
    const float base = std::floor(v);
    frac[k] = v - base;
    cell[k] = static_cast<int>(std::clamp(base, 0.0f, float(counts[k] - 1)));
  }
  glm::vec3 ambient(0.0f), directed(0.0f), direction(0.0f);
  float totalFactor = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    float factor = 1.0f;
    size_t index = 0, stride = 1;
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
      int at = cell[k];
      if (corner & (1 << k)) {
        if (at + 1 > counts[k] - 1) { inside = false; break; }
        ++at;
        factor *= frac[k];
      } else {
        factor *= 1.0f - frac[k];
      }
      index += size_t(at) * stride;
      stride *= size_t(counts[k]);
    }
    if (!inside) continue;
    const auto& s = grid.samples[index];
    const glm::vec3 sampleAmbient = colorShiftLight(glm::vec3(s[0], s[1], s[2]), shift);
    if (sampleAmbient.r + sampleAmbient.g + sampleAmbient.b <= 0.0f) continue;   // inside a wall
    const glm::vec3 sampleDirected = colorShiftLight(glm::vec3(s[3], s[4], s[5]), shift);
    totalFactor += factor;
    ambient += factor * sampleAmbient;
    directed += factor * sampleDirected;
    const float longitude = s[6] * (kTwoPi / 256.0f), latitude = s[7] * (kTwoPi / 256.0f);
    direction += factor * glm::vec3(std::cos(latitude) * std::sin(longitude),
                                    std::sin(latitude) * std::sin(longitude), std::cos(longitude));
  }
  if (totalFactor > 0.0f && totalFactor < 0.99f) {
    ambient /= totalFactor;
    directed /= totalFactor;
  }
  out.ambient = ambient * kAmbientScale;
  out.directed = directed * kDirectedScale;
  const float length = glm::length(direction);
  out.direction = length > 1e-6f ? direction / length : glm::vec3(0.0f, 0.0f, 1.0f);
  return true;
}

EntityLight noWorldLight() {
  EntityLight light;
  light.ambient = light.directed = glm::vec3(kNoWorldLight);
  light.direction = glm::normalize(glm::vec3(0.45f, 0.3f, 0.9f));
  return light;
}

EntityLight finishEntityLight(EntityLight light, const glm::vec3& lightOrigin,
                              std::span<const DynamicLight> dynamicLights) {
  light.ambient += glm::vec3(kMinimumAmbient);
  // The directed light becomes a vector so that dynamic lights can turn it.
  glm::vec3 towardLights = light.direction * glm::length(light.directed);
  for (const DynamicLight& dl : dynamicLights) {
    glm::vec3 toLight = dl.origin - lightOrigin;
    float distance = glm::length(toLight);
    toLight = distance > 0.0f ? toLight / distance : glm::vec3(0.0f);
    distance = std::max(distance, kDlightMinimumDistance);
    const float power = kDlightAtRadius * dl.radius * dl.radius / (distance * distance);
    if (!std::isfinite(power)) continue;
    light.directed += power * dl.color;
    towardLights += power * toLight;
  }
  light.ambient = glm::min(light.ambient, glm::vec3(255.0f));
  const float length = glm::length(towardLights);
  if (length > 1e-6f) light.direction = towardLights / length;
  return light;
}

glm::vec3 diffuseVertexLight(const EntityLight& light, const glm::vec3& normal) {
  const float incoming = glm::dot(normal, light.direction);
  if (!(incoming > 0.0f)) return glm::floor(light.ambient);
  return glm::min(glm::floor(light.ambient + incoming * light.directed), glm::vec3(255.0f));
}

}  // namespace glue

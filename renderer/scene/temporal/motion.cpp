#include "renderer/scene/temporal/motion.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

namespace pa::temporal {

void InstanceMotion::record(std::span<const RenderInstance> instances) {
  for (const RenderInstance& instance : instances) {
    // Hidden instances (reused slots showing nothing) are not recorded: an instance shown again
    // has no previous transform and its pixels count as disoccluded.
    if (instance.id == kNoId || (instance.mask & kMaskCamera) == 0) continue;
    if (instance.id >= current_.size()) {
      current_.resize(instance.id + 1, glm::mat4x3(1.0f));
      currentKnown_.resize(instance.id + 1, 0);
    }
    current_[instance.id] = instance.objectToWorld;
    currentKnown_[instance.id] = 1;
  }
}

void InstanceMotion::beginFrame(std::span<const RenderInstance> world, std::span<const RenderInstance> overlay) {
  std::swap(current_, previous_);
  std::swap(currentKnown_, previousKnown_);
  std::fill(currentKnown_.begin(), currentKnown_.end(), uint8_t{0});
  record(world);
  record(overlay);
  const size_t n = current_.size();
  pointToPrevious_.assign(n, glm::mat4x3(1.0f));
  normalToPrevious_.assign(n, glm::mat3(1.0f));
  valid_.assign(n, 0);
  for (size_t id = 0; id < n; ++id) {
    if (currentKnown_[id] == 0 || id >= previousKnown_.size() || previousKnown_[id] == 0) continue;
    const glm::mat4x3& now = current_[id];
    const glm::mat4x3& then = previous_[id];
    if (now == then) {   // the common case (the world): identity, exactly
      valid_[id] = 1;
      continue;
    }
    const glm::mat3 linearNow(now);
    const float det = glm::determinant(linearNow);
    if (!std::isfinite(det) || std::abs(det) < 1e-12f) continue;
    const glm::mat3 inverseNow = glm::inverse(linearNow);
    const glm::mat3 linear = glm::mat3(then) * inverseNow;   // world now -> object -> world then
    glm::mat4x3 m(linear);
    m[3] = then[3] - linear * now[3];
    pointToPrevious_[id] = m;
    normalToPrevious_[id] = glm::transpose(glm::inverse(linear));
    valid_[id] = 1;
  }
}

void InstanceMotion::reset() {
  std::fill(currentKnown_.begin(), currentKnown_.end(), uint8_t{0});
  std::fill(previousKnown_.begin(), previousKnown_.end(), uint8_t{0});
  std::fill(valid_.begin(), valid_.end(), uint8_t{0});
}

void GBuffer::resize(uint32_t w, uint32_t h) {
  width = w;
  height = h;
  const size_t n = size_t{w} * h;
  instance.resize(n);
  material.resize(n);
  motion.resize(n);
  previousDepth.resize(n);
  previousNormal.resize(n);
}

void GBuffer::write(size_t i, const PixelSample& sample, float px, float py, const InstanceMotion& motions,
                    const CameraRays* previousCamera) {
  instance[i] = sample.instance;
  material[i] = sample.material;
  motion[i] = glm::vec2(kNoMotion);
  previousDepth[i] = std::numeric_limits<float>::infinity();
  previousNormal[i] = glm::vec3(0.0f);
  if (sample.instance == kNoId || previousCamera == nullptr) return;
  glm::vec3 point = sample.position;
  glm::vec3 normal = sample.normal;
  if (!motions.toPrevious(sample.instance, point, normal)) return;
  float previousX = 0.0f, previousY = 0.0f;
  if (!previousCamera->project(point, previousX, previousY)) return;
  motion[i] = glm::vec2(previousX - px, previousY - py);
  previousDepth[i] = glm::length(point - previousCamera->origin());
  const float length = glm::length(normal);
  previousNormal[i] = length > 0.0f ? normal / length : glm::vec3(0.0f);
}

}  // namespace pa::temporal

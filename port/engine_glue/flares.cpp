#include "port/engine_glue/flares.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace glue {
namespace {

constexpr float kNearPlane = 4.0f;           // stock r_znear: nearer points are clipped
constexpr float kOccluderTolerance = 24.0f;  // a surface this close in front still shows the flare
constexpr int kFreshFadeOffsetMs = 2000;     // a flare new in view starts two seconds faded out
constexpr float kDegreesToRadians = 3.14159265358979f / 180.0f;

}  // namespace

float flareHalfSize(float viewWidth, float eyeDistance, float flareSize) {
  const float distance = std::max(eyeDistance, 1.0f);
  return viewWidth * (flareSize / 640.0f + 8.0f / distance);
}

float flareIntensity(float halfSize, float eyeDistance, float coeff) {
  const float distance = std::max(eyeDistance, 1.0f);
  const float c = std::max(coeff, 0.0f);
  const float factor = distance + halfSize * std::sqrt(c);
  return factor > 0.0f ? c * halfSize * halfSize / (factor * factor) : 0.0f;
}

void FlareTracker::reset(size_t count) {
  states_.assign(count, State{});
  viewCount_ = 0;
}

void FlareTracker::update(const FlareView& view, std::span<const Flare> flares, const FlareParams& params,
                          const FlareDepthQuery& depthAt, std::vector<FlareQuad>& out) {
  out.clear();
  if (states_.size() != flares.size()) reset(flares.size());
  ++viewCount_;
  if (view.width <= 0 || view.height <= 0) return;
  const float tanX = std::tan(std::clamp(view.fovX, 1.0f, 179.0f) * 0.5f * kDegreesToRadians);
  const float tanY = std::tan(std::clamp(view.fovY, 1.0f, 179.0f) * 0.5f * kDegreesToRadians);
  for (size_t i = 0; i < flares.size(); ++i) {
    const Flare& flare = flares[i];
    State& state = states_[i];
    const glm::vec3 toFlare = flare.origin - view.origin;
    const float distance = glm::length(toFlare);
    // Facing: a flare with a normal is seen from its front only, dimmed by the cosine.
    float facing = 1.0f;
    if (flare.normal != glm::vec3(0.0f)) {
      if (distance <= 0.0f) continue;
      facing = glm::dot(-toFlare / distance, flare.normal);
      if (facing < 0.0f) continue;
    }
    const float eyeZ = glm::dot(toFlare, view.forward);
    if (!(eyeZ > kNearPlane)) continue;
    const float ndcX = -glm::dot(toFlare, view.left) / (eyeZ * tanX);
    const float ndcY = glm::dot(toFlare, view.up) / (eyeZ * tanY);
    if (!(std::abs(ndcX) < 1.0f && std::abs(ndcY) < 1.0f)) continue;
    // The stock window position: whole pixels from the view's bottom-left corner.
    const float windowX = std::floor(0.5f * (1.0f + ndcX) * view.width + 0.5f);
    const float windowY = std::floor(0.5f * (1.0f + ndcY) * view.height + 0.5f);
    if (windowX < 0 || windowX >= view.width || windowY < 0 || windowY >= view.height) continue;
    const float centerX = static_cast<float>(view.x) + windowX;
    const float centerY = static_cast<float>(view.y + view.height) - windowY;
    if (state.addedView != viewCount_ - 1) {   // not in the previous view: starts hidden
      state.visible = false;
      state.fadeTimeMs = view.timeMs - kFreshFadeOffsetMs;
    }
    state.addedView = viewCount_;
    // Occlusion: the surface seen at the flare's pixel, as a depth along the view axis.
    const float depth = depthAt(centerX + 0.5f, centerY - 0.5f);
    const float surfaceEyeZ = std::isfinite(depth) && distance > 0.0f ? depth * eyeZ / distance : INFINITY;
    const bool visible = eyeZ - surfaceEyeZ < kOccluderTolerance;
    if (visible != state.visible) {
      state.visible = visible;
      state.fadeTimeMs = view.timeMs - 1;
    }
    const float elapsed = static_cast<float>(view.timeMs - state.fadeTimeMs) / 1000.0f * params.fade;
    const float fade = std::clamp(visible ? elapsed : 1.0f - elapsed, 0.0f, 1.0f);
    if (fade <= 0.0f) {
      state.addedView = -2;   // faded out: forgotten, as stock drops it from its chain
      continue;
    }
    const float halfSize = flareHalfSize(static_cast<float>(view.width), eyeZ, params.size);
    const float intensity = flareIntensity(halfSize, eyeZ, params.coeff);
    FlareQuad quad;
    quad.centerX = centerX;
    quad.centerY = centerY;
    quad.halfSize = halfSize;
    quad.color = glm::clamp(flare.color * (facing * fade * intensity), 0.0f, 1.0f);
    out.push_back(quad);
  }
}

}  // namespace glue

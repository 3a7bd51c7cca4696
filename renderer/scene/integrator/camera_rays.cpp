#include "renderer/scene/integrator/camera_rays.h"

#include <algorithm>
#include <numbers>
#include <string>

namespace pa {

namespace {

glm::vec3 unitAxis(const glm::vec3& v, const char* name) {
  const float len = glm::length(v);
  if (!std::isfinite(len) || !(len > 0.0f)) {
    throw SceneError(std::string("render: camera.") + name + " must be finite and non-zero");
  }
  return v / len;
}

}  // namespace

CameraRays::CameraRays(const Camera& camera, uint32_t width, uint32_t height) {
  if (!std::isfinite(camera.origin.x) || !std::isfinite(camera.origin.y) || !std::isfinite(camera.origin.z)) {
    throw SceneError("render: camera.origin is not finite");
  }
  if (!(camera.fovX > 0.0f && camera.fovX < 180.0f) || !(camera.fovY > 0.0f && camera.fovY < 180.0f)) {
    throw SceneError("render: camera.fovX and fovY must be in (0, 180) degrees");
  }
  origin_ = camera.origin;
  forward_ = unitAxis(camera.forward, "forward");
  right_ = -unitAxis(camera.left, "left");
  up_ = unitAxis(camera.up, "up");
  constexpr float kDegrees = std::numbers::pi_v<float> / 180.0f;
  tanHalfX_ = std::tan(0.5f * camera.fovX * kDegrees);
  tanHalfY_ = std::tan(0.5f * camera.fovY * kDegrees);
  width_ = static_cast<float>(width);
  height_ = static_cast<float>(height);
  spread_ = std::atan(2.0f * tanHalfY_ / std::max(1.0f, height_));
}

void CameraRays::setFootprintHeight(uint32_t height) {
  spread_ = std::atan(2.0f * tanHalfY_ / std::max(1.0f, static_cast<float>(height)));
}

}  // namespace pa

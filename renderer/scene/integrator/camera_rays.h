#pragma once
// Primary rays of the game-style camera: pixel (0, 0) is the top-left corner, +x goes right
// (= -left), +y goes down (= -up); fovX/fovY are full angles in degrees.
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/geometric.hpp>

#include "renderer/core/ray.h"
#include "renderer/scene/scene_types.h"

namespace pa {

/// Generates camera rays for one image size.
class CameraRays {
 public:
  /// Validates the camera (finite, non-degenerate axes, 0 < fov < 180) or throws SceneError.
  CameraRays(const Camera& camera, uint32_t width, uint32_t height);

  /// Ray through film position (px, py) in pixels (continuous, (0,0) = top-left corner).
  Ray generate(float px, float py) const {
    Ray r;
    generate(px, py, r);
    return r;
  }
  /// generate() written into `out` in place (a copy of a Ray just built on the stack reads its
  /// fields back wider than they were written, and stalls).
  void generate(float px, float py, Ray& out) const {
    const float sx = (2.0f * px / width_ - 1.0f) * tanHalfX_;
    const float sy = (1.0f - 2.0f * py / height_) * tanHalfY_;
    out.origin = origin_;
    out.tmin = 0.0f;
    out.dir = glm::normalize(forward_ + sx * right_ + sy * up_);
    out.tmax = std::numeric_limits<float>::infinity();
  }
  /// Film position (pixels, continuous) whose ray passes through world point p: the inverse of
  /// generate() for orthonormal camera axes. False when p is not in front of the camera.
  bool project(const glm::vec3& p, float& px, float& py) const {
    const glm::vec3 d = p - origin_;
    const float z = glm::dot(d, forward_);
    if (!(z > 1e-6f)) return false;
    px = (glm::dot(d, right_) / (z * tanHalfX_) + 1.0f) * 0.5f * width_;
    py = (1.0f - glm::dot(d, up_) / (z * tanHalfY_)) * 0.5f * height_;
    return std::isfinite(px) && std::isfinite(py);
  }
  /// What generate() and project() compute with (for code that runs them on many pixels at once).
  struct Basis {
    glm::vec3 origin, forward, right, up;
    float tanHalfX, tanHalfY, width, height;
  };
  /// This camera's basis.
  Basis basis() const { return {origin_, forward_, right_, up_, tanHalfX_, tanHalfY_, width_, height_}; }
  /// Eye position.
  const glm::vec3& origin() const { return origin_; }
  /// Unit forward axis (eye-space depth = distance along it).
  const glm::vec3& forward() const { return forward_; }
  /// Angle subtended by one pixel (ray-cone spread for texture filtering).
  float pixelSpreadAngle() const { return spread_; }
  /// Texture footprints of an image `height` pixels tall (TAAU shows more pixels than it traces:
  /// textures are filtered for the picture shown).
  void setFootprintHeight(uint32_t height);

 private:
  glm::vec3 origin_, forward_, right_, up_;
  float tanHalfX_, tanHalfY_;
  float width_, height_;
  float spread_;
};

}  // namespace pa

#pragma once
// The environment: a constant radiance, a cube map (six textures) or a per-direction picture
// (SkyPicture) times colour * intensity,
// and the scene's unshadowed ambient terms (lights/ambient.h).
#include <array>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/scene/lights/ambient.h"
#include "renderer/scene/sampling/alias_table.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/textures/texture.h"

namespace pa {

/// Cube-map face lookup: which face a direction hits and where, (u, v) from the top-left.
/// Face f looks along its axis (+X, -X, +Y, -Y, +Z, -Z); its image top points to +Z
/// (+X for the two Z faces) and its image right is axis x top.
struct CubeLookup {
  uint32_t face = 0;
  float u = 0.0f;
  float v = 0.0f;
};

/// Face and coordinates for a non-zero direction.
CubeLookup cubeLookup(const glm::vec3& dir);

/// Axis, image-top and image-right vectors of a cube face (right = axis x top).
struct CubeFaceBasis {
  glm::vec3 axis, top, right;
};
/// The layout of SkyDesc::faces: face 0..5 = +X, -X, +Y, -Y, +Z, -Z (Z up); face is clamped.
const CubeFaceBasis& cubeFaceBasis(uint32_t face);

/// Immutable sky used while rendering. Cube-map skies are importance sampled: a
/// kImportanceGrid^2 grid per face, cells weighted by luminance x solid angle.
class Sky {
 public:
  /// Sampling grid cells per face side.
  static constexpr uint32_t kImportanceGrid = 32;

  Sky() = default;
  /// Resolves texture ids (validated by the caller).
  Sky(const SkyDesc& desc, const std::vector<std::shared_ptr<const Texture>>& textures);

  /// Radiance seen along dir (pointing away from the scene) by the camera and mirrors.
  glm::vec3 radiance(const glm::vec3& dir) const;
  /// Radiance along dir where the sky lights a surface (radiance x SkyDesc::lightingScale).
  glm::vec3 lightingRadiance(const glm::vec3& dir) const { return lightingScale_ * radiance(dir); }
  /// Mean lighting radiance over all directions (light selection).
  glm::vec3 average() const { return average_; }
  /// True when directions are drawn from the cube-map distribution (else: cosine lobes).
  bool importanceSampled() const { return !table_.empty(); }
  /// Draws a direction from the cube-map distribution; pdf in solid angle.
  bool sample(const glm::vec3& u, glm::vec3& dir, float& pdf) const;
  /// Solid-angle pdf of sample() producing dir.
  float pdf(const glm::vec3& dir) const;
  /// True when the sky lights nothing.
  bool black() const { return average_.x <= 0.0f && average_.y <= 0.0f && average_.z <= 0.0f; }
  /// The scene-wide ambient terms (SkyDesc::ambientRadiance, SkyDesc::minimumRadiance).
  const AmbientLight& ambient() const { return ambient_; }
  /// True when Sky(desc, textures) would differ from this sky at most in its picture
  /// (SkyDesc::picture): the same terms and the same face textures. False for a default Sky.
  bool sameButPicture(const SkyDesc& desc, const std::vector<std::shared_ptr<const Texture>>& textures) const;
  /// Shows `picture` instead of the faces (SkyDesc::picture), keeping the rest: what a moving
  /// sky changes per frame, without building the sampling distribution again.
  void setPicture(std::shared_ptr<const SkyPicture> picture) { picture_ = std::move(picture); }

 private:
  glm::vec3 scale_{0.0f};
  float lightingScale_ = 1.0f;
  std::array<std::shared_ptr<const Texture>, 6> faces_{};
  std::shared_ptr<const SkyPicture> picture_;
  bool hasFaces_ = false;
  glm::vec3 average_{0.0f};
  sampling::AliasTable table_;
  AmbientLight ambient_;
  SkyDesc source_;        ///< The desc it was made from, without its picture (sameButPicture).
  bool made_ = false;     ///< Made from a desc (not default-constructed).

  void buildImportance();
};

}  // namespace pa

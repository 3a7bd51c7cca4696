#pragma once
// Quake III -> glTF 2.0 coordinates. Quake: right-handed, Z up, X forward, 1 unit ~ 1 inch.
// glTF: right-handed, Y up, metres. (x, y, z)_q3 -> (x, z, -y)_gltf is a proper rotation
// (determinant +1) so triangle winding and handedness are preserved; lengths scale by
// metresPerUnit (see README "Units and axes").
#include <glm/vec3.hpp>

namespace pa::converter {

/// Default scale: 1 Quake unit = 1/32 m (the 56-unit player box is 1.75 m tall).
inline constexpr float kDefaultMetresPerUnit = 1.0f / 32.0f;

/// A direction (or normal) from Quake axes to glTF axes, no scaling.
inline glm::vec3 toGltfDirection(const glm::vec3& q3) { return {q3.x, q3.z, -q3.y}; }

/// A position from Quake units/axes to glTF metres/axes.
inline glm::vec3 toGltfPosition(const glm::vec3& q3, float metresPerUnit) {
  return toGltfDirection(q3) * metresPerUnit;
}

}  // namespace pa::converter

#pragma once
// Scenes for the bench: a glTF/glb file (all instances flattened to world-space triangles,
// through pa_gltf_io) or a synthetic scene "soup:N", "sphere:N", "thin:N".
#include <optional>
#include <string>

#include <glm/vec3.hpp>

#include "renderer/bvh/testing/scene_generators.h"

namespace pa::bench {

/// A pinhole camera for the primary rays.
struct BenchCamera {
  glm::vec3 origin{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float yfov = 0.9f;   ///< Vertical field of view, radians.
};

/// Triangles plus where to look from.
struct BenchScene {
  std::string name;
  testing::TestMesh mesh;
  BenchCamera camera;
  bool cameraFromFile = false;
  std::string gltfPath;   ///< Source file; empty for synthetic scenes.
};

/// Loads a glTF/glb file; throws std::runtime_error with the reason.
BenchScene loadGltfScene(const std::string& path);

/// Parses "soup:N" / "sphere:N" / "thin:N"; throws std::invalid_argument on anything else.
BenchScene makeSyntheticScene(const std::string& spec);

/// A camera outside the bounds looking at their centre (used when the file has none).
BenchCamera cameraFromBounds(const Bounds& bounds);

}  // namespace pa::bench

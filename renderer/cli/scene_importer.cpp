// The importer registry (by extension) and camera helpers shared by all formats.
#include "renderer/cli/scene_importer.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "renderer/cli/gltf_importer.h"

namespace pa::cli {

namespace {
std::vector<std::unique_ptr<SceneImporter>>& importerRegistry() {
  // Built-in formats first; registerSceneImporter() appends (before rendering starts).
  static std::vector<std::unique_ptr<SceneImporter>> importers = [] {
    std::vector<std::unique_ptr<SceneImporter>> builtIn;
    builtIn.push_back(std::make_unique<GltfImporter>());
    return builtIn;
  }();
  return importers;
}
}  // namespace

std::span<const std::unique_ptr<SceneImporter>> sceneImporters() { return importerRegistry(); }

void registerSceneImporter(std::unique_ptr<SceneImporter> importer) {
  if (importer) importerRegistry().push_back(std::move(importer));
}

const SceneImporter* findImporter(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const auto& importer : sceneImporters()) {
    const auto handled = importer->extensions();
    if (std::find(handled.begin(), handled.end(), extension) != handled.end()) return importer.get();
  }
  return nullptr;
}

ImportedCamera framingCamera(const ImportedScene& scene) {
  const glm::vec3 center = 0.5f * (scene.boundsMin + scene.boundsMax);
  const float radius = std::max(0.5f * glm::length(scene.boundsMax - scene.boundsMin), 1e-3f);
  const glm::vec3 up = glm::normalize(scene.worldUp);
  // A horizontal axis perpendicular to up, then look from a raised diagonal.
  const glm::vec3 side = std::abs(up.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::vec3 horizontal = glm::normalize(side - up * glm::dot(side, up));
  const glm::vec3 other = glm::cross(up, horizontal);
  const glm::vec3 viewDirection = glm::normalize(-(horizontal + other) + -0.6f * up);
  ImportedCamera camera;
  camera.name = "framing";
  camera.yfovRadians = glm::radians(50.0f);
  camera.origin = center - viewDirection * (radius / std::sin(0.5f * camera.yfovRadians));
  camera.forward = viewDirection;
  camera.left = glm::normalize(glm::cross(up, camera.forward));
  camera.up = glm::cross(camera.forward, camera.left);
  return camera;
}

Camera toRendererCamera(const ImportedCamera& camera, float aspect) {
  Camera out;
  out.origin = camera.origin;
  out.forward = camera.forward;
  out.left = camera.left;
  out.up = camera.up;
  out.fovY = glm::degrees(camera.yfovRadians);
  out.fovX = glm::degrees(fovAcross(camera.yfovRadians, aspect));
  return out;
}

}  // namespace pa::cli

#pragma once
// Scene importers of pa-render: each one reads a file format and fills a pa::Renderer.
// The importer is chosen by file extension; to add a format (e.g. Quake .bsp), implement
// SceneImporter and list it in sceneImporters() (scene_importer.cpp).
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/scene/renderer.h"

namespace pa::cli {

/// A camera offered by the scene file (axes orthonormal, world space).
struct ImportedCamera {
  std::string name;
  glm::vec3 origin{0.0f};
  glm::vec3 forward{1.0f, 0.0f, 0.0f};
  glm::vec3 left{0.0f, 1.0f, 0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};
  float yfovRadians = 1.0f;
  float aspectRatio = 0.0f;   ///< width / height preferred by the file; 0 = none.
};

/// What an importer reports after filling the renderer.
struct ImportedScene {
  std::vector<ImportedCamera> cameras;
  glm::vec3 boundsMin{0.0f};       ///< World bounds of all instanced geometry.
  glm::vec3 boundsMax{0.0f};
  glm::vec3 worldUp{0.0f, 1.0f, 0.0f};  ///< The format's up axis (glTF +Y, Quake +Z).
  size_t triangles = 0;            ///< Instanced triangles.
  size_t lights = 0;
  std::vector<std::string> warnings;
};

/// Settings shared by all importers.
struct ImportOptions {
  float lightScale = 1.0f;   ///< Photometric -> renderer units (see pa-render --help).
};

/// One input format.
class SceneImporter {
 public:
  virtual ~SceneImporter() = default;
  /// Human-readable format name ("glTF 2.0").
  virtual std::string_view formatName() const = 0;
  /// Lower-case extensions handled, with the dot (".gltf").
  virtual std::span<const std::string_view> extensions() const = 0;
  /// Loads `path` into `renderer` (no commit). Throws std::runtime_error on failure.
  virtual ImportedScene load(const std::filesystem::path& path, Renderer& renderer,
                             const ImportOptions& options) const = 0;
};

/// Every importer pa-render knows.
std::span<const std::unique_ptr<SceneImporter>> sceneImporters();

/// The importer for `path` by (case-insensitive) extension, or nullptr.
const SceneImporter* findImporter(const std::filesystem::path& path);

/// A camera that frames the scene bounds, looking at the centre from a raised diagonal.
ImportedCamera framingCamera(const ImportedScene& scene);

/// The renderer camera for an image of `aspect` (width / height); vertical fov kept.
Camera toRendererCamera(const ImportedCamera& camera, float aspect);

}  // namespace pa::cli

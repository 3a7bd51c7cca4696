#pragma once
// pa-render's glTF 2.0 importer (.gltf, .glb), on top of pa_gltf_io.
#include "renderer/cli/scene_importer.h"

namespace pa::cli {

/// Loads .gltf / .glb through pa::gltf::loadScene + uploadToRenderer.
class GltfImporter final : public SceneImporter {
 public:
  std::string_view formatName() const override { return "glTF 2.0"; }
  std::span<const std::string_view> extensions() const override;
  ImportedScene load(const std::filesystem::path& path, Renderer& renderer,
                     const ImportOptions& options) const override;
};

}  // namespace pa::cli

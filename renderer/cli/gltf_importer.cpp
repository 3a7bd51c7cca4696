// glTF importer: loadScene -> uploadToRenderer, plus cameras and bounds for pa-render.
#include "renderer/cli/gltf_importer.h"

#include <array>
#include <limits>

#include <glm/common.hpp>

#include "renderer/gltf_io/gltf_loader.h"
#include "renderer/gltf_io/gltf_upload.h"

namespace pa::cli {

std::span<const std::string_view> GltfImporter::extensions() const {
  static constexpr std::array<std::string_view, 2> kExtensions = {".gltf", ".glb"};
  return kExtensions;
}

ImportedScene GltfImporter::load(const std::filesystem::path& path, Renderer& renderer,
                                 const ImportOptions& options) const {
  gltf::LoadOptions loadOptions;
  loadOptions.lightUnitScale = options.lightScale;
  const gltf::GltfScene scene = gltf::loadScene(path, loadOptions);
  try {
    gltf::uploadToRenderer(scene, renderer);
  } catch (const std::exception& e) {
    throw std::runtime_error(path.string() + ": renderer rejected the scene: " + e.what());
  }

  ImportedScene imported;
  imported.worldUp = glm::vec3(0.0f, 1.0f, 0.0f);
  imported.lights = scene.lights.size();
  imported.warnings = scene.warnings;
  for (const gltf::GltfCamera& camera : scene.cameras) {
    ImportedCamera out;
    out.name = camera.name;
    out.origin = camera.origin;
    out.forward = camera.forward;
    out.left = camera.left;
    out.up = camera.up;
    out.yfovRadians = camera.yfov;
    out.aspectRatio = camera.aspectRatio;
    imported.cameras.push_back(out);
  }
  glm::vec3 lo(std::numeric_limits<float>::max());
  glm::vec3 hi(-std::numeric_limits<float>::max());
  for (const gltf::GltfInstance& instance : scene.instances) {
    const gltf::GltfMesh& mesh = scene.meshes[instance.mesh];
    const glm::mat4x3& m = instance.objectToWorld;
    for (const glm::vec3& p : mesh.positions) {
      const glm::vec3 world = m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3];
      lo = glm::min(lo, world);
      hi = glm::max(hi, world);
    }
    imported.triangles += mesh.indices.size() / 3;
  }
  if (lo.x <= hi.x) {
    imported.boundsMin = lo;
    imported.boundsMax = hi;
  }
  return imported;
}

}  // namespace pa::cli

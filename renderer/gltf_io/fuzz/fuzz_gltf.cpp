// libFuzzer: .gltf / .glb bytes -> loadSceneFromMemory (tinygltf, GLB checks, accessors,
// materials, images, node traversal) -> flattenTriangles. The only acceptable failure is
// std::runtime_error; every index in the result must be in range.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <stdexcept>

#include "renderer/gltf_io/gltf_loader.h"

namespace {

/// Aborts (a libFuzzer crash) when an invariant of the imported scene does not hold.
void require(bool condition) {
  if (!condition) std::abort();
}

bool validIndex(uint32_t index, size_t size) { return index == pa::gltf::kNone || index < size; }

void checkScene(const pa::gltf::GltfScene& scene) {
  for (const pa::gltf::GltfMesh& mesh : scene.meshes) {
    const size_t n = mesh.positions.size();
    require(mesh.indices.size() % 3 == 0 && mesh.triangleMaterials.size() == mesh.indices.size() / 3);
    for (size_t attribute : {mesh.normals.size(), mesh.uvs.size(), mesh.colors.size(), mesh.lightmapUvs.size()})
      require(attribute == 0 || attribute == n);  // absent from every primitive, or one per vertex
    require(mesh.triangleLightmaps.empty() || mesh.triangleLightmaps.size() == mesh.indices.size() / 3);
    for (uint32_t i : mesh.indices) require(i < n);
    for (uint32_t m : mesh.triangleMaterials) require(validIndex(m, scene.materials.size()));
    for (uint32_t t : mesh.triangleLightmaps) require(validIndex(t, scene.textures.size()));
  }
  for (const pa::gltf::GltfInstance& instance : scene.instances) require(instance.mesh < scene.meshes.size());
  for (const pa::gltf::GltfMaterial& material : scene.materials)
    require(validIndex(material.baseColorTexture, scene.textures.size()) &&
            validIndex(material.emissiveTexture, scene.textures.size()));
  for (const pa::gltf::GltfTexture& texture : scene.textures) require(validIndex(texture.image, scene.images.size()));
  for (const pa::gltf::GltfImage& image : scene.images)
    require(image.rgba8.empty() || image.rgba8.size() == size_t{image.width} * image.height * 4);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pa::gltf::LoadOptions options;
  options.decodeImages = size % 2 == 0;  // both paths, chosen by the input itself
  options.scene = size % 3 == 0 ? 1 : -1;
  try {
    const pa::gltf::GltfScene scene = pa::gltf::loadSceneFromMemory(
        std::span(reinterpret_cast<const std::byte*>(data), size), "fuzz.gltf", {}, options);
    checkScene(scene);
    const pa::gltf::TriangleSoup soup = pa::gltf::flattenTriangles(scene);
    require(soup.indices.size() % 3 == 0);
    for (uint32_t i : soup.indices) require(i < soup.positions.size());
  } catch (const std::runtime_error&) {
    // Malformed input: refused with a message.
  }
  return 0;
}

#pragma once
// Hands a loaded glTF scene to pa::Renderer through its flat scene API
// (mapping of materials, lights, sky and cameras: see gltf_mapping.h).
#include <vector>

#include "renderer/gltf_io/gltf_mapping.h"
#include "renderer/gltf_io/gltf_scene.h"
#include "renderer/scene/renderer.h"

namespace pa::gltf {

/// Renderer ids of everything uploaded, indexed like the GltfScene arrays.
struct UploadedScene {
  std::vector<MeshId> meshes;
  std::vector<InstanceId> instances;
  std::vector<MaterialId> materials;
  std::vector<TextureId> textures;   ///< kNoId where the glTF texture had no usable image.
  std::vector<LightId> lights;
};

/// Adds textures, materials, meshes, instances and lights, and sets the sky. Does not commit().
/// Throws pa::SceneError (from the renderer) if the renderer rejects something.
UploadedScene uploadToRenderer(const GltfScene& scene, Renderer& renderer);

}  // namespace pa::gltf

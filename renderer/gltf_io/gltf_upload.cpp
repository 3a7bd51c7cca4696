// GltfScene -> pa::Renderer: textures, materials, meshes, instances, lights, sky.
#include "renderer/gltf_io/gltf_upload.h"

namespace pa::gltf {

UploadedScene uploadToRenderer(const GltfScene& scene, Renderer& renderer) {
  UploadedScene uploaded;
  for (const GltfTexture& texture : scene.textures) {
    if (texture.image >= scene.images.size() || scene.images[texture.image].rgba8.empty()) {
      uploaded.textures.push_back(kNoId);
      continue;
    }
    const GltfImage& image = scene.images[texture.image];
    TextureDesc desc;
    desc.width = image.width;
    desc.height = image.height;
    desc.rgba8 = image.rgba8;
    desc.srgb = true;
    desc.wrap = texture.wrap == Wrap::Clamp ? TextureWrap::Clamp : TextureWrap::Repeat;
    uploaded.textures.push_back(renderer.addTexture(desc));
  }
  for (const GltfMaterial& material : scene.materials)
    uploaded.materials.push_back(renderer.addMaterial(toMaterialDesc(material, uploaded.textures)));

  std::vector<MaterialId> triangleMaterials;
  for (const GltfMesh& mesh : scene.meshes) {
    triangleMaterials.resize(mesh.triangleMaterials.size());
    for (size_t t = 0; t < mesh.triangleMaterials.size(); ++t) {
      const uint32_t m = mesh.triangleMaterials[t];
      triangleMaterials[t] = m < uploaded.materials.size() ? uploaded.materials[m] : kNoId;
    }
    MeshDesc desc;
    desc.positions = mesh.positions;
    desc.indices = mesh.indices;
    desc.normals = mesh.normals;
    desc.uvs = mesh.uvs;
    desc.colors = mesh.colors;
    desc.materials = triangleMaterials;
    uploaded.meshes.push_back(mesh.indices.empty() ? kNoId : renderer.addMesh(desc));
  }
  for (const GltfInstance& instance : scene.instances) {
    if (instance.mesh >= uploaded.meshes.size() || uploaded.meshes[instance.mesh] == kNoId) {
      uploaded.instances.push_back(kNoId);
      continue;
    }
    InstanceDesc desc;
    desc.mesh = uploaded.meshes[instance.mesh];
    desc.objectToWorld = instance.objectToWorld;
    uploaded.instances.push_back(renderer.addInstance(desc));
  }
  for (const GltfLight& light : scene.lights) uploaded.lights.push_back(renderer.addLight(toLightDesc(light)));
  renderer.setSky(toSkyDesc(scene.sceneExtras));
  return uploaded;
}

}  // namespace pa::gltf

// GltfScene -> pa::Renderer: textures, materials, meshes, instances, lights, sky.
#include "renderer/gltf_io/gltf_upload.h"

#include <map>
#include <utility>

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

  // Lightmaps: textures brightened once each, and one material variant per (material, lightmap).
  const float lightmapScale = lightmapBrightness(scene.sceneExtras);
  std::map<uint32_t, TextureId> lightmapTextures;
  std::map<std::pair<uint32_t, uint32_t>, MaterialId> lightmappedMaterials;
  auto lightmapTexture = [&](uint32_t gltfTexture) {
    if (const auto it = lightmapTextures.find(gltfTexture); it != lightmapTextures.end()) return it->second;
    TextureId id = kNoId;
    const uint32_t imageIndex = gltfTexture < scene.textures.size() ? scene.textures[gltfTexture].image : kNone;
    if (imageIndex < scene.images.size() && !scene.images[imageIndex].rgba8.empty()) {
      const GltfImage& image = scene.images[imageIndex];
      const std::vector<uint8_t> pixels = brightenLightmap(image.rgba8, lightmapScale);
      TextureDesc desc;
      desc.width = image.width;
      desc.height = image.height;
      desc.rgba8 = pixels;
      desc.srgb = true;
      desc.wrap = TextureWrap::Clamp;
      id = renderer.addTexture(desc);
    }
    lightmapTextures.emplace(gltfTexture, id);
    return id;
  };
  auto materialFor = [&](uint32_t material, uint32_t lightmap) -> MaterialId {
    if (material >= scene.materials.size()) return kNoId;
    if (lightmap == kNone) return uploaded.materials[material];
    const auto key = std::make_pair(material, lightmap);
    if (const auto it = lightmappedMaterials.find(key); it != lightmappedMaterials.end()) return it->second;
    MaterialDesc desc = toMaterialDesc(scene.materials[material], uploaded.textures);
    desc.stock.lightmapTexture = lightmapTexture(lightmap);
    desc.stock.lightmapStageScale = lightmapStageScale(scene.materials[material]);   // as the .bsp bridge sets it
    desc.stock.bakedLightScale *= desc.stock.lightmapStageScale;
    const MaterialId id = desc.stock.lightmapTexture == kNoId ? uploaded.materials[material] : renderer.addMaterial(desc);
    lightmappedMaterials.emplace(key, id);
    return id;
  };

  std::vector<MaterialId> triangleMaterials;
  for (const GltfMesh& mesh : scene.meshes) {
    triangleMaterials.resize(mesh.triangleMaterials.size());
    const bool lightmapped = mesh.triangleLightmaps.size() == mesh.triangleMaterials.size();
    for (size_t t = 0; t < mesh.triangleMaterials.size(); ++t)
      triangleMaterials[t] = materialFor(mesh.triangleMaterials[t], lightmapped ? mesh.triangleLightmaps[t] : kNone);
    uploaded.meshes.push_back(mesh.indices.empty() ? kNoId : renderer.addMesh(meshDescOf(mesh, triangleMaterials)));
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

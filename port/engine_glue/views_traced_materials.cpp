// ViewRenderer::Impl: entity textures and materials, dynamic mesh slots, brush model instances
// and the dynamic light pool.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "port/engine_glue/stock_look.h"
#include "port/engine_glue/views_traced_impl.h"
#include "port/q3formats/shader/shader_time.h"

namespace glue {

/// The renderer texture of an image, repeating or clamped to its edges (clampMap), shrunk by
/// r_picmip unless `noPicmip`, its colours scaled by r_intensity (as stock treats mipmapped images).
pa::TextureId ViewRenderer::Impl::texture(const std::shared_ptr<const Image>& image, bool clamp, bool noPicmip) {
  if (!image) return pa::kNoId;
  const auto key = std::make_tuple(image.get(), clamp, !noPicmip);
  if (const auto found = map.textures.find(key); found != map.textures.end()) return found->second.second;
  int width = image->width, height = image->height;
  std::vector<uint8_t> pixels = picmipImage(image->rgba, width, height, noPicmip ? 0 : pictureSettings.picmip);
  applyIntensity(pixels, pictureSettings.intensity);
  pa::TextureDesc desc;
  desc.width = static_cast<uint32_t>(width);
  desc.height = static_cast<uint32_t>(height);
  desc.rgba8 = pixels;
  desc.wrap = clamp ? pa::TextureWrap::Clamp : pa::TextureWrap::Repeat;
  const pa::TextureId id = renderer->addTexture(desc);
  map.textures.emplace(key, std::make_pair(image, id));
  return id;
}

/// `layer` 0 is the shader's first stage, k > 0 its look.layers[k - 1]; animMap stages show the
/// frame of that time, tcMods and waves move with it (entityTranslate by `scroll`).
pa::MaterialId ViewRenderer::Impl::material(ShaderRegistry& shaders, q3abi::qhandle_t handle, MaterialUse use,
                                            uint32_t layer, double seconds, std::array<float, 2> scroll) {
  const ShaderEntry& entry = shaders.resolve(handle);
  if (layer > entry.look.layers.size() || layer > entry.layerFrames.size()) layer = 0;
  const ShaderLook& look = layer == 0 ? entry.look : entry.look.layers[layer - 1];
  const auto& frames = layer == 0 ? entry.frames : entry.layerFrames[layer - 1];
  uint32_t frameIndex = 0;
  if (frames.size() > 1 && look.animFrequency > 0.0f && std::isfinite(seconds))
    frameIndex = static_cast<uint32_t>(q3::animMapFrame(frames.size(), look.animFrequency, seconds));
  const std::shared_ptr<const Image> image = frames.empty() ? nullptr : frames[frameIndex];
  const MaterialKeyView key{entry.name, use, layer, frameIndex};
  if (const auto found = map.materials.find(key); found != map.materials.end()) return found->second;
  auto found = map.moving.find(key);
  if (found == map.moving.end()) {   // first use: still or moving
    StageMotion motion = motionOf(look);
    if (!motion.timeDependent()) {
      const pa::MaterialId id = renderer->addMaterial(materialAt(motion, 0.0, describe(entry, look, image, use, layer)));
      map.materials.emplace(MaterialKey(entry.name, use, layer, frameIndex), id);
      return id;
    }
    found = map.moving.emplace(MaterialKey(entry.name, use, layer, frameIndex),
                               MovingMaterial{describe(entry, look, image, use, layer), {}, std::move(motion)}).first;
  }
  MovingMaterial& m = found->second;
  return m.pool.get(m.motion, m.still, seconds, scroll, viewCount, *renderer, animationUpdates);
}

void ViewRenderer::Impl::prepareMaterials(ShaderRegistry& shaders, bool lightmapLook, bool pictures) {
  const int look = lightmapLook ? 1 : 0;
  if (map.preparedLook != look) {
    map.preparedLook = look;
    map.preparedShaders = 1;   // handle 0 is the default shader
  }
  const int count = shaders.count();
  if (map.preparedShaders >= count) return;
  const auto start = std::chrono::steady_clock::now();
  const size_t materialsBefore = map.materials.size() + map.moving.size(), texturesBefore = map.textures.size();
  const MaterialUse uses[2] = {lightmapLook ? MaterialUse::StockModel : MaterialUse::Model,
                               lightmapLook ? MaterialUse::StockEffect : MaterialUse::Effect};
  for (int handle = map.preparedShaders; handle < count; ++handle) {
    const ShaderEntry* entry = &shaders.resolve(handle);   // as material() sees it (remapped)
    if (entry->isDefault || (entry->clampToEdge && !pictures)) continue;
    map.modelDeforms.find(entry->name);   // its deforms looked up once, too
    for (uint32_t layer = 0; layer <= entry->look.layers.size() && layer <= entry->layerFrames.size(); ++layer) {
      const ShaderLook& stage = layer == 0 ? entry->look : entry->look.layers[layer - 1];
      const size_t frames = layer == 0 ? entry->frames.size() : entry->layerFrames[layer - 1].size();
      const bool animated = frames > 1 && stage.animFrequency > 0.0f;
      for (size_t frame = 0; frame < (animated ? frames : 1); ++frame) {
        // The middle of animMap frame `frame` (q3::animMapFrame).
        const double seconds = animated ? (static_cast<double>(frame) + 0.5) / stage.animFrequency : 0.0;
        for (const MaterialUse use : uses) material(shaders, handle, use, layer, seconds);
      }
    }
  }
  engine.print(q3abi::PRINT_DEVELOPER, "pathtracer: prepared shaders %d-%d: %zu materials, %zu textures, %.1f ms\n",
               map.preparedShaders, count - 1, map.materials.size() + map.moving.size() - materialsBefore,
               map.textures.size() - texturesBefore,
               std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  map.preparedShaders = count;
}

/// The still look of a stage (entity_materials.h), its images made textures of this renderer.
pa::MaterialDesc ViewRenderer::Impl::describe(const ShaderEntry& entry, const ShaderLook& look,
                                              const std::shared_ptr<const Image>& image, MaterialUse use,
                                              uint32_t layer) {
  const ImageTextures textures = [this](const std::shared_ptr<const Image>& i, bool clamp, bool noPicmip) {
    return texture(i, clamp, noPicmip);
  };
  pa::MaterialDesc desc = describeStage(entry, look, image, use, layer, textures);
  // Models lit by the light grid: the display's overbright doubles texture x light (settings.h).
  if (desc.stock.useVertexLight) desc.stock.bakedLightScale = pictureSettings.bakedLightScale();
  return desc;
}

const q3::Md3Model* ViewRenderer::Impl::md3(const ModelEntry& entry) {
  return entry.lods.empty() ? nullptr : entry.lods[0].get();
}

/// Shader time `seconds` less each triangle's batch.triangleShaderTimes; entityTranslate scrolls by `scroll`.
void ViewRenderer::Impl::fillSlot(const EntityKey& key, const glm::vec3& origin, ShaderRegistry& shaders,
                                  MaterialUse use, const glm::mat4x3& transform, uint32_t mask, bool onTop,
                                  double seconds, std::array<float, 2> scroll, const glm::vec3* specularViewer) {
  GeometryBatch& batch = scratch.batch;
  addShaderLayers(shaders, batch);
  const size_t triangles = batch.triangles();
  const size_t index = map.entitySlots.claim(key, origin, triangles);
  if (map.slots.size() <= index) map.slots.resize(index + 1);
  DynamicSlot& slot = map.slots[index];
  const bool newSlot = slot.mesh == pa::kNoId;
  if (specularViewer != nullptr) {
    const auto specular = [&shaders](q3abi::qhandle_t handle, uint32_t layer) {
      const ShaderLook& look = shaders.resolve(handle).look;
      const ShaderLook& stage = layer == 0 || layer > look.layers.size() ? look : look.layers[layer - 1];
      return stage.alphaGen == q3::AlphaGen::LightingSpecular;
    };
    specularAlphaLikeStock(specular, *specularViewer, batch);
  }
  scratch.triangleMaterials.resize(batch.triangles());
  // (shader, layer, shader time behind) -> material: a batch has few, mostly in runs.
  auto& slotMaterials = scratch.slotMaterials;
  slotMaterials.clear();
  for (size_t t = 0; t < batch.triangleShaders.size(); ++t) {
    const float behind = t < batch.triangleShaderTimes.size() ? batch.triangleShaderTimes[t] : 0.0f;
    const ViewScratch::SlotMaterialKey key{batch.triangleShaders[t],
                                           t < batch.triangleLayers.size() ? batch.triangleLayers[t] : 0u, behind};
    auto found = std::find_if(slotMaterials.rbegin(), slotMaterials.rend(),
                              [&](const auto& entry) { return entry.first == key; });
    if (found == slotMaterials.rend()) {
      slotMaterials.emplace_back(key, material(shaders, std::get<0>(key), use, std::get<1>(key), seconds - behind, scroll));
      found = slotMaterials.rbegin();
    }
    scratch.triangleMaterials[t] = found->second;
  }
  pa::InstanceDesc instance;
  instance.objectToWorld = transform;
  instance.mask = mask;
  instance.drawOnTop = onTop;
  showInSlot(slot, batch, scratch.triangleMaterials, instance);
  // The effects batch keeps its own slot and sizes only that one: model slots follow the largest model.
  if (key.kind == kEffectsBatchKind) return;
  if (triangles > map.largestSlotTriangles) {
    map.largestSlotTriangles = triangles;
    map.largestSlot = index;
    map.largestSlotGrew = true;   // its BVH is built at this view's commit
  } else if (newSlot && map.largestSlot != index && map.largestSlot < map.slots.size() && !map.largestSlotGrew) {
    renderer->reserveMeshLike(slot.mesh, map.slots[map.largestSlot].mesh);
  }
}

void ViewRenderer::Impl::reserveSlotMemory() {
  if (!map.largestSlotGrew || map.largestSlot >= map.slots.size()) return;
  map.largestSlotGrew = false;
  const pa::MeshId largest = map.slots[map.largestSlot].mesh;
  for (const DynamicSlot& slot : map.slots)
    if (slot.mesh != pa::kNoId && slot.mesh != largest) renderer->reserveMeshLike(slot.mesh, largest);
}

void ViewRenderer::Impl::hideUnclaimedSlots() {
  for (size_t i = 0; i < map.slots.size(); ++i)
    if (!map.entitySlots.claimed(i)) hideSlot(map.slots[i]);
}

/// Its own mesh keeps the last triangles until the slot is shown again.
void ViewRenderer::Impl::hideSlot(DynamicSlot& slot) {
  if (!slot.visible || slot.instance == pa::kNoId) return;
  pa::InstanceDesc hidden;
  hidden.mesh = map.emptyMesh;
  hidden.mask = 0;
  renderer->setInstance(slot.instance, hidden);
  slot.visible = false;
}

void ViewRenderer::Impl::setBrushInstance(size_t model, const pa::InstanceDesc& desc) {
  if (model >= map.world.modelInstances.size() || map.world.modelInstances[model] == pa::kNoId) return;
  if (map.brushInstances[model] == desc) return;
  renderer->setInstance(map.world.modelInstances[model], desc);
  map.brushInstances[model] = desc;
}

void ViewRenderer::Impl::setLight(size_t index, const pa::LightDesc& desc, bool on) {
  if (index >= map.lights.size()) {
    map.lights.push_back(renderer->addLight(desc));
    map.lightOn.push_back(on);
    return;
  }
  if (!on && !map.lightOn[index]) return;
  renderer->setLight(map.lights[index], desc);
  map.lightOn[index] = on;
}

}  // namespace glue

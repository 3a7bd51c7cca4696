// ViewRenderer over pa::Renderer. The map is read once per LoadWorld (glue::World's q3::BspFile,
// tessellation and shader library -> q3::WorldScene -> pa_scene_bridge, whose sky and fog it
// shows; portal surfaces -> PortalViews, portals.h); per view,
// brush sub-models get their entity transforms, every MD3 entity becomes a dynamic mesh
// instance, effects and polygons one world-space dynamic mesh, dynamic lights reuse a pool of
// renderer lights, portals follow the frame's RT_PORTALSURFACE entities, and the frame is traced
// at r_pt_scale resolution.
// The lightmap preset adds the stock opengl1 look (README "The lightmap preset's stock look"):
// the stock sky (sky_cube.h), dynamic-light overlay, world autosprites, stock model colours
// (stock_look.h).
#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <tbb/task_arena.h>

#include "port/engine_glue/dlight_overlay.h"
#include "port/engine_glue/engine.h"
#include "port/engine_glue/entity_geometry.h"
#include "port/engine_glue/entity_materials.h"
#include "port/engine_glue/entity_lighting.h"
#include "port/engine_glue/entity_slots.h"
#include "port/engine_glue/models.h"
#include "port/engine_glue/portals.h"
#include "port/engine_glue/scene.h"
#include "port/engine_glue/shader_animation.h"
#include "port/engine_glue/shaders.h"
#include "port/engine_glue/sky_cube.h"
#include "port/engine_glue/reflection_look.h"
#include "port/engine_glue/stock_look.h"
#include "port/engine_glue/views.h"
#include "port/engine_glue/world_sprites.h"
#include "port/engine_glue/world_deforms.h"
#include "port/engine_glue/fog_volumes.h"
#include "port/engine_glue/world.h"
#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/common/format_error.h"
#include "port/q3formats/model/md3.h"
#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/shader/shader_time.h"
#include "port/q3formats/world/world_scene.h"
#include "port/scene_bridge/scene_bridge.h"
#include "renderer/scene/renderer.h"

namespace glue {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kStockSkyFaceSize = 256;   // texels a side of the baked stock sky

/// A reusable dynamic mesh + instance.
struct DynamicSlot {
  pa::MeshId mesh = pa::kNoId;
  pa::InstanceId instance = pa::kNoId;
  bool visible = false;
};


glm::mat4x3 entityTransform(const q3abi::refEntity_t& e) {
  glm::mat4x3 m(1.0f);
  for (int a = 0; a < 3; ++a) m[a] = glm::vec3(e.axis[a][0], e.axis[a][1], e.axis[a][2]);
  m[3] = glm::vec3(e.origin[0], e.origin[1], e.origin[2]);
  return m;
}

pa::Integrator integratorFor(Preset preset) {
  switch (preset) {
    case Preset::Lightmap: return pa::Integrator::Lightmap;
    case Preset::Direct: return pa::Integrator::Direct;
    default: return pa::Integrator::Path;
  }
}

/// False for entities whose axes are degenerate (the game hides some that way).
bool placeable(const glm::mat4x3& m) {
  const float det = glm::determinant(glm::mat3(m));
  return std::isfinite(det) && std::fabs(det) > 1e-9f;
}

bool sameInstance(const pa::InstanceDesc& a, const pa::InstanceDesc& b) {
  return a.mesh == b.mesh && a.mask == b.mask && a.drawOnTop == b.drawOnTop &&
         a.materialOverride == b.materialOverride && a.objectToWorld == b.objectToWorld &&
         a.tint == b.tint;
}

/// The engine dlclose()s the module on vid_restart and at exit. The tracer's thread pool (oneTBB)
/// keeps worker threads alive for the whole process; if libtbb were unloaded with the module,
/// those threads would run unmapped code. Mark the already loaded libtbb "never unload".
void pinThreadPoolLibrary(const Engine& engine) {
#ifdef PATHARENA_TBB_SONAME
  if (dlopen(PATHARENA_TBB_SONAME, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE) == nullptr)
    engine.warn(std::string("could not pin ") + PATHARENA_TBB_SONAME + ": " + dlerror());
#else
  (void)engine;
#endif
}

}  // namespace

struct ViewRenderer::Impl {
  const Engine& engine;
  int threads = 0;
  std::unique_ptr<pa::Renderer> renderer;
  std::optional<q3::WorldScene> worldScene;
  pa::bridge::WorldHandles world;
  std::vector<pa::InstanceDesc> brushInstances;       ///< Current description per world model.
  /// (shader name, use, layer, animation frame) -> renderer material.
  using MaterialKey = std::tuple<std::string, MaterialUse, uint32_t, uint32_t>;
  /// A MaterialKey to look up with (transparent comparison: no string is made per lookup).
  using MaterialKeyView = std::tuple<std::string_view, MaterialUse, uint32_t, uint32_t>;
  std::map<MaterialKey, pa::MaterialId, std::less<>> materials;
  /// Animated shaders (shader_animation.h): their still look and their materials per shader time.
  struct MovingMaterial {
    pa::MaterialDesc still;
    MovingMaterialPool pool;
    StageMotion motion;
  };
  std::map<MaterialKey, MovingMaterial, std::less<>> moving;
  uint64_t viewCount = 0;
  size_t animationUpdates = 0;     ///< Entity materials replaced for animation in this view.
  WorldAnimation worldAnimation;   ///< World and brush-model materials at refdef time.
  /// (image, clamp, picmip applies) -> renderer texture.
  std::map<std::tuple<const Image*, bool, bool>, std::pair<std::shared_ptr<const Image>, pa::TextureId>> textures;
  PictureSettings pictureSettings;   ///< r_picmip, r_intensity, r_mapOverBrightBits for what is loaded.
  std::vector<DynamicSlot> slots;
  EntitySlots entitySlots;   ///< Which slot each model entity (and the effects batch) takes.
  std::vector<pa::LightId> lights;
  std::vector<bool> lightOn;
  pa::LightId headlight = pa::kNoId;
  pa::MaterialId defaultMaterial = pa::kNoId;
  /// A mesh without triangles: hidden dynamic slots show it, so that the renderer leaves their
  /// instances out of the scene (no stale boxes in the instance hierarchy, no lights from them).
  pa::MeshId emptyMesh = pa::kNoId;
  GeometryBatch batch;
  std::vector<pa::MaterialId> triangleMaterials;
  using SlotMaterialKey = std::tuple<q3abi::qhandle_t, uint32_t, float>;
  std::vector<std::pair<SlotMaterialKey, pa::MaterialId>> slotMaterials;   ///< fillSlot's working list.
  std::vector<q3abi::qhandle_t> surfaceShaders;   ///< An MD3 entity's shader per surface (working memory).
  std::vector<bool> surfaceAutosprite;            ///< ... and whether it is an autosprite.
  std::vector<bool> brushPlaced;                  ///< Per brush model: placed by an entity this view.
  std::vector<uint8_t> picture;
  uint32_t frameCounter = 0;
  PortalViews portals;   ///< Mirrors and portal cameras (portals.h).
  pa::SkyDesc bridgeSky;               ///< The world's sky as the bridge makes it (how it lights).
  pa::SkyDesc stockSky;                ///< The stock look (far box + clouds) for the lightmap preset.
  pa::SkyDesc tracedSky;               ///< The traced presets': the stock look lighting as bridgeSky.
  bool skyHidden = false;              ///< A view without the world set a black sky.
  bool stockSkyReady = false;
  bool stockSkyShown = false;
  bool stockEmissionShown = false;     ///< World surface lights drawn the stock way.
  std::unordered_map<uint32_t, glm::vec3> glowColors;   ///< World material -> glow stage colour (linear).
  WorldSprites worldSprites;                        ///< deformVertexes autosprite world surfaces.
  std::vector<uint32_t> spriteMaterials;            ///< Their world materials (static copy hidden).
  std::unordered_map<std::string, q3abi::qhandle_t> spriteHandles;
  const ShaderScripts* scripts = nullptr;           ///< The module's, while a world is loaded.
  ImageCache* images = nullptr;
  /// The stock sky: its cube faces are baked once per map (the sky's mean and sampling); camera
  /// rays see stockSkyPictureAt(skyBaker, shader time), so moving clouds cost no bake per frame.
  std::shared_ptr<const SkyBaker> skyBaker;
  /// The threads the sky bake may use: as many as the renderer's (r_pt_threads, 0 = all cores).
  tbb::task_arena bakeArena{threads > 0 ? threads : int(tbb::task_arena::automatic)};
  double stockSkySeconds = -1.0;   ///< Shader time of stockSky.picture.
  DlightOverlayBuilder dlightBuilder;  ///< The world's triangles for the stock dynamic-light pass.
  DlightOverlay dlightOverlay;
  DynamicSlot dlightSlot;
  std::unordered_map<uint32_t, pa::MaterialId> dlightMaterials;   ///< Per world material.
  std::vector<pa::MaterialId> dlightTriangleMaterials;
  WorldDeforms worldDeforms;    ///< deformVertexes wave/normal/bulge/move world surfaces (dynamic meshes).
  ShaderDeforms modelDeforms;   ///< The same deforms on MD3 surfaces, by shader name.
  ViewFog fog;                  ///< The map's fog volumes.

  void resetRenderer() {
    renderer = std::make_unique<pa::Renderer>(pa::RendererConfig{static_cast<uint32_t>(threads)});
    worldScene.reset();
    world = {};
    brushInstances.clear();
    materials.clear();
    moving.clear();
    worldAnimation.clear();
    textures.clear();
    slots.clear();
    entitySlots = EntitySlots{};
    lights.clear();
    lightOn.clear();
    headlight = pa::kNoId;
    portals.clear();
    defaultMaterial = renderer->addMaterial(pa::MaterialDesc{});
    emptyMesh = renderer->addMesh(pa::MeshDesc{});
    bridgeSky = stockSky = tracedSky = pa::SkyDesc{};
    skyBaker.reset();
    stockSkySeconds = -1.0;
    dlightBuilder = DlightOverlayBuilder{};
    dlightSlot = DynamicSlot{};
    dlightMaterials.clear();
    glowColors.clear();
    worldSprites = WorldSprites{};
    spriteMaterials.clear();
    spriteHandles.clear();
    worldDeforms = WorldDeforms{};
    modelDeforms.reset(nullptr);
    fog = ViewFog{};
    stockSkyReady = stockSkyShown = stockEmissionShown = skyHidden = false;
  }

  /// Hides the static copies of the autosprite world surfaces (drawn per view instead).
  void prepareWorldSprites(const q3::ShaderLibrary& library) {
    spriteMaterials = worldSprites.prepare(*worldScene, library);
    for (const auto& [key, id] : world.materials) {
      if (std::find(spriteMaterials.begin(), spriteMaterials.end(), key.first) == spriteMaterials.end()) continue;
      pa::MaterialDesc desc = pa::bridge::materialDesc(*worldScene, world, key.first, key.second);
      desc.visible = false;
      desc.castsShadows = false;
      worldAnimation.setMaterial(id, desc, *renderer);
    }
  }

  /// The shader handle of an autosprite world shader (registered on first use; 0 if it fails).
  q3abi::qhandle_t spriteHandle(ShaderRegistry& shaders, const std::string& name) {
    if (const auto found = spriteHandles.find(name); found != spriteHandles.end()) return found->second;
    q3abi::qhandle_t handle = shaders.find(name);
    if (handle == 0 && scripts != nullptr && images != nullptr)
      handle = shaders.registerShader(engine, *scripts, *images, name, true);
    spriteHandles.emplace(name, handle);
    return handle;
  }

  /// The layer twin of a world material that carries the stock dynamic-light pass: dst * (1 + vertex colour).
  pa::MaterialId dlightMaterial(uint32_t worldMaterial) {
    if (const auto found = dlightMaterials.find(worldMaterial); found != dlightMaterials.end()) return found->second;
    pa::MaterialDesc desc = pa::bridge::materialDesc(*worldScene, world, worldMaterial, -1);
    desc.alphaMode = pa::AlphaMode::Additive;
    desc.stock.layerBlend = pa::LayerBlend::MultiplyAdd;
    desc.baseTexture = pa::kNoId;  // the vertex colour alone is the light the pass multiplies in
    desc.baseColor = glm::vec4(1.0f);
    desc.stock.useVertexLight = false;
    desc.stock.lightmapTexture = pa::kNoId;
    desc.emissiveTexture = pa::kNoId;
    desc.emission = glm::vec3(0.0f);
    desc.mirror = false;
    desc.specular = 0.0f;
    desc.castsShadows = false;
    desc.twoSided = true;
    desc.visible = true;
    const pa::MaterialId id = renderer->addMaterial(desc);
    dlightMaterials.emplace(worldMaterial, id);
    return id;
  }

  /// Lightmap preset: the world brightened by dynamic lights the stock way (dlight_overlay.h),
  /// seen by camera rays only. Hidden in the traced presets, which light with real lights.
  void drawStockDlights(std::span<const DynamicLight> lights, bool show) {
    dlightOverlay.clear();
    if (show && worldScene) dlightBuilder.build(lights, dlightOverlay);
    if (dlightOverlay.indices.empty()) {
      hideSlot(dlightSlot);
      return;
    }
    dlightTriangleMaterials.resize(dlightOverlay.triangleMaterials.size());
    for (size_t t = 0; t < dlightOverlay.triangleMaterials.size(); ++t)
      dlightTriangleMaterials[t] = dlightMaterial(dlightOverlay.triangleMaterials[t]);
    pa::InstanceDesc instance;
    instance.mask = pa::kMaskCamera;
    showInSlot(dlightSlot, dlightOverlay, dlightTriangleMaterials, instance);
  }

  /// Uploads dynamic triangles (positions, indices, normals, uvs, colours) with one material
  /// per triangle into `slot` and shows its instance (mesh filled in here).
  template <typename Geometry>
  void showInSlot(DynamicSlot& slot, const Geometry& geometry, const std::vector<pa::MaterialId>& materials,
                  pa::InstanceDesc instance) {
    const pa::MeshDesc mesh = pa::meshDescOf(geometry, materials, true);
    if (slot.mesh == pa::kNoId) slot.mesh = renderer->addMesh(mesh);
    else renderer->updateMesh(slot.mesh, mesh);
    instance.mesh = slot.mesh;
    if (slot.instance == pa::kNoId) slot.instance = renderer->addInstance(instance);
    else renderer->setInstance(slot.instance, instance);
    slot.visible = true;
  }

  /// The stock renderer shows a q3map_surfacelight surface through its stages only (its light
  /// is baked in the lightmaps): in the lightmap preset such surfaces glow only through their
  /// additive glow stage, at the texture's own brightness. The traced presets keep the
  /// bridge's emitters.
  void selectWorldEmission(bool stockLook) {
    if (stockLook == stockEmissionShown || !worldScene) return;
    for (const auto& [key, id] : world.materials) {
      const q3::WorldMaterial& m = worldScene->materials.at(key.first);
      if (!(m.surfaceLight > 0.0f) || m.alphaMode == q3::WorldAlphaMode::Additive) continue;
      if (std::find(spriteMaterials.begin(), spriteMaterials.end(), key.first) != spriteMaterials.end()) continue;
      pa::MaterialDesc desc = pa::bridge::materialDesc(*worldScene, world, key.first, key.second);
      if (stockLook) {
        const bool glows = m.emissiveTexture >= 0 && size_t(m.emissiveTexture) < world.textures.size();
        desc.emissiveTexture = glows ? world.textures[size_t(m.emissiveTexture)] : pa::kNoId;
        const auto colour = glowColors.find(key.first);
        desc.emission = glows ? (colour != glowColors.end() ? colour->second : glm::vec3(1.0f)) : glm::vec3(0.0f);
      }
      worldAnimation.setMaterial(id, desc, *renderer);
    }
    stockEmissionShown = stockLook;
  }

  /// Bakes the map's sky shader as opengl1 draws it (far box under scrolling cloud layers)
  /// into six renderer textures; the lightmap preset shows it instead of the bridge's sky.
  void prepareStockSky(const q3::ShaderLibrary& library, ImageCache& images) {
    stockSkyReady = false;
    tracedSky = bridgeSky;
    if (!worldScene || worldScene->sky.shaderName.empty()) return;
    const q3::ShaderDef* shader = library.find(worldScene->sky.shaderName);
    if (shader == nullptr) return;
    const SkyImageLoader load = [&](const std::string& path) { return images.load(engine, path); };
    auto baker = std::make_shared<SkyBaker>();
    if (!baker->prepare(*shader, load, kStockSkyFaceSize)) return;
    SkyCube cube;
    bakeArena.execute([&] { baker->bake(0.0, cube); });
    stockSky = pa::SkyDesc{};
    stockSky.color = glm::vec3(1.0f);
    for (size_t f = 0; f < 6; ++f) {
      pa::TextureDesc desc;
      desc.width = desc.height = static_cast<uint32_t>(cube.size);
      desc.rgba8 = cube.faces[f];
      desc.wrap = pa::TextureWrap::Clamp;
      stockSky.faces[f] = renderer->addTexture(desc);
    }
    skyBaker = std::move(baker);
    stockSky.picture = stockSkyPictureAt(skyBaker, 0.0);
    stockSkySeconds = 0.0;
    stockSkyReady = true;
    // Still clouds (shader time 0): a sky that changed per frame would restart reference's mean.
    tracedSky = litStockSky(stockSky, skyCubeMeanLinear(cube), bridgeSky, pa::bridge::skyLightingRadiance(*worldScene));
    if (!stockSkyShown && !skyHidden) renderer->setSky(tracedSky);   // in place of the upload's bridge sky
  }

  /// Shows the stock sky (its clouds moved to shader time `seconds`) or the traced presets' one.
  void selectSky(bool stockLook, double seconds) {
    const bool stock = stockLook && stockSkyReady;
    const bool moved = stock && skyBaker->animated() && seconds != stockSkySeconds;
    if (moved) {
      stockSky.picture = stockSkyPictureAt(skyBaker, seconds);
      stockSkySeconds = seconds;
    }
    if (!moved && stock == stockSkyShown && !skyHidden) return;
    renderer->setSky(stock ? stockSky : tracedSky);
    stockSkyShown = stock;
    skyHidden = false;
  }

  /// Views without the world (menu models, HUD heads) have nothing behind them: a black sky, so
  /// that their premultiplied picture adds over the 2D only what the rays met (additive glows).
  void hideSky() {
    if (skyHidden) return;
    renderer->setSky(pa::SkyDesc{});
    skyHidden = true;
  }

  /// The renderer texture of an image, repeating or clamped to its edges (clampMap), shrunk by
  /// r_picmip unless `noPicmip`, its colours scaled by r_intensity (as stock treats mipmapped images).
  pa::TextureId texture(const std::shared_ptr<const Image>& image, bool clamp = false, bool noPicmip = false) {
    if (!image) return pa::kNoId;
    const auto key = std::make_tuple(image.get(), clamp, !noPicmip);
    if (const auto found = textures.find(key); found != textures.end()) return found->second.second;
    int width = image->width, height = image->height;
    std::vector<uint8_t> pixels = picmipImage(image->rgba, width, height, noPicmip ? 0 : pictureSettings.picmip);
    applyIntensity(pixels, pictureSettings.intensity);
    pa::TextureDesc desc;
    desc.width = static_cast<uint32_t>(width);
    desc.height = static_cast<uint32_t>(height);
    desc.rgba8 = pixels;
    desc.wrap = clamp ? pa::TextureWrap::Clamp : pa::TextureWrap::Repeat;
    const pa::TextureId id = renderer->addTexture(desc);
    textures.emplace(key, std::make_pair(image, id));
    return id;
  }

  /// The renderer material of a shader handle (resolving RemapShader) at shader time `seconds`.
  /// `layer` 0 is the shader's first stage, k > 0 its look.layers[k - 1]; animMap stages show
  /// the frame of that time, tcMods and waves move with it (entityTranslate by `scroll`).
  pa::MaterialId material(ShaderRegistry& shaders, q3abi::qhandle_t handle, MaterialUse use, uint32_t layer,
                          double seconds, std::array<float, 2> scroll = {0, 0}) {
    const ShaderEntry& entry = shaders.resolve(handle);
    if (layer > entry.look.layers.size() || layer > entry.layerFrames.size()) layer = 0;
    const ShaderLook& look = layer == 0 ? entry.look : entry.look.layers[layer - 1];
    const auto& frames = layer == 0 ? entry.frames : entry.layerFrames[layer - 1];
    uint32_t frameIndex = 0;
    if (frames.size() > 1 && look.animFrequency > 0.0f && std::isfinite(seconds))
      frameIndex = static_cast<uint32_t>(q3::animMapFrame(frames.size(), look.animFrequency, seconds));
    const std::shared_ptr<const Image> image = frames.empty() ? nullptr : frames[frameIndex];
    const MaterialKeyView key{entry.name, use, layer, frameIndex};
    if (const auto found = materials.find(key); found != materials.end()) return found->second;
    auto found = moving.find(key);
    if (found == moving.end()) {   // first use: still or moving
      StageMotion motion = motionOf(look);
      if (!motion.timeDependent()) {
        const pa::MaterialId id = renderer->addMaterial(materialAt(motion, 0.0, describe(entry, look, image, use, layer)));
        materials.emplace(MaterialKey(entry.name, use, layer, frameIndex), id);
        return id;
      }
      found = moving.emplace(MaterialKey(entry.name, use, layer, frameIndex),
                             MovingMaterial{describe(entry, look, image, use, layer), {}, std::move(motion)}).first;
    }
    MovingMaterial& m = found->second;
    return m.pool.get(m.motion, m.still, seconds, scroll, viewCount, *renderer, animationUpdates);
  }

  /// The still look (no animation) of a shader stage drawn as `use` with `image` (entity_materials.h).
  pa::MaterialDesc describe(const ShaderEntry& entry, const ShaderLook& look, const std::shared_ptr<const Image>& image,
                            MaterialUse use, uint32_t layer) {
    const ImageTextures textures = [this](const std::shared_ptr<const Image>& i, bool clamp, bool noPicmip) {
      return texture(i, clamp, noPicmip);
    };
    return describeStage(entry, look, image, use, layer, textures);
  }

  /// The parsed geometry of an MD3 model (LOD 0), parsed once at registration.
  static const q3::Md3Model* md3(const ModelEntry& entry) {
    return entry.lods.empty() ? nullptr : entry.lods[0].get();
  }

  /// Puts a batch into dynamic slot `index` (creating it on first use).
  /// Shader time `seconds` less each triangle's batch.triangleShaderTimes; entityTranslate scrolls by `scroll`.
  void fillSlot(size_t index, ShaderRegistry& shaders, MaterialUse use, const glm::mat4x3& transform,
                uint32_t mask, bool onTop, double seconds, std::array<float, 2> scroll = {0, 0}) {
    if (slots.size() <= index) slots.resize(index + 1);
    DynamicSlot& slot = slots[index];
    addShaderLayers(shaders, batch);
    triangleMaterials.resize(batch.triangles());
    // (shader, layer, shader time behind) -> material: a batch has few, mostly in runs.
    slotMaterials.clear();
    for (size_t t = 0; t < batch.triangleShaders.size(); ++t) {
      const float behind = t < batch.triangleShaderTimes.size() ? batch.triangleShaderTimes[t] : 0.0f;
      const SlotMaterialKey key{batch.triangleShaders[t], t < batch.triangleLayers.size() ? batch.triangleLayers[t] : 0u, behind};
      auto found = std::find_if(slotMaterials.rbegin(), slotMaterials.rend(),
                                [&](const auto& entry) { return entry.first == key; });
      if (found == slotMaterials.rend()) {
        slotMaterials.emplace_back(key, material(shaders, std::get<0>(key), use, std::get<1>(key), seconds - behind, scroll));
        found = slotMaterials.rbegin();
      }
      triangleMaterials[t] = found->second;
    }
    pa::InstanceDesc instance;
    instance.objectToWorld = transform;
    instance.mask = mask;
    instance.drawOnTop = onTop;
    showInSlot(slot, batch, triangleMaterials, instance);
  }

  /// Hides every slot no entity claimed this frame.
  void hideUnclaimedSlots() {
    for (size_t i = 0; i < slots.size(); ++i)
      if (!entitySlots.claimed(i)) hideSlot(slots[i]);
  }

  /// Hides a dynamic slot's instance: it shows the empty mesh (its own mesh keeps the last
  /// triangles until the slot is shown again).
  void hideSlot(DynamicSlot& slot) {
    if (!slot.visible || slot.instance == pa::kNoId) return;
    pa::InstanceDesc hidden;
    hidden.mesh = emptyMesh;
    hidden.mask = 0;
    renderer->setInstance(slot.instance, hidden);
    slot.visible = false;
  }

  void setBrushInstance(size_t model, const pa::InstanceDesc& desc) {
    if (model >= world.modelInstances.size() || world.modelInstances[model] == pa::kNoId) return;
    if (sameInstance(brushInstances[model], desc)) return;
    renderer->setInstance(world.modelInstances[model], desc);
    brushInstances[model] = desc;
  }

  void setLight(size_t index, const pa::LightDesc& desc, bool on) {
    if (index >= lights.size()) {
      lights.push_back(renderer->addLight(desc));
      lightOn.push_back(on);
      return;
    }
    if (!on && !lightOn[index]) return;
    renderer->setLight(lights[index], desc);
    lightOn[index] = on;
  }
};

bool ViewRenderer::available() { return true; }

ViewRenderer::ViewRenderer(const Engine& engine, int threads) : impl_(new Impl{engine, threads}) {
  pinThreadPoolLibrary(engine);
  impl_->resetRenderer();
}

ViewRenderer::~ViewRenderer() = default;

void ViewRenderer::clearWorld() {
  impl_->resetRenderer();
}

void ViewRenderer::setPicture(const PictureSettings& picture) {
  if (picture.picmip != impl_->pictureSettings.picmip || picture.intensity != impl_->pictureSettings.intensity)
    impl_->textures.clear();   // entity textures are made again at the new detail
  impl_->pictureSettings = picture;
}

void ViewRenderer::shadersChanged() {
  // Remapped shaders resolve to other entries: rebuild entity materials lazily.
  impl_->materials.clear();
  impl_->moving.clear();
}

void ViewRenderer::loadWorld(const World& world, const ShaderScripts& moduleScripts, ImageCache& images) {
  Impl& d = *impl_;
  d.resetRenderer();
  const Engine& engine = d.engine;
  const int start = engine.milliseconds();
  const q3::BspFile& bsp = world.bsp();
  const q3::ShaderLibrary& library = world.shaders();
  const q3::FileLoader loader = [&](std::string_view path) -> std::optional<std::vector<std::byte>> {
    auto bytes = engine.readFile(std::string(path));
    if (!bytes) return std::nullopt;
    const auto* p = reinterpret_cast<const std::byte*>(bytes->data());
    return std::vector<std::byte>(p, p + bytes->size());
  };
  d.worldScene = q3::buildWorldScene(bsp, world.surfaces(), library, loader);
  for (const std::string& warning : d.worldScene->warnings)
    engine.print(q3abi::PRINT_DEVELOPER, "pathtracer: %s\n", warning.c_str());
  stockWorldLook(*d.worldScene, library, d.glowColors, d.pictureSettings.lightShift());
  applyPictureToWorld(*d.worldScene, library, d.pictureSettings);
  d.worldDeforms.extract(*d.worldScene, library);   // before the upload: leaves the static mesh
  pa::bridge::UploadOptions upload;
  upload.lightmapShift = d.pictureSettings.lightShift();
  d.world = pa::bridge::uploadWorld(*d.worldScene, *d.renderer, upload);
  d.bridgeSky = d.world.sky;
  d.renderer->setSky(d.bridgeSky);
  d.fog.load(std::move(d.world.fog), *d.renderer);
  d.worldDeforms.bind(*d.worldScene, d.world);
  d.worldAnimation.prepare(*d.worldScene, library, d.world, *d.renderer, [&](const std::string& path, bool clamp) {
    return d.texture(images.load(engine, path), clamp);
  });
  d.portals.load(bsp, *d.worldScene);
  d.prepareStockSky(library, images);
  d.dlightBuilder.prepare(*d.worldScene);
  d.scripts = &moduleScripts;
  d.images = &images;
  d.prepareWorldSprites(library);
  d.brushInstances.assign(d.world.modelInstances.size(), pa::InstanceDesc{});
  for (size_t m = 0; m < d.world.modelInstances.size(); ++m) {
    d.brushInstances[m].mesh = m < d.world.modelMeshes.size() ? d.world.modelMeshes[m] : pa::kNoId;
    d.brushInstances[m].mask = pa::kMaskAll;
  }
  d.modelDeforms.reset(world.sharedShaders());
  d.renderer->commit();
  engine.print(q3abi::PRINT_ALL,
               "pathtracer: %s traced scene: %zu materials, %zu textures, %zu lights, %llu "
               "triangles + %zu deformed, %zu fog volumes, %zu animated materials (%d ms)\n",
               world.name().c_str(), d.worldScene->materials.size(), d.worldScene->textures.size(),
               d.worldScene->lights.size(), static_cast<unsigned long long>(d.world.triangles),
               d.worldDeforms.triangles(), d.fog.size(), d.worldAnimation.animatedCount(), engine.milliseconds() - start);
}

std::optional<TracedPicture> ViewRenderer::render(const q3abi::refdef_t& view,
                                                  const SceneFrame& scene,
                                                  const TracerSettings& settings,
                                                  ShaderRegistry& shaders,
                                                  const ModelRegistry& models, const World* world) {
  Impl& d = *impl_;
  const auto start = std::chrono::steady_clock::now();
  const bool withWorld = world != nullptr && d.worldScene.has_value();
  pa::Camera camera;
  camera.origin = {view.vieworg[0], view.vieworg[1], view.vieworg[2]};
  camera.forward = {view.viewaxis[0][0], view.viewaxis[0][1], view.viewaxis[0][2]};
  camera.left = {view.viewaxis[1][0], view.viewaxis[1][1], view.viewaxis[1][2]};
  camera.up = {view.viewaxis[2][0], view.viewaxis[2][1], view.viewaxis[2][2]};
  camera.fovX = std::clamp(view.fov_x, 1.0f, 179.0f);
  camera.fovY = std::clamp(view.fov_y, 1.0f, 179.0f);
  const Viewer viewer{camera.origin, camera.left, camera.up};
  const bool lightmapLook = settings.preset == Preset::Lightmap;
  const double seconds = view.time * 0.001;   // the stock shader time of this view
  ++d.viewCount;
  d.animationUpdates = 0;
  double animationMs = 0.0;

  // The world and its brush models: hidden in model-only views, placed by their entities.
  std::vector<bool>& brushPlaced = d.brushPlaced;
  brushPlaced.assign(d.world.modelInstances.size(), false);
  d.entitySlots.beginFrame();
  for (const q3abi::refEntity_t& e : scene.entities()) {
    uint32_t mask = pa::kMaskAll;
    if (e.renderfx & q3abi::RF_THIRD_PERSON) mask &= ~uint32_t(pa::kMaskCamera);
    if (e.renderfx & q3abi::RF_FIRST_PERSON) mask = pa::kMaskCamera;
    const bool onTop = (e.renderfx & q3abi::RF_DEPTHHACK) != 0;
    if (e.reType != q3abi::RT_MODEL) continue;
    const ModelEntry* model = models.model(e.hModel);
    if (model == nullptr || !placeable(entityTransform(e))) continue;
    if (model->kind == ModelKind::Brush) {
      const auto index = static_cast<size_t>(model->brushIndex);
      if (!withWorld || index >= brushPlaced.size()) continue;
      pa::InstanceDesc desc = d.brushInstances[index];
      desc.objectToWorld = entityTransform(e);
      desc.mask = mask;
      d.setBrushInstance(index, desc);
      brushPlaced[index] = true;
      continue;
    }
    const q3::Md3Model* md3 = d.md3(*model);
    if (md3 == nullptr) continue;
    md3SurfaceShaders(*md3, e, models.skin(e.customSkin), shaders, d.surfaceShaders);
    const std::vector<q3abi::qhandle_t>& surfaceShaders = d.surfaceShaders;
    d.batch.clear();
    std::vector<bool>& autosprite = d.surfaceAutosprite;
    autosprite.assign(surfaceShaders.size(), false);
    for (size_t s = 0; s < surfaceShaders.size(); ++s) autosprite[s] = shaders.resolve(surfaceShaders[s]).look.autosprite;
    appendMd3(*md3, e, surfaceShaders, d.batch, autosprite, spriteAxesFor(e, viewer));
    if (d.batch.indices.empty()) continue;
    deformBatch(d.batch, seconds, [&](q3abi::qhandle_t h) { return d.modelDeforms.find(shaders.resolve(h).name); });
    if (lightmapLook) {
      const float* at = (e.renderfx & q3abi::RF_LIGHTING_ORIGIN) ? e.lightingOrigin : e.origin;
      const glm::vec3 lightOrigin(at[0], at[1], at[2]);
      EntityLight light;
      if (!withWorld || !lightGridAt(d.worldScene->lightGrid, lightOrigin, light, d.pictureSettings.lightShift()))
        light = noWorldLight();
      light = finishEntityLight(light, lightOrigin, scene.lights());
      lightModelLikeStock(e, entityTransform(e), light, shaders, d.batch);
    }
    const EntityKey key{e.hModel, e.customSkin, e.customShader, onTop ? 1 : 0};
    d.fillSlot(d.entitySlots.claim(key, glm::vec3(e.origin[0], e.origin[1], e.origin[2])), shaders,
               MaterialUse::Model, entityTransform(e), mask, onTop, seconds - e.shaderTime,
               {e.shaderTexCoord[0], e.shaderTexCoord[1]});
  }
  for (size_t m = 0; m < brushPlaced.size(); ++m) {
    pa::InstanceDesc desc = d.brushInstances[m];
    if (m == 0) {
      desc.mask = withWorld ? pa::kMaskAll : 0;
      desc.objectToWorld = glm::mat4x3(1.0f);
    } else if (!brushPlaced[m]) {
      desc.mask = 0;   // a mover the game did not add this frame is not drawn
    } else {
      continue;
    }
    d.setBrushInstance(m, desc);
  }
  // Where each world model is this view (null: not drawn); one reference captured, so the
  // std::function it becomes holds it without a heap block.
  const struct {
    const Impl& d;
    bool withWorld;
    glm::mat4x3 identity{1.0f};
  } placing{d, withWorld};
  const auto placeOf = [&placing](uint32_t model) -> const glm::mat4x3* {
    if (model == 0) return placing.withWorld ? &placing.identity : nullptr;
    const Impl& v = placing.d;
    return model < v.brushPlaced.size() && v.brushPlaced[model] ? &v.brushInstances[model].objectToWorld : nullptr;
  };
  d.worldDeforms.update(seconds, placeOf, *d.renderer);

  // Effects and polygons: one world-space mesh.
  d.batch.clear();
  for (const q3abi::refEntity_t& e : scene.entities()) {
    if (e.reType == q3abi::RT_MODEL) continue;
    const size_t before = d.batch.triangles();
    if (!appendEffect(e, viewer, d.batch) || e.shaderTime == 0.0f) continue;
    d.batch.triangleShaderTimes.resize(before, 0.0f);   // an entity's shader clock runs shaderTime behind
    d.batch.triangleShaderTimes.resize(d.batch.triangles(), e.shaderTime);
  }
  appendPolys(scene.polys(), scene.polyVerts(), d.batch);
  if (withWorld)
    d.worldSprites.append(
        seconds, viewer, [&](const std::string& name) { return d.spriteHandle(shaders, name); },
        [&](uint32_t model) -> const glm::mat4x3* {
          return model < brushPlaced.size() && brushPlaced[model] ? &d.brushInstances[model].objectToWorld : nullptr;
        },
        d.batch);
  if (!d.batch.indices.empty()) {
    if (lightmapLook) premultiplyBlendedEffects(shaders, d.batch);
    d.fillSlot(d.entitySlots.claim(EntityKey{0, 0, 0, 2}, glm::vec3(0.0f)), shaders,
               lightmapLook ? MaterialUse::StockEffect : MaterialUse::Effect, glm::mat4x3(1.0f), pa::kMaskAll, false,
               seconds);
  }
  d.hideUnclaimedSlots();

  // Dynamic lights (radius = reach, linear falloff as in Quake); a headlight for model views.
  size_t lightIndex = 0;
  for (const DynamicLight& light : scene.lights()) {
    pa::LightDesc desc;
    desc.type = pa::LightType::Point;
    desc.position = light.origin;
    desc.color = light.color;
    desc.intensity = kPi;
    desc.falloff = pa::Falloff::Linear;
    desc.range = light.radius;
    d.setLight(lightIndex++, desc, true);
  }
  if (!withWorld) {   // views of the world are lit by the world alone
    pa::LightDesc head;
    head.type = pa::LightType::Directional;
    head.direction = glm::normalize(camera.forward - camera.up * 0.5f);
    head.intensity = kPi;
    d.setLight(lightIndex++, head, true);
  }
  for (size_t i = lightIndex; i < d.lights.size(); ++i) {
    pa::LightDesc off;
    off.intensity = 0.0f;
    d.setLight(i, off, false);
  }
  if (withWorld) {
    d.portals.update(scene.entities(), view.time, *d.renderer);
    d.selectSky(lightmapLook, seconds);
    d.selectWorldEmission(lightmapLook);
    const auto animationStart = std::chrono::steady_clock::now();
    d.worldAnimation.update(seconds, *d.renderer);
    animationMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - animationStart).count();
  } else {
    d.hideSky();
  }
  d.drawStockDlights(scene.lights(), withWorld && lightmapLook);
  d.fog.show(withWorld, *d.renderer);
  const double sceneMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  d.renderer->commit();

  pa::RenderSettings rs;
  const float scale = withWorld ? settings.resolutionScale : 1.0f;
  rs.width = static_cast<uint32_t>(std::max(8, static_cast<int>(std::lround(view.width * scale))));
  rs.height = static_cast<uint32_t>(std::max(8, static_cast<int>(std::lround(view.height * scale))));
  rs.integrator = integratorFor(settings.preset);
  rs.samplesPerPixel = static_cast<uint32_t>(settings.samplesPerPixel);
  rs.maxBounces = static_cast<uint32_t>(settings.maxBounces);
  rs.accumulate = settings.preset == Preset::Reference;
  rs.radianceClamp = settings.radianceClamp >= 0.0f ? settings.radianceClamp
                     : settings.preset == Preset::Reference ? 0.0f : 10.0f;
  rs.seed = settings.seed + (rs.accumulate ? 0u : d.frameCounter++);
  rs.denoise = settings.denoise && (settings.preset == Preset::Direct || settings.preset == Preset::Path);
  // Views of the world only: HUD model views share one renderer between differing views.
  rs.temporal = settings.temporal && withWorld && (settings.preset == Preset::Direct || settings.preset == Preset::Path);
  rs.restir = settings.restir && withWorld && (settings.preset == Preset::Direct || settings.preset == Preset::Path);
  rs.spreadFireflies = settings.fireflies;   // with the denoiser or temporal accumulation only
  // The stock look has no tone curve: colours are clamped, as opengl1's framebuffer does. The
  // traced presets show the light they find as the lightmap shows its texels (r_pt_look stock).
  if (lightmapLook || settings.stockLook) rs.tonemap = pa::Tonemap::Clamp;
  if (!lightmapLook && settings.stockLook) rs.lightingLook = pa::LightingLook::DisplaySpace;
  const pa::FrameView frame = d.renderer->render(camera, rs);

  d.picture.assign(frame.rgba8.begin(), frame.rgba8.end());
  if (!withWorld && frame.depth.size() * 4 == d.picture.size()) {
    for (size_t i = 0; i < frame.depth.size(); ++i)
      if (!std::isfinite(frame.depth[i])) d.picture[i * 4 + 3] = 0;   // see-through background
  }
  const ViewTimings timings{sceneMs, frame.timings.commitMs, frame.timings.traceMs, frame.timings.temporalMs,
                            frame.timings.denoiseMs, frame.timings.resolveMs, animationMs,
                            double(d.animationUpdates + (withWorld ? d.worldAnimation.lastUpdates() : 0)),
                            frame.timings.resampleMs};
  return TracedPicture{static_cast<int>(frame.width), static_cast<int>(frame.height), d.picture.data(), timings,
                       frame.accumulatedFrames, frame.radiance, frame.variance};
}

}  // namespace glue

#pragma once
// ViewRenderer's insides (views_traced*.cpp only): what lives as long as the module, the state of
// the loaded map (MapState, renewed as one value by startMap), the working buffers that keep
// their capacity from view to view (ViewScratch), and the per-view passes render() runs.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/mat4x3.hpp>
#include <glm/vec3.hpp>
#include <tbb/task_arena.h>

#include "port/engine_glue/entity_geometry.h"
#include "port/engine_glue/entity_materials.h"
#include "port/engine_glue/entity_slots.h"
#include "port/engine_glue/fog_volumes.h"
#include "port/engine_glue/images.h"
#include "port/engine_glue/models.h"
#include "port/engine_glue/portals.h"
#include "port/engine_glue/scene.h"
#include "port/engine_glue/shader_animation.h"
#include "port/engine_glue/shader_scripts.h"
#include "port/engine_glue/shaders.h"
#include "port/engine_glue/sky_cube.h"
#include "port/engine_glue/views.h"
#include "port/engine_glue/world_deforms.h"
#include "port/engine_glue/world_sprites.h"
#include "port/q3formats/model/md3.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/world/world_scene.h"
#include "port/scene_bridge/scene_bridge.h"
#include "renderer/scene/renderer.h"

namespace glue {

/// A reusable dynamic mesh + instance.
struct DynamicSlot {
  pa::MeshId mesh = pa::kNoId;           ///< Made on first use.
  pa::InstanceId instance = pa::kNoId;   ///< Made on first use.
  bool visible = false;                  ///< The instance shows the slot's mesh.
};

/// (shader name, use, layer, animation frame) -> renderer material.
using MaterialKey = std::tuple<std::string, MaterialUse, uint32_t, uint32_t>;
/// A MaterialKey to look up with (transparent comparison: no string is made per lookup).
using MaterialKeyView = std::tuple<std::string_view, MaterialUse, uint32_t, uint32_t>;

/// Animated shaders (shader_animation.h): their still look and their materials per shader time.
struct MovingMaterial {
  pa::MaterialDesc still;     ///< The look before motion.
  MovingMaterialPool pool;    ///< Its materials per shader time.
  StageMotion motion;         ///< How it moves.
};

/// Everything the renderer and the glue know of the loaded map: ids into the renderer that
/// startMap made, and what was derived from the map. Replaced as a whole by startMap.
struct MapState {
  std::optional<q3::WorldScene> worldScene;      ///< The map as the bridge reads it (none: no world).
  pa::bridge::WorldHandles world;                ///< The renderer ids uploadWorld made.
  std::vector<pa::InstanceDesc> brushInstances;   ///< Current description per world model.
  std::map<MaterialKey, pa::MaterialId, std::less<>> materials;   ///< Still entity materials.
  std::map<MaterialKey, MovingMaterial, std::less<>> moving;      ///< Animated entity materials.
  WorldAnimation worldAnimation;   ///< World and brush-model materials at refdef time.
  /// (image, clamp, picmip applies) -> renderer texture.
  std::map<std::tuple<const Image*, bool, bool>, std::pair<std::shared_ptr<const Image>, pa::TextureId>> textures;
  std::vector<DynamicSlot> slots;   ///< Entity and effect meshes.
  EntitySlots entitySlots;          ///< Which slot each model entity (and the effects batch) takes.
  /// The model slot that has shown the most triangles: every slot takes its memory (reserveSlotMemory).
  size_t largestSlot = SIZE_MAX;
  size_t largestSlotTriangles = 0;   ///< How many.
  bool largestSlotGrew = false;      ///< The other slots take its memory at the next view.
  std::vector<pa::LightId> lights;  ///< Dynamic lights (a pool, reused from view to view).
  std::vector<bool> lightOn;        ///< Per pooled light: lit in the last view.
  pa::MaterialId defaultMaterial = pa::kNoId;   ///< A plain material, the renderer's first (startMap).
  int preparedShaders = 0;     ///< Shader handles below this have their materials made (prepareMaterials).
  int preparedLook = -1;       ///< The look they were made for (1: lightmap, 0: traced, -1: none yet).
  /// A mesh without triangles: hidden dynamic slots show it, so that the renderer leaves their
  /// instances out of the scene (no stale boxes in the instance hierarchy, no lights from them).
  pa::MeshId emptyMesh = pa::kNoId;
  PortalViews portals;            ///< Mirrors and portal cameras (portals.h).
  pa::SkyDesc bridgeSky;          ///< The world's sky as the bridge makes it (how it lights).
  pa::SkyDesc stockSky;           ///< The stock look (far box + clouds) for the lightmap preset.
  pa::SkyDesc tracedSky;          ///< The traced presets': the stock look lighting as bridgeSky.
  bool skyHidden = false;         ///< A view without the world set a black sky.
  bool stockSkyReady = false;     ///< stockSky was baked (the map has a sky shader).
  bool stockSkyShown = false;     ///< The renderer shows stockSky (else tracedSky).
  /// World surface lights drawn the stock way (1) or as the traced presets see them (0); -1 =
  /// as uploaded, not yet chosen.
  int stockEmissionShown = -1;
  /// The stock sky: its cube faces are baked once per map (the sky's mean and sampling); camera
  /// rays see stockSkyPicture (stockSky.picture), moved to each view's shader time in place, so
  /// moving clouds cost no bake, texture or allocation per frame.
  std::shared_ptr<const SkyBaker> skyBaker;
  std::shared_ptr<StockSkyPicture> stockSkyPicture;
  double stockSkySeconds = -1.0;   ///< Shader time of stockSky.picture.
  std::unordered_map<uint32_t, glm::vec3> glowColors;   ///< World material -> glow stage colour (linear).
  WorldSprites worldSprites;                 ///< deformVertexes autosprite world surfaces.
  std::vector<uint32_t> spriteMaterials;     ///< Their world materials (static copy hidden).
  std::unordered_map<std::string, q3abi::qhandle_t> spriteHandles;   ///< Their shaders' handles.
  const ShaderScripts* scripts = nullptr;    ///< The module's, while a world is loaded.
  ImageCache* images = nullptr;              ///< The module's, while a world is loaded.
  WorldDeforms worldDeforms;    ///< deformVertexes wave/normal/bulge/move world surfaces (dynamic meshes).
  ShaderDeforms modelDeforms;   ///< The same deforms on MD3 surfaces, by shader name.
  ViewFog fog;                  ///< The map's fog volumes.
};

/// Working memory of one view, refilled every view: it keeps its capacity so that steady
/// play does not allocate (CTest engine_allocations).
struct ViewScratch {
  GeometryBatch batch;                                ///< An entity's (or the effects') triangles.
  std::vector<pa::MaterialId> triangleMaterials;      ///< ... and their materials.
  /// (shader, layer, shader time behind) of a batch's triangles.
  using SlotMaterialKey = std::tuple<q3abi::qhandle_t, uint32_t, float>;
  std::vector<std::pair<SlotMaterialKey, pa::MaterialId>> slotMaterials;   ///< fillSlot's working list.
  std::vector<q3abi::qhandle_t> surfaceShaders;   ///< An MD3 entity's shader per surface.
  std::vector<bool> surfaceAutosprite;            ///< ... and whether it is an autosprite.
  std::vector<bool> brushPlaced;                  ///< Per brush model: placed by an entity this view.
  std::vector<pa::StockDynamicLight> stockDlights;   ///< The stock dynamic-light pass's lights.
  std::vector<uint8_t> picture;                   ///< The traced view handed out (RGBA8).
};

/// What every pass of one view reads.
struct ViewContext {
  pa::Camera camera;           ///< The view's camera.
  Viewer viewer;               ///< The same, for sprites facing it.
  bool withWorld = false;      ///< The world is drawn (not a model-only view).
  bool lightmapLook = false;   ///< The stock look: the lightmap preset, and HUD model views (stockLookFor).
  double seconds = 0.0;        ///< The view's stock shader time.
};

/// What the glue measured and set up for the view being traced (render, start).
struct StartedView {
  ViewContext ctx;               ///< The view's context.
  double sceneMs = 0.0;          ///< ViewTimings::sceneMs.
  double animationMs = 0.0;      ///< ViewTimings::animationMs.
  double animationUpdates = 0.0; ///< ViewTimings::animationUpdates.
};

/// ViewRenderer's state by lifetime, and its passes.
struct ViewRenderer::Impl {
  /// Holds the engine; `threads` = r_pt_threads (0: all cores), `avx2Kernels` = r_pt_isa avx2,
  /// `lampVisibility` = r_pt_lamp_vis.
  /// startMap makes the renderer.
  Impl(const Engine& engine, int threads, bool avx2Kernels, bool lampVisibility);

  // ---- for the module's life
  const Engine& engine;              ///< Files, cvars and printing.
  const int threads;                 ///< The renderer's threads (0: all cores).
  const bool avx2Kernels;            ///< The renderer's BVHs keep the AVX2 kernels (RendererConfig::bvh).
  const bool lampVisibility;         ///< RendererConfig::lampVisibility.
  /// The threads the sky bake may use: as many as the renderer's (r_pt_threads, 0 = all cores).
  tbb::task_arena bakeArena;
  PictureSettings pictureSettings;   ///< r_picmip, r_intensity, r_mapOverBrightBits for what is loaded.
  uint64_t viewCount = 0;            ///< Views rendered (MovingMaterialPool's clock).
  uint32_t frameCounter = 0;         ///< Seeds of the presets that do not accumulate.
  size_t animationUpdates = 0;       ///< Entity materials replaced for animation in this view.

  // ---- per map: startMap() replaces the renderer and the map state together
  std::unique_ptr<pa::Renderer> renderer;   ///< The tracer and its scene.
  MapState map;                             ///< What the tracer and the glue know of the map.

  // ---- reused from view to view
  ViewScratch scratch;                      ///< Working buffers (keep their capacity).
  StartedView started;                      ///< The view last set up (prepareView).

  /// Waits for a view start() began and drops its picture (saying why if it failed): whatever
  /// changes the renderer or the map state does this first.
  void dropStartedView();
  /// Every pass of a view up to the renderer's commit; fills `started`; returns the view's settings.
  pa::RenderSettings prepareView(const q3abi::refdef_t& view, const SceneFrame& scene, const TracerSettings& settings,
                                 ShaderRegistry& shaders, const ModelRegistry& models, const World* world);

  /// A new renderer and an empty map state (constructor, map change).
  void startMap();
  /// Builds the map's scene: world, sky, fog, deforms, animation, portals, sprites, dynamic lights.
  void loadMap(const World& world, const ShaderScripts& moduleScripts, ImageCache& images);

  // ---- the passes of one view (views_traced.cpp), in render() order
  /// The camera and what every pass reads.
  ViewContext beginView(const q3abi::refdef_t& view, const TracerSettings& settings, const World* world);
  /// Brush models placed by their entities; every MD3 entity into its dynamic slot.
  void placeModelEntities(const ViewContext& ctx, const SceneFrame& scene, ShaderRegistry& shaders,
                          const ModelRegistry& models);
  /// The world shown unless model-only; movers the game did not add this view hidden.
  void placeBrushModels(const ViewContext& ctx);
  /// deformVertexes world surfaces at the view's shader time, where their models are.
  void deformWorld(const ViewContext& ctx);
  /// Effects, polygons and world autosprites as one world-space mesh; unclaimed slots hidden.
  void drawEffects(const ViewContext& ctx, const SceneFrame& scene, ShaderRegistry& shaders);
  /// The frame's dynamic lights (and a headlight for model-only views) into the light pool.
  void placeDynamicLights(const ViewContext& ctx, std::span<const DynamicLight> lights);
  /// Portals, sky, surface lights and world animation of the preset; returns the animation's ms.
  double showWorldLook(const ViewContext& ctx, std::span<const q3abi::refEntity_t> entities, int timeMs);
  /// The renderer's settings for this view's preset.
  pa::RenderSettings renderSettings(const ViewContext& ctx, const q3abi::refdef_t& view,
                                    const TracerSettings& settings);
  /// The traced frame as the picture handed out (see-through background for model-only views).
  TracedPicture picture(const pa::FrameView& frame, const StartedView& glue);

  // ---- the world's look (views_traced_world.cpp)
  /// Hides the static copies of the autosprite world surfaces (drawn per view instead).
  void prepareWorldSprites(const q3::ShaderLibrary& library);
  /// The shader handle of an autosprite world shader (registered on first use; 0 if it fails).
  q3abi::qhandle_t spriteHandle(ShaderRegistry& shaders, const std::string& name);
  /// Lightmap preset: q3map_surfacelight surfaces glow only through their glow stage.
  void selectWorldEmission(bool stockLook);
  /// Bakes the map's sky shader as opengl1 draws it into six renderer textures.
  void prepareStockSky(const q3::ShaderLibrary& library, ImageCache& images);
  /// Shows the stock sky (its clouds moved to shader time `seconds`) or the traced presets' one.
  void selectSky(bool stockLook, double seconds);
  /// A black sky for views without the world.
  void hideSky();
  /// Lightmap preset: the world brightened by dynamic lights the stock way (lights/stock_dlights.h).
  void drawStockDlights(std::span<const DynamicLight> lights, bool show);

  // ---- entity materials and dynamic meshes (views_traced_materials.cpp)
  /// The renderer texture of an image (clamped or repeating, r_picmip unless noPicmip, r_intensity).
  pa::TextureId texture(const std::shared_ptr<const Image>& image, bool clamp = false, bool noPicmip = false);
  /// The renderer material of a shader handle's stage `layer` drawn as `use` at shader time `seconds`.
  pa::MaterialId material(ShaderRegistry& shaders, q3abi::qhandle_t handle, MaterialUse use, uint32_t layer,
                          double seconds, std::array<float, 2> scroll = {0, 0});
  /// Makes the materials (and textures) of every shader registered since the last call, for
  /// this look's model and effect uses, every stage and animMap frame: play then finds them made
  /// instead of creating them the first time an effect shows (no allocation in steady play).
  /// Without `pictures`, shaders registered for 2D (no mipmaps) are left to be made on first use.
  void prepareMaterials(ShaderRegistry& shaders, bool lightmapLook, bool pictures);
  /// The still look (no animation) of a shader stage drawn as `use` with `image`.
  pa::MaterialDesc describe(const ShaderEntry& entry, const ShaderLook& look, const std::shared_ptr<const Image>& image,
                            MaterialUse use, uint32_t layer);
  /// The parsed geometry of an MD3 model (LOD 0), parsed once at registration.
  static const q3::Md3Model* md3(const ModelEntry& entry);
  /// Puts scratch.batch into the dynamic slot the entity `key` at `origin` claims (created on
  /// first use) with its materials; with `specularViewer` (the viewer in the batch's object
  /// space) layers with alphaGen lightingSpecular get the stock specular alpha (specularAlphaLikeStock).
  void fillSlot(const EntityKey& key, const glm::vec3& origin, ShaderRegistry& shaders, MaterialUse use,
                const glm::mat4x3& transform, uint32_t mask, bool onTop, double seconds,
                std::array<float, 2> scroll = {0, 0}, const glm::vec3* specularViewer = nullptr);
  /// Uploads dynamic triangles with one material per triangle into `slot` and shows its instance.
  template <typename Geometry>
  void showInSlot(DynamicSlot& slot, const Geometry& geometry, const std::vector<pa::MaterialId>& materials,
                  pa::InstanceDesc instance);
  /// Once the largest slot has grown (and its BVH was built), every slot takes as much memory,
  /// so that an entity showing a large model in a slot that held small ones allocates nothing.
  void reserveSlotMemory();
  /// Hides every slot no entity claimed this view.
  void hideUnclaimedSlots();
  /// Hides a dynamic slot's instance (it shows the empty mesh).
  void hideSlot(DynamicSlot& slot);
  /// Sets brush model `model`'s instance when its description changed.
  void setBrushInstance(size_t model, const pa::InstanceDesc& desc);
  /// Sets dynamic light `index` of the pool (added on first use; lights off stay untouched).
  void setLight(size_t index, const pa::LightDesc& desc, bool on);
};

template <typename Geometry>
void ViewRenderer::Impl::showInSlot(DynamicSlot& slot, const Geometry& geometry,
                                    const std::vector<pa::MaterialId>& materials, pa::InstanceDesc instance) {
  const pa::MeshDesc mesh = pa::meshDescOf(geometry, materials, true);
  if (slot.mesh == pa::kNoId) slot.mesh = renderer->addMesh(mesh);
  else renderer->updateMesh(slot.mesh, mesh);
  instance.mesh = slot.mesh;
  if (slot.instance == pa::kNoId) slot.instance = renderer->addInstance(instance);
  else renderer->setInstance(slot.instance, instance);
  slot.visible = true;
}

}  // namespace glue

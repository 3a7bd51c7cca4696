// ViewRenderer over pa::Renderer. The map is read once per LoadWorld (glue::World's q3::BspFile,
// tessellation and shader library -> q3::WorldScene -> pa_scene_bridge, whose sky and fog it
// shows; portal surfaces -> PortalViews, portals.h); per view, render() runs its passes in
// order: brush sub-models get their entity transforms, every MD3 entity becomes a dynamic mesh
// instance, effects and polygons one world-space dynamic mesh, dynamic lights reuse a pool of
// renderer lights, portals follow the frame's RT_PORTALSURFACE entities, and the frame is traced
// at r_pt_scale resolution.
// The lightmap preset adds the stock opengl1 look (README "The lightmap preset's stock look"):
// the stock sky (sky_cube.h), dynamic-light overlay, world autosprites, stock model colours
// (stock_look.h).
// The state is split by lifetime (views_traced_impl.h): the map's (MapState, one value renewed
// by startMap), the views' working buffers (ViewScratch) and the module's.
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "port/engine_glue/engine.h"
#include "port/engine_glue/entity_lighting.h"
#include "port/engine_glue/stock_look.h"
#include "port/engine_glue/views_traced_impl.h"
#include "port/engine_glue/world.h"

namespace glue {
namespace {

constexpr float kPi = 3.14159265358979f;

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

glm::mat4x3 entityTransform(const q3abi::refEntity_t& e) {
  glm::mat4x3 m(1.0f);
  for (int a = 0; a < 3; ++a) m[a] = glm::vec3(e.axis[a][0], e.axis[a][1], e.axis[a][2]);
  m[3] = glm::vec3(e.origin[0], e.origin[1], e.origin[2]);
  return m;
}

/// The viewer in an entity's model space as stock computes it (R_RotateForEntity): the offset
/// from the entity dotted with each axis, divided by the first axis' length when the axes are
/// not normalised.
glm::vec3 viewerInModel(const q3abi::refEntity_t& e, const glm::vec3& viewer) {
  const glm::mat4x3 m = entityTransform(e);
  const glm::vec3 delta = viewer - m[3];
  float scale = 1.0f;
  if (e.nonNormalizedAxes) {
    const float length = glm::length(m[0]);
    scale = length > 0.0f ? 1.0f / length : 0.0f;
  }
  return glm::vec3(glm::dot(delta, m[0]), glm::dot(delta, m[1]), glm::dot(delta, m[2])) * scale;
}

/// The stock look (textures x baked light, as opengl1 draws): the lightmap preset's world views,
/// and the HUD's model views (RDF_NOWORLDMODEL icons and heads) in every preset. Those are
/// interface pictures with no world to light them: the stock entity light (noWorldLight) shows
/// them as the game draws them; traced at 1 spp they would be speckled and cost more.
bool stockLookFor(const TracerSettings& settings, bool withWorld) {
  return settings.preset == Preset::Lightmap || !withWorld;
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

bool ViewRenderer::available() { return true; }

ViewRenderer::ViewRenderer(const Engine& engine, int threads, bool avx2Kernels, bool lampVisibility)
    : impl_(new Impl(engine, threads, avx2Kernels, lampVisibility)) {
  pinThreadPoolLibrary(engine);
  impl_->startMap();
}

ViewRenderer::~ViewRenderer() { impl_->dropStartedView(); }   // its tasks read the map state

void ViewRenderer::clearWorld() {
  impl_->dropStartedView();
  impl_->startMap();
}

void ViewRenderer::setPicture(const PictureSettings& picture) {
  impl_->dropStartedView();
  if (picture.picmip != impl_->pictureSettings.picmip || picture.intensity != impl_->pictureSettings.intensity)
    impl_->map.textures.clear();   // entity textures are made again at the new detail
  impl_->pictureSettings = picture;
}

void ViewRenderer::shadersChanged() {
  impl_->dropStartedView();
  // Remapped shaders resolve to other entries: rebuild entity materials lazily.
  impl_->map.materials.clear();
  impl_->map.moving.clear();
  impl_->map.preparedShaders = 0;
}

void ViewRenderer::prepareForPlay(ShaderRegistry& shaders, const TracerSettings& settings, bool withWorld) {
  Impl& d = *impl_;
  d.dropStartedView();
  const bool world = withWorld && d.map.worldScene.has_value();
  const bool lightmapLook = stockLookFor(settings, world);
  // The world's autosprite shaders are registered by the first view that draws them (the game
  // registers none): here, so that their materials are made below with the others.
  if (world) d.map.worldSprites.forEachShader([&](const std::string& name) { d.spriteHandle(shaders, name); });
  d.prepareMaterials(shaders, lightmapLook, world);
  if (!world) return;
  d.selectSky(lightmapLook, 0.0);
  d.selectWorldEmission(lightmapLook);
  if (lightmapLook)
    d.renderer->commit();
  else
    d.renderer->prepareLights();
}

std::pair<int, int> ViewRenderer::warmUp(const TracerSettings& settings, int width, int height) {
  Impl& d = *impl_;
  d.dropStartedView();
  if (!d.map.worldScene.has_value() || width <= 0 || height <= 0 || width > 16384 || height > 16384) return {0, 0};
  ViewContext ctx;
  ctx.withWorld = true;
  ctx.lightmapLook = stockLookFor(settings, true);
  // At cg_fov's default over the window's shape (a map without spawn points: from the origin).
  const std::vector<q3::WorldCamera>& spawns = d.map.worldScene->cameras;
  ctx.camera = pa::bridge::cameraFromSpawn(spawns.empty() ? q3::WorldCamera{} : spawns.front(),
                                           float(width) / float(height));
  q3abi::refdef_t view{};
  view.width = width;
  view.height = height;
  // Its seed is not counted: play sees the frames it would have seen without it. One frame is
  // enough: after a second one (with history) the first frames of play were no faster in the game.
  const uint32_t frameCounter = d.frameCounter;
  pa::FrameView frame;
  try {
    frame = d.renderer->render(ctx.camera, d.renderSettings(ctx, view, settings));
  } catch (...) {
    d.frameCounter = frameCounter;
    throw;
  }
  d.frameCounter = frameCounter;
  const std::pair<int, int> size{static_cast<int>(frame.outputWidth), static_cast<int>(frame.outputHeight)};
  d.renderer->forgetFrames();
  return size;
}

void ViewRenderer::loadWorld(const World& world, const ShaderScripts& moduleScripts, ImageCache& images) {
  impl_->dropStartedView();
  impl_->startMap();
  impl_->loadMap(world, moduleScripts, images);
}

std::optional<TracedPicture> ViewRenderer::render(const q3abi::refdef_t& view, const SceneFrame& scene,
                                                  const TracerSettings& settings, ShaderRegistry& shaders,
                                                  const ModelRegistry& models, const World* world) {
  Impl& d = *impl_;
  d.dropStartedView();
  const pa::RenderSettings renderSettings = d.prepareView(view, scene, settings, shaders, models, world);
  d.renderer->commit();
  return d.picture(d.renderer->render(d.started.ctx.camera, renderSettings), d.started);
}

void ViewRenderer::start(const q3abi::refdef_t& view, const SceneFrame& scene, const TracerSettings& settings,
                         ShaderRegistry& shaders, const ModelRegistry& models, const World* world) {
  Impl& d = *impl_;
  d.dropStartedView();
  const pa::RenderSettings renderSettings = d.prepareView(view, scene, settings, shaders, models, world);
  d.renderer->startRender(d.started.ctx.camera, renderSettings);
}

bool ViewRenderer::started() const { return impl_->renderer->rendering(); }

std::optional<TracedPicture> ViewRenderer::finish() {
  Impl& d = *impl_;
  if (!d.renderer->rendering()) return std::nullopt;
  return d.picture(d.renderer->finishRender(), d.started);
}

void ViewRenderer::Impl::dropStartedView() {
  if (!renderer || !renderer->rendering()) return;
  try {
    (void)renderer->finishRender();
  } catch (const std::exception& error) {
    engine.warn(std::string("RenderScene: ") + error.what());
  }
}

pa::RenderSettings ViewRenderer::Impl::prepareView(const q3abi::refdef_t& view, const SceneFrame& scene,
                                                   const TracerSettings& settings, ShaderRegistry& shaders,
                                                   const ModelRegistry& models, const World* world) {
  Impl& d = *this;
  const auto start = Clock::now();
  const ViewContext ctx = d.beginView(view, settings, world);
  // The world's effects use 2D-registered shaders too; HUD model views show models only.
  d.prepareMaterials(shaders, ctx.lightmapLook, ctx.withWorld);
  d.placeModelEntities(ctx, scene, shaders, models);
  d.placeBrushModels(ctx);
  d.deformWorld(ctx);
  d.drawEffects(ctx, scene, shaders);
  d.hideUnclaimedSlots();
  d.placeDynamicLights(ctx, scene.lights());
  const double animationMs = d.showWorldLook(ctx, scene.entities(), view.time);
  d.drawStockDlights(scene.lights(), ctx.withWorld && ctx.lightmapLook);
  d.map.fog.show(ctx.withWorld, *d.renderer);
  d.started.ctx = ctx;
  d.started.sceneMs = millisecondsSince(start);
  d.started.animationMs = animationMs;
  d.started.animationUpdates = double(d.animationUpdates + (ctx.withWorld ? d.map.worldAnimation.lastUpdates() : 0));
  return d.renderSettings(ctx, view, settings);
}

ViewContext ViewRenderer::Impl::beginView(const q3abi::refdef_t& view, const TracerSettings& settings,
                                          const World* world) {
  ViewContext ctx;
  ctx.withWorld = world != nullptr && map.worldScene.has_value();
  pa::Camera& camera = ctx.camera;
  const ViewAxes axes = viewAxesOf(view);
  camera.origin = axes.origin;
  camera.forward = axes.forward;
  camera.left = axes.left;
  camera.up = axes.up;
  camera.fovX = std::clamp(view.fov_x, 1.0f, 179.0f);
  camera.fovY = std::clamp(view.fov_y, 1.0f, 179.0f);
  ctx.viewer = Viewer{camera.origin, camera.left, camera.up};
  ctx.lightmapLook = stockLookFor(settings, ctx.withWorld);
  ctx.seconds = view.time * 0.001;   // the stock shader time of this view
  ++viewCount;
  animationUpdates = 0;
  return ctx;
}

void ViewRenderer::Impl::placeModelEntities(const ViewContext& ctx, const SceneFrame& scene, ShaderRegistry& shaders,
                                            const ModelRegistry& models) {
  std::vector<bool>& brushPlaced = scratch.brushPlaced;
  brushPlaced.assign(map.world.modelInstances.size(), false);
  map.entitySlots.beginFrame();
  reserveSlotMemory();
  GeometryBatch& batch = scratch.batch;
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
      if (!ctx.withWorld || index >= brushPlaced.size()) continue;
      pa::InstanceDesc desc = map.brushInstances[index];
      desc.objectToWorld = entityTransform(e);
      desc.mask = mask;
      setBrushInstance(index, desc);
      brushPlaced[index] = true;
      continue;
    }
    const q3::Md3Model* model3 = md3(*model);
    if (model3 == nullptr) continue;
    md3SurfaceShaders(*model3, e, models.skin(e.customSkin), shaders, scratch.surfaceShaders);
    const std::vector<q3abi::qhandle_t>& surfaceShaders = scratch.surfaceShaders;
    batch.clear();
    std::vector<bool>& autosprite = scratch.surfaceAutosprite;
    autosprite.assign(surfaceShaders.size(), false);
    for (size_t s = 0; s < surfaceShaders.size(); ++s) autosprite[s] = shaders.resolve(surfaceShaders[s]).look.autosprite;
    appendMd3(*model3, e, surfaceShaders, batch, autosprite, spriteAxesFor(e, ctx.viewer));
    if (batch.indices.empty()) continue;
    deformBatch(batch, ctx.seconds, [&](q3abi::qhandle_t h) { return map.modelDeforms.find(shaders.resolve(h).name); });
    if (ctx.lightmapLook) {
      const float* at = (e.renderfx & q3abi::RF_LIGHTING_ORIGIN) ? e.lightingOrigin : e.origin;
      const glm::vec3 lightOrigin(at[0], at[1], at[2]);
      EntityLight light;
      if (!ctx.withWorld || !lightGridAt(map.worldScene->lightGrid, lightOrigin, light, pictureSettings.lightShift()))
        light = noWorldLight();
      light = finishEntityLight(light, lightOrigin, scene.lights());
      lightModelLikeStock(e, entityTransform(e), light, shaders, batch);
      premultiplyBlendedEffects(shaders, batch);   // alpha-blended stages are premultiplied-over layers
    }
    const EntityKey key{e.hModel, e.customSkin, e.customShader, onTop ? 1 : 0};
    const glm::vec3 viewer = viewerInModel(e, ctx.viewer.origin);
    fillSlot(key, glm::vec3(e.origin[0], e.origin[1], e.origin[2]), shaders,
             ctx.lightmapLook ? MaterialUse::StockModel : MaterialUse::Model, entityTransform(e), mask, onTop,
             ctx.seconds - e.shaderTime, {e.shaderTexCoord[0], e.shaderTexCoord[1]}, &viewer);
  }
}

void ViewRenderer::Impl::placeBrushModels(const ViewContext& ctx) {
  const std::vector<bool>& brushPlaced = scratch.brushPlaced;
  for (size_t m = 0; m < brushPlaced.size(); ++m) {
    pa::InstanceDesc desc = map.brushInstances[m];
    if (m == 0) {
      desc.mask = ctx.withWorld ? uint32_t(pa::kMaskAll) : 0u;
      desc.objectToWorld = glm::mat4x3(1.0f);
    } else if (!brushPlaced[m]) {
      desc.mask = 0;   // a mover the game did not add this frame is not drawn
    } else {
      continue;
    }
    setBrushInstance(m, desc);
  }
}

void ViewRenderer::Impl::deformWorld(const ViewContext& ctx) {
  // Where each world model is this view (null: not drawn); one reference captured, so the
  // std::function it becomes holds it without a heap block.
  const struct {
    const Impl& d;
    bool withWorld;
    glm::mat4x3 identity{1.0f};
  } placing{*this, ctx.withWorld};
  const auto placeOf = [&placing](uint32_t model) -> const glm::mat4x3* {
    if (model == 0) return placing.withWorld ? &placing.identity : nullptr;
    const Impl& v = placing.d;
    return model < v.scratch.brushPlaced.size() && v.scratch.brushPlaced[model]
               ? &v.map.brushInstances[model].objectToWorld
               : nullptr;
  };
  map.worldDeforms.update(ctx.seconds, placeOf, *renderer);
}

void ViewRenderer::Impl::drawEffects(const ViewContext& ctx, const SceneFrame& scene, ShaderRegistry& shaders) {
  GeometryBatch& batch = scratch.batch;
  batch.clear();
  for (const q3abi::refEntity_t& e : scene.entities()) {
    if (e.reType == q3abi::RT_MODEL) continue;
    const size_t before = batch.triangles();
    if (!appendEffect(e, ctx.viewer, batch) || e.shaderTime == 0.0f) continue;
    batch.triangleShaderTimes.resize(before, 0.0f);   // an entity's shader clock runs shaderTime behind
    batch.triangleShaderTimes.resize(batch.triangles(), e.shaderTime);
  }
  appendPolys(scene.polys(), scene.polyVerts(), ctx.viewer,
              [&](int32_t shader) { return shaders.resolve(shader).look.polygonOffset; }, batch);
  if (ctx.withWorld) {
    const std::vector<bool>& brushPlaced = scratch.brushPlaced;
    map.worldSprites.append(
        ctx.seconds, ctx.viewer, [&](const std::string& name) { return spriteHandle(shaders, name); },
        [&](uint32_t model) -> const glm::mat4x3* {
          return model < brushPlaced.size() && brushPlaced[model] ? &map.brushInstances[model].objectToWorld : nullptr;
        },
        batch);
  }
  if (batch.indices.empty()) return;
  premultiplyBlendedEffects(shaders, batch);   // alpha-blended effects are premultiplied-over layers in every preset
  fillSlot(EntityKey{0, 0, 0, kEffectsBatchKind}, glm::vec3(0.0f), shaders,
           ctx.lightmapLook ? MaterialUse::StockEffect : MaterialUse::Effect, glm::mat4x3(1.0f), pa::kMaskAll, false,
           ctx.seconds);
}

/// Radius = reach, linear falloff as in Quake; views of the world are lit by the world alone,
/// model-only views by a headlight.
void ViewRenderer::Impl::placeDynamicLights(const ViewContext& ctx, std::span<const DynamicLight> lights) {
  size_t lightIndex = 0;
  for (const DynamicLight& light : lights) {
    pa::LightDesc desc;
    desc.type = pa::LightType::Point;
    desc.position = light.origin;
    desc.color = light.color;
    desc.intensity = kPi;
    desc.falloff = pa::Falloff::Linear;
    desc.range = light.radius;
    setLight(lightIndex++, desc, true);
  }
  if (!ctx.withWorld) {
    pa::LightDesc head;
    head.type = pa::LightType::Directional;
    head.direction = glm::normalize(ctx.camera.forward - ctx.camera.up * 0.5f);
    head.intensity = kPi;
    setLight(lightIndex++, head, true);
  }
  for (size_t i = lightIndex; i < map.lights.size(); ++i) {
    pa::LightDesc off;
    off.intensity = 0.0f;
    setLight(i, off, false);
  }
}

double ViewRenderer::Impl::showWorldLook(const ViewContext& ctx, std::span<const q3abi::refEntity_t> entities,
                                         int timeMs) {
  if (!ctx.withWorld) {
    hideSky();
    return 0.0;
  }
  map.portals.update(entities, timeMs, *renderer);
  selectSky(ctx.lightmapLook, ctx.seconds);
  selectWorldEmission(ctx.lightmapLook);
  const auto animationStart = Clock::now();
  map.worldAnimation.update(ctx.seconds, *renderer);
  return millisecondsSince(animationStart);
}

pa::RenderSettings ViewRenderer::Impl::renderSettings(const ViewContext& ctx, const q3abi::refdef_t& view,
                                                      const TracerSettings& settings) {
  const bool traced = !ctx.lightmapLook && isRealTimeTraced(settings.preset);
  pa::RenderSettings rs;
  const float scale = ctx.withWorld ? settings.resolutionScale : 1.0f;
  rs.width = static_cast<uint32_t>(std::max(8, static_cast<int>(std::lround(view.width * scale))));
  rs.height = static_cast<uint32_t>(std::max(8, static_cast<int>(std::lround(view.height * scale))));
  rs.integrator = ctx.lightmapLook ? pa::Integrator::Lightmap : integratorFor(settings.preset);
  rs.samplesPerPixel = static_cast<uint32_t>(settings.samplesPerPixel);
  rs.stockTextureFilter = settings.textureFilter;   // as stock's texture units (r_textureMode)
  rs.maxBounces = static_cast<uint32_t>(settings.maxBounces);
  rs.bakedLightAtPathEnd = settings.bakedEnd;
  rs.rouletteStart = static_cast<uint32_t>(settings.rouletteStart);
  rs.accumulate = settings.preset == Preset::Reference && !ctx.lightmapLook;
  // In play the world never stands still (items bob, the player's own body breathes, shaders
  // animate): a still view keeps accumulating, restarting only the pixels that show a change.
  rs.accumulateThroughEdits = rs.accumulate && ctx.withWorld;
  rs.radianceClamp = settings.radianceClamp >= 0.0f ? settings.radianceClamp
                     : settings.preset == Preset::Reference ? 0.0f : 10.0f;
  rs.seed = settings.seed + (rs.accumulate ? 0u : frameCounter++);
  rs.denoise = settings.denoise && traced;
  // Views of the world only: HUD model views share one renderer between differing views.
  rs.temporal = settings.temporal && ctx.withWorld && traced;
  rs.restir = settings.restir && ctx.withWorld && traced;
  rs.temporalGradients = settings.gradientStratum != 0;
  if (settings.gradientStratum != 0) rs.gradientStratum = settings.gradientStratum;
  // TAAU to the window's size (world views only; HUD model views are traced at full size). With
  // dynamic resolution it stays on at scale 1 too, so that its history lives through the changes.
  const bool smaller = rs.width != static_cast<uint32_t>(view.width) || rs.height != static_cast<uint32_t>(view.height);
  rs.taau = ctx.withWorld && (settings.taau == 2 || (settings.taau == 1 && (smaller || settings.targetFps > 0.0f)));
  // r_pt_taau_size below 1: TAAU resolves to that part of the window, the presentation stretches it.
  const auto [outputWidth, outputHeight] =
      taauOutputSize(static_cast<uint32_t>(view.width), static_cast<uint32_t>(view.height), rs.width, rs.height,
                     rs.taau ? settings.taauSize : 1.0f);
  rs.outputWidth = outputWidth;
  rs.outputHeight = outputHeight;
  // The stock look samples textures at pixel centres, as opengl1 rasterises. With TAAU every
  // one-sample frame does, moved by TAAU's jitter: the upscaler then knows where each sample lies
  // and the texture detail of the window's size builds up over frames (the first-hit albedo
  // multiplies the filtered light), where a random position in each pixel reached it as a blur.
  rs.pixelCentres = rs.samplesPerPixel == 1 && (ctx.lightmapLook || rs.taau);
  rs.spreadFireflies = settings.fireflies;   // with the denoiser or temporal accumulation only
  rs.motionVectors = false;   // the picture reads none (the renderer works it out for its own stages)
  rs.normalAov = false;       // nor the normals (the denoiser asks for its own)
  rs.surfaceAovs = false;     // nor albedo and normal planes
  // The stock look has no tone curve: colours are clamped, as opengl1's framebuffer does. The
  // traced presets show the light they find as the lightmap shows its texels (r_pt_look stock).
  if (ctx.lightmapLook || settings.stockLook) rs.tonemap = pa::Tonemap::Clamp;
  if (!ctx.lightmapLook && settings.stockLook) rs.lightingLook = pa::LightingLook::DisplaySpace;
  return rs;
}

TracedPicture ViewRenderer::Impl::picture(const pa::FrameView& frame, const StartedView& glue) {
  const ViewContext& ctx = glue.ctx;
  const ViewTimings timings{glue.sceneMs,         frame.timings.commitMs, frame.timings.traceMs,
                            frame.timings.temporalMs, frame.timings.denoiseMs, frame.timings.resolveMs,
                            glue.animationMs,     glue.animationUpdates,  frame.timings.resampleMs,
                            frame.timings.taauMs};
  std::vector<uint8_t>& rgba = scratch.picture;
  rgba.assign(frame.output.begin(), frame.output.end());
  if (!ctx.withWorld && frame.depth.size() * 4 == rgba.size()) {
    for (size_t i = 0; i < frame.depth.size(); ++i)
      if (!std::isfinite(frame.depth[i])) rgba[i * 4 + 3] = 0;   // see-through background
  }
  return TracedPicture{static_cast<int>(frame.outputWidth), static_cast<int>(frame.outputHeight), rgba.data(), timings,
                       frame.accumulatedFrames, static_cast<int>(frame.width), static_cast<int>(frame.height),
                       frame.radiance, frame.variance, frame.depth};
}

}  // namespace glue

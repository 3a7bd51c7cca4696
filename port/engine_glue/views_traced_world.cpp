// ViewRenderer::Impl: a map's scene (startMap, loadMap) and the world's look per preset: stock
// or traced sky, surface lights, autosprite surfaces, the stock dynamic-light pass.
#include <algorithm>
#include <cmath>
#include <string>

#include "port/engine_glue/engine.h"
#include "port/engine_glue/reflection_look.h"
#include "port/engine_glue/stock_look.h"
#include "port/engine_glue/views_traced_impl.h"
#include "port/engine_glue/world.h"
#include "port/light_recovery/recover_lights.h"
#include "port/q3formats/bsp/bsp_file.h"
#include "renderer/scene/lights/stock_dlights.h"

namespace glue {
namespace {

constexpr int kStockSkyFaceSize = 256;   // texels a side of the baked stock sky

}  // namespace

ViewRenderer::Impl::Impl(const Engine& engine, int threads, bool avx2Kernels, bool lampVisibility)
    : engine(engine),
      threads(threads),
      avx2Kernels(avx2Kernels),
      lampVisibility(lampVisibility),
      bakeArena(threads > 0 ? threads : int(tbb::task_arena::automatic)) {}

void ViewRenderer::Impl::startMap() {
  map = MapState{};   // first: it holds ids of the renderer it replaces
  pa::RendererConfig config{.threads = static_cast<uint32_t>(threads)};
  config.bvh.allowAvx512 = !avx2Kernels;
  config.lampVisibility = lampVisibility;
  renderer = std::make_unique<pa::Renderer>(config);
  map.defaultMaterial = renderer->addMaterial(pa::MaterialDesc{});
  map.emptyMesh = renderer->addMesh(pa::MeshDesc{});
}

void ViewRenderer::Impl::loadMap(const World& world, const ShaderScripts& moduleScripts, ImageCache& images) {
  const int start = engine.milliseconds();
  const q3::BspFile& bsp = world.bsp();
  const q3::ShaderLibrary& library = world.shaders();
  const q3::FileLoader loader = [&](std::string_view path) -> std::optional<std::vector<std::byte>> {
    auto bytes = engine.readFile(std::string(path));
    if (!bytes) return std::nullopt;
    const auto* p = reinterpret_cast<const std::byte*>(bytes->data());
    return std::vector<std::byte>(p, p + bytes->size());
  };
  map.worldScene = q3::buildWorldScene(bsp, world.surfaces(), library, loader);
  q3::WorldScene& scene = *map.worldScene;
  const pa::recovery::RecoveredLights recovered = pa::recovery::recoverLights(scene);
  pa::recovery::applyRecoveredLights(scene, recovered);
  for (const std::string& warning : scene.warnings)
    engine.print(q3abi::PRINT_DEVELOPER, "pathtracer: %s\n", warning.c_str());
  stockWorldLook(scene, library, map.glowColors, pictureSettings.lightShift());
  applyPictureToWorld(scene, library, pictureSettings);
  map.worldDeforms.extract(scene, library);   // before the upload: leaves the static mesh
  pa::bridge::UploadOptions upload;
  upload.lightmapShift = pictureSettings.lightShift();
  upload.bakedLightScale = pictureSettings.bakedLightScale();
  map.world = pa::bridge::uploadWorld(scene, *renderer, upload);
  map.bridgeSky = map.world.sky;
  renderer->setSky(map.bridgeSky);
  map.fog.load(std::move(map.world.fog), *renderer);
  map.worldDeforms.bind(scene, map.world);
  map.worldAnimation.prepare(scene, library, map.world, *renderer, [&](const std::string& path, bool clamp) {
    return texture(images.load(engine, path), clamp);
  });
  map.portals.load(bsp, scene);
  prepareStockSky(library, images);
  map.scripts = &moduleScripts;
  map.images = &images;
  prepareWorldSprites(library);
  map.brushInstances.assign(map.world.modelInstances.size(), pa::InstanceDesc{});
  for (size_t m = 0; m < map.world.modelInstances.size(); ++m) {
    map.brushInstances[m].mesh = m < map.world.modelMeshes.size() ? map.world.modelMeshes[m] : pa::kNoId;
    map.brushInstances[m].mask = pa::kMaskAll;
  }
  map.modelDeforms.reset(world.sharedShaders());
  renderer->commit();
  engine.print(q3abi::PRINT_ALL,
               "pathtracer: %s traced scene: %zu materials, %zu textures, %zu lights (%zu recovered in %.0f ms), %llu "
               "triangles + %zu deformed, %zu fog volumes, %zu animated materials (%d ms)\n",
               world.name().c_str(), scene.materials.size(), scene.textures.size(), map.world.lights.size(),
               recovered.lights.size() - recovered.stats.authored, recovered.stats.milliseconds,
               static_cast<unsigned long long>(map.world.triangles), map.worldDeforms.triangles(), map.fog.size(),
               map.worldAnimation.animatedCount(), engine.milliseconds() - start);
}

void ViewRenderer::Impl::prepareWorldSprites(const q3::ShaderLibrary& library) {
  map.spriteMaterials = map.worldSprites.prepare(*map.worldScene, library);
  for (const auto& [key, id] : map.world.materials) {
    if (std::find(map.spriteMaterials.begin(), map.spriteMaterials.end(), key.first) == map.spriteMaterials.end())
      continue;
    pa::MaterialDesc desc = pa::bridge::materialDesc(*map.worldScene, map.world, key.first, key.second);
    desc.visible = false;
    desc.castsShadows = false;
    map.worldAnimation.setMaterial(id, desc, *renderer);
  }
}

q3abi::qhandle_t ViewRenderer::Impl::spriteHandle(ShaderRegistry& shaders, const std::string& name) {
  if (const auto found = map.spriteHandles.find(name); found != map.spriteHandles.end()) return found->second;
  q3abi::qhandle_t handle = shaders.find(name);
  if (handle == 0 && map.scripts != nullptr && map.images != nullptr)
    handle = shaders.registerShader(engine, *map.scripts, *map.images, name, true);
  map.spriteHandles.emplace(name, handle);
  return handle;
}

/// The Lightmap compositor multiplies each lit pixel by them; the traced presets light with point
/// lights instead (placeDynamicLights), so they get none.
void ViewRenderer::Impl::drawStockDlights(std::span<const DynamicLight> lights, bool show) {
  std::vector<pa::StockDynamicLight>& stock = scratch.stockDlights;   // memory kept
  stock.clear();
  if (show && map.worldScene) {
    for (const DynamicLight& light : lights) {
      if (stock.size() == pa::kMaxStockDynamicLights) break;
      if (light.radius > 0.0f && std::isfinite(light.radius))
        stock.push_back({light.origin, light.radius, light.color});
    }
  }
  renderer->setStockDynamicLights(stock);
}

/// The stock renderer shows a q3map_surfacelight surface through its stages only (its light is
/// baked in the lightmaps): in the lightmap preset such surfaces glow only through their
/// additive glow stage, at the texture's own brightness. The traced presets light with the
/// bridge's emitters and show camera rays the glow stage in its colour (seenEmission).
void ViewRenderer::Impl::selectWorldEmission(bool stockLook) {
  if (int(stockLook) == map.stockEmissionShown || !map.worldScene) return;
  for (const auto& [key, id] : map.world.materials) {
    const q3::WorldMaterial& m = map.worldScene->materials.at(key.first);
    if (!(m.surfaceLight > 0.0f) || q3::seeThroughLayer(m.alphaMode)) continue;
    if (std::find(map.spriteMaterials.begin(), map.spriteMaterials.end(), key.first) != map.spriteMaterials.end())
      continue;
    pa::MaterialDesc desc = pa::bridge::materialDesc(*map.worldScene, map.world, key.first, key.second);
    const bool glows = m.emissiveTexture >= 0 && size_t(m.emissiveTexture) < map.world.textures.size();
    const auto colour = map.glowColors.find(key.first);
    const glm::vec3 glowColour = colour != map.glowColors.end() ? colour->second : glm::vec3(1.0f);
    if (stockLook) {
      desc.emissiveTexture = glows ? map.world.textures[size_t(m.emissiveTexture)] : pa::kNoId;
      desc.emission = glows ? glowColour : glm::vec3(0.0f);
    } else if (glows && desc.seenEmission.x >= 0.0f) {
      desc.seenEmission = glowColour;   // the glow stage as the stock renderer draws it
    }
    map.worldAnimation.setMaterial(id, desc, *renderer);
  }
  map.stockEmissionShown = int(stockLook);
}

/// The far box under scrolling cloud layers; the lightmap preset shows it instead of the
/// bridge's sky, and the traced presets a still copy lighting as the bridge's (litStockSky).
void ViewRenderer::Impl::prepareStockSky(const q3::ShaderLibrary& library, ImageCache& images) {
  map.stockSkyReady = false;
  map.tracedSky = map.bridgeSky;
  if (!map.worldScene || map.worldScene->sky.shaderName.empty()) return;
  const q3::ShaderDef* shader = library.find(map.worldScene->sky.shaderName);
  if (shader == nullptr) return;
  const SkyImageLoader load = [&](const std::string& path) { return images.load(engine, path); };
  auto baker = std::make_shared<SkyBaker>();
  if (!baker->prepare(*shader, load, kStockSkyFaceSize)) return;
  SkyCube cube;
  bakeArena.execute([&] { baker->bake(0.0, cube); });
  pa::SkyDesc& stockSky = map.stockSky;
  stockSky = pa::SkyDesc{};
  stockSky.color = glm::vec3(1.0f);
  for (size_t f = 0; f < 6; ++f) {
    pa::TextureDesc desc;
    desc.width = desc.height = static_cast<uint32_t>(cube.size);
    desc.rgba8 = cube.faces[f];
    desc.wrap = pa::TextureWrap::Clamp;
    stockSky.faces[f] = renderer->addTexture(desc);
  }
  map.skyBaker = std::move(baker);
  map.stockSkyPicture = stockSkyPictureAt(map.skyBaker, 0.0);
  stockSky.picture = map.stockSkyPicture;
  map.stockSkySeconds = 0.0;
  map.stockSkyReady = true;
  // Still clouds (shader time 0, a picture of their own that never moves): a sky that changed
  // per frame would restart reference's mean.
  map.tracedSky = litStockSky(stockSky, skyCubeMeanLinear(cube), map.bridgeSky,
                              pa::bridge::skyLightingRadiance(*map.worldScene));
  if (map.tracedSky.picture == stockSky.picture) map.tracedSky.picture = stockSkyPictureAt(map.skyBaker, 0.0);
  if (!map.stockSkyShown && !map.skyHidden) renderer->setSky(map.tracedSky);   // in place of the bridge sky
}

void ViewRenderer::Impl::selectSky(bool stockLook, double seconds) {
  const bool stock = stockLook && map.stockSkyReady;
  const bool moved = stock && map.skyBaker->animated() && seconds != map.stockSkySeconds;
  if (moved) {
    // No render reads the picture now (each view finishes the one in flight before it is prepared).
    map.stockSkyPicture->setTime(seconds);
    map.stockSkySeconds = seconds;
  }
  if (!moved && stock == map.stockSkyShown && !map.skyHidden) return;
  renderer->setSky(stock ? map.stockSky : map.tracedSky);
  map.stockSkyShown = stock;
  map.skyHidden = false;
}

/// Views without the world (menu models, HUD heads) have nothing behind them: a black sky, so
/// that their premultiplied picture adds over the 2D only what the rays met (additive glows).
void ViewRenderer::Impl::hideSky() {
  if (map.skyHidden) return;
  renderer->setSky(pa::SkyDesc{});
  map.skyHidden = true;
}

}  // namespace glue

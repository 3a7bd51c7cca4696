// uploadWorld on synthetic worlds, checked through real renders: the lightmapped look and
// the direct-light look agree where Quake shows a texture unmodified.
#include <cmath>
#include <numbers>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "port/q3formats/world/world_lights.h"
#include "port/scene_bridge/scene_bridge.h"

namespace pa::bridge {
namespace {

/// A 512x512 white wall in the plane x = 0 facing +X, one material, lightmap 0 or vertex-lit.
q3::WorldScene wallScene(uint8_t lightmapValue, bool vertexLit) {
  q3::WorldScene scene;
  scene.textures.push_back({"white", "white.tga", q3::WorldImage{2, 2, std::vector<uint8_t>(16, 255)}, false, false});
  q3::WorldMaterial m;
  m.shaderName = "textures/test/white";
  m.baseTexture = 0;
  m.vertexLit = vertexLit;
  scene.materials.push_back(m);
  scene.lightmaps.push_back(q3::WorldImage{128, 128, std::vector<uint8_t>(128 * 128 * 4, lightmapValue)});
  for (size_t i = 3; i < scene.lightmaps[0].rgba8.size(); i += 4) scene.lightmaps[0].rgba8[i] = 255;
  q3::WorldMesh mesh;
  mesh.material = 0;
  mesh.lightmap = vertexLit ? -1 : 0;
  mesh.positions = {{0, -256, -256}, {0, 256, -256}, {0, 256, 256}, {0, -256, 256}};
  mesh.normals.assign(4, glm::vec3(1, 0, 0));
  mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.lightmapUvs = mesh.uvs;
  float c = lightmapValue / 255.0f;
  mesh.colors.assign(4, glm::vec4(c, c, c, 1.0f));
  mesh.indices = {0, 1, 2, 0, 2, 3};
  scene.models.resize(2);   // model 1 empty: no mesh, no instance
  scene.models[0].meshes.push_back(mesh);
  return scene;
}

/// Mean radiance of a small image of the wall's centre, seen from +X.
float centreRadiance(Renderer& renderer, Integrator integrator, uint32_t spp) {
  q3::WorldCamera spawn;
  spawn.eye = {200, 0, 0};
  spawn.forward = {-1, 0, 0};
  spawn.left = {0, -1, 0};
  spawn.up = {0, 0, 1};
  Camera camera = cameraFromSpawn(spawn, 1.0f, 20.0f);
  RenderSettings settings;
  settings.width = 8;
  settings.height = 8;
  settings.integrator = integrator;
  settings.samplesPerPixel = spp;
  settings.maxBounces = integrator == Integrator::Direct ? 1 : 0;   // Direct needs one scatter for light sampling
  FrameView frame = renderer.render(camera, settings);
  double sum = 0.0;
  for (const glm::vec3& r : frame.radiance) sum += r.g;
  return float(sum / double(frame.radiance.size()));
}

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

TEST(SceneBridge, ColorShiftKeepsHue) {
  std::vector<uint8_t> out = colorShiftLightmap({100, 50, 10, 255, 20, 30, 40, 255}, 2);
  // 400, 200, 40 -> scaled so the peak is 255.
  EXPECT_EQ(out[0], 255);
  EXPECT_EQ(out[1], 127);
  EXPECT_EQ(out[2], 25);
  EXPECT_EQ(out[3], 255);
  EXPECT_EQ(out[4], 80);
  EXPECT_EQ(out[5], 120);
  EXPECT_EQ(out[6], 160);
}

TEST(SceneBridge, UploadsOneMeshAndInstancePerNonEmptyModel) {
  Renderer renderer;
  q3::WorldScene scene = wallScene(64, false);
  WorldHandles handles = uploadWorld(scene, renderer);
  ASSERT_EQ(handles.modelMeshes.size(), 2u);
  EXPECT_NE(handles.modelMeshes[0], kNoId);
  EXPECT_EQ(handles.modelMeshes[1], kNoId);
  EXPECT_EQ(handles.modelInstances[1], kNoId);
  EXPECT_EQ(handles.triangles, 2u);
  EXPECT_EQ(handles.materials.size(), 1u);
  EXPECT_EQ(handles.lightmaps.size(), 1u);
}

TEST(SceneBridge, FullBrightLightmapShowsTheTextureUnmodified) {
  for (uint8_t value : {uint8_t(64), uint8_t(32)}) {
    Renderer renderer;
    showSkyAndFog(uploadWorld(wallScene(value, false), renderer), renderer);
    renderer.commit();
    // Quake: white * min(1, value * 4 / 255); ours decodes the shifted byte as sRGB.
    float expected = srgbToLinear(std::min(255, value * 4) / 255.0f);
    EXPECT_NEAR(centreRadiance(renderer, Integrator::Lightmap, 1), expected, 0.01f) << int(value);
  }
}

TEST(SceneBridge, LightmapImageNamedByAShaderIsDrawnUnbrightened) {
  // Stock draws a shader stage's lightmap image as an ordinary image: white x 64/255.
  q3::WorldScene scene = wallScene(64, false);
  scene.lightmapNamedByShader = {true};
  Renderer renderer;
  showSkyAndFog(uploadWorld(scene, renderer), renderer);
  renderer.commit();
  EXPECT_NEAR(centreRadiance(renderer, Integrator::Lightmap, 1), srgbToLinear(64 / 255.0f), 0.005f);
}

TEST(SceneBridge, BakedLightScaleDoublesTheLitTextureInDisplayValues) {
  // A display with one overbright bit: shift 1 (x2) and texture x light doubled, clamped at
  // white: 32 -> 64 -> 128 displayed; 100 -> 200 -> 400 clamps at 255.
  for (const auto& [value, shown] : {std::pair<uint8_t, int>{32, 128}, std::pair<uint8_t, int>{100, 255}}) {
    UploadOptions options;
    options.lightmapShift = 1;
    options.bakedLightScale = 2.0f;
    Renderer renderer;
    showSkyAndFog(uploadWorld(wallScene(value, false), renderer, options), renderer);
    renderer.commit();
    EXPECT_NEAR(centreRadiance(renderer, Integrator::Lightmap, 1), srgbToLinear(shown / 255.0f), 0.01f) << int(value);
  }
}

TEST(SceneBridge, FogVolumesCarryTheBrushColourAndStockMinimumDepth) {
  q3::WorldScene scene = wallScene(64, false);
  q3::WorldFog fog;
  fog.shaderName = "textures/test/fog";
  fog.planes = {{1, 0, 0, 150}, {-1, 0, 0, -50}, {0, 1, 0, 300}, {0, -1, 0, 300}, {0, 0, 1, 300}, {0, 0, -1, 300}};
  fog.color = {0.5f, 0.25f, 1.0f};
  fog.depthForOpaque = 0.0f;   // stock raises it to 1
  scene.fogs.push_back(fog);
  q3::WorldFog noBrush;
  scene.fogs.push_back(noBrush);   // no planes: left out
  const FogVolumes volumes = fogVolumes(scene, 2.0f);
  ASSERT_EQ(volumes.volumes.size(), 1u);
  EXPECT_EQ(volumes.volumes[0].planes.size(), 6u);
  EXPECT_FLOAT_EQ(volumes.volumes[0].depthForOpaque, 1.0f);
  EXPECT_NEAR(volumes.volumes[0].color.r, 2.0f * srgbToLinear(0.5f), 1e-6f);
  EXPECT_NEAR(volumes.volumes[0].color.b, 2.0f, 1e-6f);
}

TEST(SceneBridge, FogBetweenCameraAndWallBlendsTheLightmappedLook) {
  // The wall (x = 0) seen from x = 200 through fog filling x in [0, 100]: 100 units deep.
  q3::WorldScene scene = wallScene(64, false);
  q3::WorldFog fog;
  fog.planes = {{1, 0, 0, 100}, {-1, 0, 0, 0}, {0, 1, 0, 300}, {0, -1, 0, 300}, {0, 0, 1, 300}, {0, 0, -1, 300}};
  fog.color = {0.0f, 0.0f, 0.0f};
  fog.depthForOpaque = 400.0f;
  scene.fogs.push_back(fog);
  Renderer renderer;
  const WorldHandles handles = uploadWorld(scene, renderer);
  showSkyAndFog(handles, renderer);
  EXPECT_EQ(handles.fog.volumes.size(), 1u);
  renderer.commit();
  const float opacity = std::sqrt(100.0f / 400.0f - 1.0f / 64.0f);
  // Display-space blend toward black: the encoded white drops to 1 - opacity.
  EXPECT_NEAR(centreRadiance(renderer, Integrator::Lightmap, 1), srgbToLinear(1.0f - opacity), 0.01f);
}

TEST(SceneBridge, UploadReturnsTheSkyWithoutSettingIt) {
  // The worldspawn ambient lights the wall through the sky (SkyDesc::ambientRadiance): dark
  // until the caller sets the sky uploadWorld returned.
  q3::WorldScene scene = wallScene(64, false);
  scene.ambientLight = glm::vec3(64.0f);
  Renderer renderer;
  const WorldHandles handles = uploadWorld(scene, renderer);
  renderer.commit();
  EXPECT_EQ(centreRadiance(renderer, Integrator::Direct, 4), 0.0f);
  EXPECT_EQ(handles.sky.ambientRadiance, skyDesc(scene, handles).ambientRadiance);
  showSkyAndFog(handles, renderer);
  renderer.commit();
  EXPECT_NEAR(centreRadiance(renderer, Integrator::Direct, 4), 1.0f, 1e-5f);
}

TEST(SceneBridge, EnvironmentBaseReadsTheReflectionSphere) {
  q3::WorldScene scene = wallScene(64, false);
  WorldHandles handles;
  EXPECT_EQ(materialDesc(scene, handles, 0, 0).baseTexCoords, TexCoordSource::Mesh);
  scene.materials[0].baseReflects = true;
  scene.materials[0].uvScale = {0.5f, 0.5f};
  const MaterialDesc desc = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(desc.baseTexCoords, TexCoordSource::ReflectionSphere);
  EXPECT_FLOAT_EQ(desc.uvTransform[0][0], 0.5f);   // tcMod scale applies after the lookup
  // The surface's own texture added over the reflection and lit with it: that texture is the base.
  scene.textures.push_back(scene.textures[0]);
  scene.materials[0].reflectionOverlayTexture = 1;
  handles.textures = {3, 8};
  const MaterialDesc overlaid = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(overlaid.baseTexCoords, TexCoordSource::Mesh);
  EXPECT_EQ(overlaid.baseTexture, 8u);
  EXPECT_EQ(overlaid.uvTransform, glm::mat3x2(1.0f));   // the chrome's tcMod scale is not the texture's
}

TEST(SceneBridge, CoverStageKeepsItsTextureUvsAndAlphaSource) {
  q3::WorldScene scene = wallScene(64, false);
  scene.textures.push_back(scene.textures[0]);
  WorldHandles handles;
  handles.textures = {3, 8};
  EXPECT_EQ(materialDesc(scene, handles, 0, 0).coverTexture, kNoId);
  q3::WorldMaterial& m = scene.materials[0];
  m.coverTexture = 1;
  q3::TcMod scale;
  scale.kind = q3::TcModKind::Scale;
  scale.scroll = {2.0f, 4.0f};
  m.coverTcMods = {scale};
  m.coverVertexAlpha = true;
  m.coverAlphaCutoff = 0.5f;
  const MaterialDesc desc = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(desc.coverTexture, 8u);
  EXPECT_EQ(desc.coverUvTransform * glm::vec3(0.5f, 0.25f, 1.0f), glm::vec2(1.0f, 1.0f));   // tcMod scale 2 4
  EXPECT_TRUE(desc.coverVertexAlpha);
  EXPECT_FLOAT_EQ(desc.coverAlphaCutoff, 0.5f);
  EXPECT_EQ(desc.uvTransform, glm::mat3x2(1.0f));   // the base's own uvs untouched
}

TEST(SceneBridge, DoublingLightmapStageDoublesTheBakedLight) {
  q3::WorldScene scene = wallScene(64, false);
  WorldHandles handles;
  handles.lightmaps = {5};
  handles.bakedLightScale = 1.5f;
  scene.materials[0].lightmapScale = 2.0f;
  EXPECT_FLOAT_EQ(materialDesc(scene, handles, 0, 0).stock.bakedLightScale, 3.0f);
  // The stage's own part, for Direct and Path (a brighter base colour).
  EXPECT_FLOAT_EQ(materialDesc(scene, handles, 0, 0).stock.lightmapStageScale, 2.0f);
  // Vertex-lit (no lightmap page): the vertex colours as they are.
  EXPECT_FLOAT_EQ(materialDesc(scene, handles, 0, -1).stock.bakedLightScale, 1.0f);
  EXPECT_FLOAT_EQ(materialDesc(scene, handles, 0, -1).stock.lightmapStageScale, 1.0f);
}

TEST(SceneBridge, PlainAdditiveSurfaceLightsShowTheirGlowStage) {
  q3::WorldScene scene = wallScene(64, false);
  scene.textures.push_back(scene.textures[0]);
  WorldHandles handles;
  handles.textures = {3, 8};
  q3::WorldMaterial& m = scene.materials[0];
  m.alphaMode = q3::WorldAlphaMode::Additive;
  m.surfaceLight = 455.0f;
  m.emissiveTexture = 1;
  // blendFunc add (teleporter rings): the glow stage at its own brightness; never a light.
  MaterialDesc desc = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(desc.emissiveTexture, 8u);
  EXPECT_EQ(desc.emission, glm::vec3(1.0f));
  // GL_SRC_ALPHA GL_ONE (flames) and GL_DST_COLOR GL_ONE (water): the base alone.
  for (const q3::BlendFactor source : {q3::BlendFactor::SrcAlpha, q3::BlendFactor::DstColor}) {
    m.additiveSource = source;
    desc = materialDesc(scene, handles, 0, 0);
    EXPECT_EQ(desc.emissiveTexture, kNoId);
    EXPECT_EQ(desc.emission, glm::vec3(0.0f));
  }
}

TEST(SceneBridge, FiltersMultiplyWhatIsBehind) {
  q3::WorldScene scene = wallScene(64, false);
  WorldHandles handles;
  q3::WorldMaterial& m = scene.materials[0];
  m.alphaMode = q3::WorldAlphaMode::Filter;   // tinted glass, energy fields: a see-through layer
  MaterialDesc desc = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(desc.alphaMode, AlphaMode::Additive);
  EXPECT_EQ(desc.stock.layerBlend, LayerBlend::Multiply);
  m.filterBlend = q3::FilterBlend::Modulate2x;
  EXPECT_EQ(materialDesc(scene, handles, 0, 0).stock.layerBlend, LayerBlend::Modulate2x);
  m.filterBlend = q3::FilterBlend::MultiplyInverse;
  EXPECT_EQ(materialDesc(scene, handles, 0, 0).stock.layerBlend, LayerBlend::MultiplyInverse);
  // A filter that is a surface light (ctf_gate1's energy fields) glows through its invisible twin,
  // not through the layer.
  m.surfaceLight = 150.0f;
  desc = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(desc.emission, glm::vec3(0.0f));
  EXPECT_TRUE(surfaceLightProxy(scene, handles, 0, 1.0f).has_value());
}

TEST(SceneBridge, AdditiveStagesBlendByTheirSourceFactor) {
  q3::WorldScene scene = wallScene(64, false);
  WorldHandles handles;
  q3::WorldMaterial& m = scene.materials[0];
  m.alphaMode = q3::WorldAlphaMode::Additive;
  // gl_one gl_one: the texture added.
  MaterialDesc desc = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(desc.alphaMode, AlphaMode::Additive);
  EXPECT_EQ(desc.stock.layerBlend, LayerBlend::Add);
  EXPECT_FALSE(desc.layerAlphaTest);
  // gl_src_alpha gl_one (flames): the texture x its alpha.
  m.additiveSource = q3::BlendFactor::SrcAlpha;
  desc = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(desc.stock.layerBlend, LayerBlend::Factors);
  EXPECT_EQ(desc.stock.layerSrcFactor, BlendFactor::SrcAlpha);
  EXPECT_EQ(desc.stock.layerDstFactor, BlendFactor::One);
  // gl_dst_color gl_one with alphaFunc GE128 (team decals): dst x (1 + src) where the test passes.
  m.additiveSource = q3::BlendFactor::DstColor;
  m.additiveAlphaTest = true;
  m.alphaCutoff = 0.5f;
  desc = materialDesc(scene, handles, 0, 0);
  EXPECT_EQ(desc.stock.layerBlend, LayerBlend::MultiplyAdd);
  EXPECT_TRUE(desc.layerAlphaTest);
  EXPECT_FLOAT_EQ(desc.alphaCutoff, 0.5f);
  EXPECT_FALSE(desc.alphaInvert);
}

TEST(SceneBridge, MapDecalsInTheWallsPlaneShowOnEveryPixel) {
  // A red additive decal (polygonOffset) with the wall's very corners: stock draws it over the
  // wall with its depth offset; here it moves off the wall along its normal, so every camera
  // ray meets it in front (without that, rounding decides, or a tie hides it).
  q3::WorldScene scene = wallScene(16, false);   // a dark grey wall
  q3::WorldMaterial decal = scene.materials[0];
  decal.shaderName = "textures/test/decal";
  decal.alphaMode = q3::WorldAlphaMode::Additive;
  decal.baseColor = glm::vec4(0.5f, 0.0f, 0.0f, 1.0f);
  decal.decal = true;
  scene.materials.push_back(decal);
  q3::WorldMesh mesh = scene.models[0].meshes[0];
  mesh.material = 1;
  scene.models[0].meshes.push_back(mesh);
  Renderer renderer;
  showSkyAndFog(uploadWorld(scene, renderer), renderer);
  renderer.commit();
  q3::WorldCamera spawn;   // a slanted view of the wall
  spawn.eye = {300, 120, 40};
  spawn.forward = glm::normalize(glm::vec3(-1.0f, -0.3f, -0.1f));
  spawn.left = glm::normalize(glm::cross(glm::vec3(0, 0, 1), spawn.forward));
  spawn.up = glm::cross(spawn.forward, spawn.left);
  RenderSettings settings;
  settings.width = 32;
  settings.height = 32;
  settings.integrator = Integrator::Lightmap;
  settings.maxBounces = 0;
  const FrameView frame = renderer.render(cameraFromSpawn(spawn, 1.0f, 40.0f), settings);
  size_t withoutDecal = 0;
  for (const glm::vec3& r : frame.radiance) withoutDecal += r.r < r.g + 0.1f ? 1 : 0;
  EXPECT_EQ(withoutDecal, 0u) << "of " << frame.radiance.size() << " pixels";
}

TEST(SceneBridge, VertexLitSurfacesUseVertexColoursAsBakedLight) {
  Renderer renderer;
  showSkyAndFog(uploadWorld(wallScene(128, true), renderer), renderer);
  renderer.commit();
  EXPECT_NEAR(centreRadiance(renderer, Integrator::Lightmap, 1), srgbToLinear(128 / 255.0f), 0.01f);
}

TEST(SceneBridge, VertexLightIsInterpolatedInDisplayValues) {
  // Vertex light 0 along the bottom edge, 255 along the top: halfway up, a raster renderer's
  // Gouraud shading shows byte 128 (linear 0.214), not linear 0.5.
  q3::WorldScene scene = wallScene(0, true);
  auto& colors = scene.models[0].meshes[0].colors;
  colors = {glm::vec4(0, 0, 0, 1), glm::vec4(0, 0, 0, 1), glm::vec4(1, 1, 1, 1), glm::vec4(1, 1, 1, 1)};
  Renderer renderer;
  showSkyAndFog(uploadWorld(scene, renderer), renderer);
  renderer.commit();
  EXPECT_NEAR(centreRadiance(renderer, Integrator::Lightmap, 1), srgbToLinear(0.5f), 0.01f);
}

/// A q3map2 light of value 300 on the wall's axis at the distance where it lights a facing
/// texel full bright (300 * pointScale / d^2 = 64, "texture unmodified").
q3::WorldLight fullBrightPointLight() {
  q3::WorldLight light;
  light.position = {std::sqrt(300.0f * q3::kQ3mapPointScale / q3::kQ3FullBright), 0, 0};
  light.intensity = q3::pointLightIntensity(300.0f);
  return light;
}

TEST(SceneBridge, PointLightAtFullBrightDistanceGivesRadianceOne) {
  // q3map2: a 300 light at distance d lights a facing texel with 300 * 7500 / d^2; at 64 the
  // lightmapped look is "texture unmodified", so the direct look must give radiance 1 there.
  q3::WorldScene scene = wallScene(64, false);
  scene.lights.push_back(fullBrightPointLight());
  Renderer renderer;
  uploadWorld(scene, renderer);   // the sky stays unset
  renderer.commit();
  // The 20-degree view covers +-35 units of the wall: cos and distance vary by < 3 %.
  EXPECT_NEAR(centreRadiance(renderer, Integrator::Direct, 4), 1.0f, 0.05f);
}

TEST(SceneBridge, WorldspawnAmbientAndMinlightLightTheWallAsTheyLitItsTexels) {
  // `_ambient 64` or `_minlight 64` with no light: every texel at 64 ("texture unmodified"),
  // so Direct shows the white wall at radiance 1, Lightmap the texture unmodified too.
  for (bool floor : {false, true}) {
    q3::WorldScene scene = wallScene(64, false);
    (floor ? scene.minimumLight : scene.ambientLight) = glm::vec3(64.0f);
    Renderer renderer;
    showSkyAndFog(uploadWorld(scene, renderer), renderer);
    renderer.commit();
    EXPECT_NEAR(centreRadiance(renderer, Integrator::Direct, 4), 1.0f, 1e-5f) << floor;
    EXPECT_NEAR(centreRadiance(renderer, Integrator::Lightmap, 1), 1.0f, 0.01f) << floor;
  }
  // A floor under a full-bright point light changes nothing; an ambient adds to it.
  q3::WorldScene scene = wallScene(64, false);
  scene.lights.push_back(fullBrightPointLight());
  scene.minimumLight = glm::vec3(32.0f);
  Renderer floored;
  showSkyAndFog(uploadWorld(scene, floored), floored);
  floored.commit();
  EXPECT_NEAR(centreRadiance(floored, Integrator::Direct, 4), 1.0f, 0.05f);
  scene.ambientLight = glm::vec3(32.0f);
  Renderer ambient;
  showSkyAndFog(uploadWorld(scene, ambient), ambient);
  ambient.commit();
  EXPECT_NEAR(centreRadiance(ambient, Integrator::Direct, 4) - centreRadiance(floored, Integrator::Direct, 4), 0.5f,
              1e-4f);
}

TEST(SceneBridge, SurfaceLightEmitsItsQ3map2Radiance) {
  q3::WorldScene scene = wallScene(64, false);
  scene.materials[0].surfaceLight = 1000.0f;
  scene.materials[0].emission = glm::vec3(1.0f);
  Renderer renderer;
  const WorldHandles handles = uploadWorld(scene, renderer);   // the sky stays unset
  renderer.commit();
  // It lights with 1000 * 3 * 0.25 / 64 for a white texture (emission x the texture's mean)...
  const MaterialDesc desc = materialDesc(scene, handles, 0, -1);
  EXPECT_NEAR(desc.emission.g, q3::surfaceLightRadiance(1000.0f), 0.05f);
  // ... and camera rays see the texture at its own brightness, as the stock renderer draws it
  // (no bounces: emission only).
  EXPECT_EQ(desc.seenEmission, glm::vec3(1.0f));
  EXPECT_NEAR(centreRadiance(renderer, Integrator::Direct, 1), 1.0f, 1e-3f);
}

TEST(SceneBridge, ColouredSurfaceLightEmitsTheCompilersColourOnce) {
  // q3map2 lights with the light image's mean colour (normalised: czest1dm's lanterns
  // 1, 0.67, 0.18), uniform over the surface; the renderer shows the emission through the
  // texture. The texture's mean must not tint that colour again: emission x the texture's mean
  // linear colour is the compiler's colour x its radiance in every channel (was 1.97, 0.54,
  // 0.01 x the radiance for this orange texture: a red pool where the bake shows an orange glow).
  q3::WorldScene scene = wallScene(64, false);
  std::vector<uint8_t> orange(16, 255);
  for (size_t i = 0; i < orange.size(); i += 4) orange[i + 1] = 170, orange[i + 2] = 45;
  scene.textures[0].image.rgba8 = orange;
  scene.materials[0].surfaceLight = 1000.0f;
  scene.materials[0].emission = glm::vec3(1.0f, 170.0f / 255.0f, 45.0f / 255.0f);
  Renderer renderer;
  const WorldHandles handles = uploadWorld(scene, renderer);
  const MaterialDesc desc = materialDesc(scene, handles, 0, -1);
  const glm::vec3 mean(srgbToLinear(1.0f), srgbToLinear(170.0f / 255.0f), srgbToLinear(45.0f / 255.0f));
  const glm::vec3 expected = scene.materials[0].emission * q3::surfaceLightRadiance(1000.0f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(desc.emission[c] * mean[c], expected[c], 1e-3f * expected[c]) << c;
  EXPECT_EQ(desc.seenEmission, glm::vec3(1.0f));   // camera rays still see the texture as drawn
}

TEST(SceneBridge, CameraFromSpawnKeepsAxesAndDerivesVerticalFov) {
  q3::WorldCamera spawn;
  spawn.eye = {1, 2, 3};
  Camera camera = cameraFromSpawn(spawn, 16.0f / 9.0f, 90.0f);
  EXPECT_EQ(camera.origin, glm::vec3(1, 2, 3));
  EXPECT_FLOAT_EQ(camera.fovX, 90.0f);
  EXPECT_NEAR(camera.fovY, 58.7155f, 1e-3f);   // 2 atan(tan 45 / (16/9))
}

}  // namespace
}  // namespace pa::bridge

namespace pa::bridge {
namespace {

TEST(SceneBridge, AdditiveSurfaceLightLightsTheMapWithoutGlaringItself) {
  // q3map2 lights maps from additive surface-light shaders too (flames, sfx/flame2 in oa_dm1,
  // q3map_surfacelight 30000 in oa_ctf2); the renderer samples no additive surface as a light.
  q3::WorldScene scene = wallScene(64, false);
  q3::WorldMaterial flame;
  flame.shaderName = "textures/sfx/flame";
  flame.baseTexture = 0;
  flame.alphaMode = q3::WorldAlphaMode::Additive;
  flame.surfaceLight = 1000.0f;
  flame.emission = glm::vec3(1.0f);
  flame.castsShadows = false;
  scene.materials.push_back(flame);
  // A 20x20 quad out of the camera's view, 50 units in front of the wall, 70 to the side.
  q3::WorldMesh quad;
  quad.material = 1;
  quad.positions = {{50, 60, -10}, {50, 80, -10}, {50, 80, 10}, {50, 60, 10}};
  quad.normals.assign(4, glm::vec3(-1, 0, 0));
  quad.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  quad.lightmapUvs = quad.uvs;
  quad.colors.assign(4, glm::vec4(1.0f));
  quad.indices = {0, 2, 1, 0, 3, 2};
  scene.models[0].meshes.push_back(quad);

  Renderer renderer;
  WorldHandles handles = uploadWorld(scene, renderer);   // the sky stays unset
  renderer.commit();
  EXPECT_EQ(handles.lightProxies.size(), 1u);
  EXPECT_EQ(handles.triangles, 4u);
  // Drawn as an additive texture, not at q3map2's radiance (11.7 for 1000).
  EXPECT_EQ(materialDesc(scene, handles, 1, -1).emission, glm::vec3(0.0f));
  // Small-source estimate E = L * A * cos_r * cos_e / d^2 (white wall radiance E / pi),
  // averaged over the wall points seen by centreRadiance's 8x8 pixel centres.
  const float halfWidth = 200.0f * std::tan(glm::radians(10.0f));
  float expected = 0.0f;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const glm::vec3 wall(0.0f, halfWidth * ((i + 0.5f) / 4.0f - 1.0f), halfWidth * ((j + 0.5f) / 4.0f - 1.0f));
      const glm::vec3 toLight = glm::vec3(50.0f, 70.0f, 0.0f) - wall;
      const float d2 = glm::dot(toLight, toLight), cosine = toLight.x / std::sqrt(d2);
      expected += q3::surfaceLightRadiance(1000.0f) * 400.0f * cosine * cosine / d2 / std::numbers::pi_v<float> / 64.0f;
    }
  EXPECT_NEAR(centreRadiance(renderer, Integrator::Direct, 64), expected, 0.1f * expected);
}

}  // namespace
}  // namespace pa::bridge

namespace pa::bridge {
namespace {

/// A sky box of six uniform faces of sRGB grey `value`, handles 0..5.
std::pair<q3::WorldScene, WorldHandles> skyBoxScene(uint8_t value) {
  q3::WorldScene scene;
  WorldHandles handles;
  std::vector<uint8_t> rgba(16, value);
  for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
  for (uint32_t f = 0; f < 6; ++f) {
    scene.textures.push_back({"sky", "sky.tga", q3::WorldImage{2, 2, rgba}, true, false});
    scene.sky.faces[f] = int32_t(f);
    handles.textures.push_back(f);
  }
  return {std::move(scene), std::move(handles)};
}

TEST(SceneBridgeSky, SkyLightOfQ3map2IsItsDomeOfSunsOnAnUpwardSurface) {
  // 2 iterations: 4 suns at 22.5 degrees and one at the zenith share the value.
  EXPECT_NEAR(q3::skyLightRadiance(64.0f, 2), (1.0 + 4.0 * std::sin(std::numbers::pi / 8.0)) / 5.0, 1e-6);
  EXPECT_EQ(q3::skyLightRadiance(64.0f, 1), 0.0f);   // q3map2 needs 2 iterations
  EXPECT_EQ(q3::skyLightRadiance(-5.0f, 4), 0.0f);
  // Many iterations approach a uniform dome: mean sin(elevation) over elevation = 2 / pi.
  EXPECT_NEAR(q3::skyLightRadiance(64.0f, 200), 2.0 / std::numbers::pi, 0.01);
}

TEST(SceneBridgeSky, DarkBoxLightsWithTheCompiledRadianceAndLooksAsDrawn) {
  auto [scene, handles] = skyBoxScene(32);
  scene.sky.surfaceLight = 100.0f;
  scene.sky.skyLight = 50.0f;
  scene.sky.skyLightIterations = 3;
  const SkyDesc sky = skyDesc(scene, handles);
  EXPECT_EQ(sky.color, glm::vec3(1.0f));
  for (uint32_t f = 0; f < 6; ++f) EXPECT_EQ(sky.faces[f], f);
  const float shown = srgbToLinear(32.0f / 255.0f);
  const float compiled = q3::skyLightRadiance(50.0f, 3);   // a box's surface light is not used
  EXPECT_NEAR(sky.lightingScale * shown, compiled, 1e-4f * compiled);
  EXPECT_GT(sky.lightingScale, 10.0f);   // this box is far darker than its light

  UploadOptions brighter;
  brighter.lightScale = 2.0f;
  EXPECT_NEAR(skyDesc(scene, handles, brighter).lightingScale, 2.0f * sky.lightingScale, 1e-3f * sky.lightingScale);
}

TEST(SceneBridgeSky, SunOnlySkyLightsNothingAndUnlitSkyKeepsItsLook) {
  auto [scene, handles] = skyBoxScene(200);
  scene.sky.sunLit = true;
  EXPECT_EQ(skyDesc(scene, handles).lightingScale, 0.0f);
  scene.sky.surfaceLight = 100.0f;   // sun and surface light (oa_dm6): the box lights as drawn
  EXPECT_EQ(skyDesc(scene, handles).lightingScale, 1.0f);
  scene.sky.sunLit = false;
  scene.sky.surfaceLight = 0.0f;
  EXPECT_EQ(skyDesc(scene, handles).lightingScale, 1.0f);

  // No box: the constant colour carries the compiled radiance (seen and lighting alike).
  q3::WorldScene flat;
  flat.sky.color = glm::vec3(0.2f, 0.4f, 0.8f);
  flat.sky.skyLight = 64.0f;
  flat.sky.skyLightIterations = 2;
  const SkyDesc constant = skyDesc(flat, WorldHandles{});
  EXPECT_NEAR(constant.color.b, q3::skyLightRadiance(64.0f, 2), 1e-6f);
  EXPECT_NEAR(constant.color.r, 0.25f * q3::skyLightRadiance(64.0f, 2), 1e-6f);
  EXPECT_EQ(constant.lightingScale, 1.0f);
  flat.sky.skyLight = 0.0f;
  flat.sky.sunLit = true;
  EXPECT_EQ(skyDesc(flat, WorldHandles{}).lightingScale, 0.0f);
}

TEST(SceneBridgeSky, CarriesTheWorldspawnAmbientAsRadiancePerAlbedo) {
  auto [scene, handles] = skyBoxScene(100);
  scene.ambientLight = {46.0f, 28.0f, 28.0f};
  scene.minimumLight = glm::vec3(32.0f);
  UploadOptions options;
  options.lightScale = 2.0f;
  options.skyIntensity = 5.0f;   // the sky's brightness, not the ambient's
  for (const SkyDesc& sky : {skyDesc(scene, handles, options), skyDesc(q3::WorldScene(scene), WorldHandles{}, options)}) {
    EXPECT_NEAR(sky.ambientRadiance.r, 2.0f * 46.0f / 64.0f, 1e-6f);
    EXPECT_NEAR(sky.ambientRadiance.g, 2.0f * 28.0f / 64.0f, 1e-6f);
    EXPECT_EQ(sky.minimumRadiance, glm::vec3(1.0f));
  }
}

}  // namespace
}  // namespace pa::bridge

// Known-answer tests of the glTF writer on synthetic WorldScenes.
#include <cstring>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "assets_converter/glb_builder.h"
#include "assets_converter/gltf_export.h"
#include "port/q3formats/world/world_lights.h"

namespace {

using nlohmann::json;

uint32_t u32At(const std::vector<std::byte>& b, size_t offset) {
  uint32_t v;
  std::memcpy(&v, b.data() + offset, 4);
  return v;
}

/// Parses the GLB container by hand; returns the JSON chunk and the BIN chunk.
std::pair<json, std::vector<std::byte>> splitGlb(const std::vector<std::byte>& glb) {
  EXPECT_GE(glb.size(), 20u);
  EXPECT_EQ(u32At(glb, 0), 0x46546C67u);
  EXPECT_EQ(u32At(glb, 4), 2u);
  EXPECT_EQ(u32At(glb, 8), glb.size());
  uint32_t jsonLength = u32At(glb, 12);
  EXPECT_EQ(u32At(glb, 16), 0x4E4F534Au);
  EXPECT_EQ(jsonLength % 4, 0u);
  std::string text(reinterpret_cast<const char*>(glb.data() + 20), jsonLength);
  std::vector<std::byte> bin;
  size_t binHeader = 20 + jsonLength;
  if (binHeader < glb.size()) {
    uint32_t binLength = u32At(glb, binHeader);
    EXPECT_EQ(u32At(glb, binHeader + 4), 0x004E4942u);
    EXPECT_EQ(binLength % 4, 0u);
    bin.assign(glb.begin() + binHeader + 8, glb.begin() + binHeader + 8 + binLength);
  }
  return {json::parse(text), bin};
}

q3::WorldImage solidImage(uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
  q3::WorldImage image{w, h, std::vector<uint8_t>(size_t(w) * h * 4)};
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    image.rgba8[i * 4 + 0] = r;
    image.rgba8[i * 4 + 1] = g;
    image.rgba8[i * 4 + 2] = b;
    image.rgba8[i * 4 + 3] = a;
  }
  return image;
}

/// One triangle on the three Quake axes, 32 units out, with material `material`.
q3::WorldMesh axisTriangle(uint32_t material) {
  q3::WorldMesh mesh;
  mesh.material = material;
  mesh.positions = {{32, 0, 0}, {0, 32, 0}, {0, 0, 32}};
  mesh.normals = {glm::normalize(glm::vec3(1, 1, 1)), glm::normalize(glm::vec3(1, 1, 1)), glm::normalize(glm::vec3(1, 1, 1))};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {0, 1, 2};
  for (auto& p : mesh.positions) mesh.bounds.extend(p);
  return mesh;
}

q3::WorldScene sceneWithMaterials(std::vector<q3::WorldMaterial> materials) {
  q3::WorldScene scene;
  scene.mapName = "maps/test.bsp";
  scene.textures.push_back({"textures/test/a", "textures/test/a.tga", solidImage(2, 2, 200, 100, 50, 40), false, false});
  scene.models.emplace_back();
  for (uint32_t i = 0; i < materials.size(); ++i) scene.models[0].meshes.push_back(axisTriangle(i));
  scene.materials = std::move(materials);
  return scene;
}

q3::WorldMaterial texturedMaterial(const char* name) {
  q3::WorldMaterial m;
  m.shaderName = name;
  m.baseTexture = 0;
  return m;
}

TEST(GlbBuilder, ContainerIsAlignedAndReadableByTinyGltf) {
  q3::WorldScene scene = sceneWithMaterials({texturedMaterial("textures/test/a")});
  std::vector<std::byte> glb = pa::converter::exportGlb(scene);
  auto [doc, bin] = splitGlb(glb);
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_EQ(doc["buffers"][0]["byteLength"].get<size_t>(), bin.size());
  for (const auto& view : doc["bufferViews"]) EXPECT_EQ(view["byteOffset"].get<size_t>() % 4, 0u);

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                          static_cast<unsigned>(glb.size())))
      << err;
  ASSERT_EQ(model.images.size(), 1u);
  EXPECT_EQ(model.images[0].width, 2);
  EXPECT_EQ(model.images[0].image[3], 40);   // PNG round trip keeps alpha
}

TEST(GltfExport, ConvertsZUpInchesToYUpMetres) {
  q3::WorldScene scene = sceneWithMaterials({texturedMaterial("a")});
  pa::converter::ExportOptions options;
  options.metresPerUnit = 1.0f / 32.0f;
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(scene, options));
  const json& prim = doc["meshes"][0]["primitives"][0];
  const json& accessor = doc["accessors"][prim["attributes"]["POSITION"].get<int>()];
  // (32,0,0) -> (1,0,0); (0,32,0) -> (0,0,-1); (0,0,32) -> (0,1,0)
  EXPECT_EQ(accessor["min"], json::array({0.0, 0.0, -1.0}));
  EXPECT_EQ(accessor["max"], json::array({1.0, 1.0, 0.0}));
  const json& view = doc["bufferViews"][accessor["bufferView"].get<int>()];
  glm::vec3 p[3];
  std::memcpy(p, bin.data() + view["byteOffset"].get<size_t>(), sizeof(p));
  EXPECT_EQ(p[0], glm::vec3(1, 0, 0));
  EXPECT_EQ(p[1], glm::vec3(0, 0, -1));
  EXPECT_EQ(p[2], glm::vec3(0, 1, 0));
  // The normal turns with the axes and stays unit length.
  const json& normals = doc["accessors"][prim["attributes"]["NORMAL"].get<int>()];
  glm::vec3 n;
  std::memcpy(&n, bin.data() + doc["bufferViews"][normals["bufferView"].get<int>()]["byteOffset"].get<size_t>(), sizeof(n));
  EXPECT_NEAR(n.x, 1 / std::sqrt(3.0f), 1e-6f);
  EXPECT_NEAR(n.y, 1 / std::sqrt(3.0f), 1e-6f);
  EXPECT_NEAR(n.z, -1 / std::sqrt(3.0f), 1e-6f);
  EXPECT_EQ(doc["accessors"][prim["indices"].get<int>()]["componentType"], 5123);   // 3 vertices: uint16
}

TEST(GltfExport, LargeMeshesUse32BitIndices) {
  q3::WorldScene scene = sceneWithMaterials({texturedMaterial("a")});
  q3::WorldMesh& mesh = scene.models[0].meshes[0];
  mesh.positions.assign(70000, glm::vec3(0));
  mesh.normals.assign(70000, glm::vec3(0, 0, 1));
  mesh.uvs.assign(70000, glm::vec2(0));
  for (uint32_t i = 0; i < 70000; ++i) mesh.positions[i] = glm::vec3(float(i), float(i % 7), 0);
  mesh.indices = {0, 1, 69999};
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(scene));
  EXPECT_EQ(doc["accessors"][doc["meshes"][0]["primitives"][0]["indices"].get<int>()]["componentType"], 5125);
}

TEST(GltfExport, MapsQuakeBlendingToGltfAlphaModes) {
  q3::WorldMaterial opaque = texturedMaterial("opaque");
  q3::WorldMaterial mask = texturedMaterial("mask");
  mask.alphaMode = q3::WorldAlphaMode::Mask;
  mask.alphaCutoff = 0.5f;
  mask.alphaInvert = true;   // LT128
  q3::WorldMaterial blend = texturedMaterial("blend");
  blend.alphaMode = q3::WorldAlphaMode::Blend;
  blend.opacity = 0.5f;
  q3::WorldMaterial additive = texturedMaterial("add");
  additive.alphaMode = q3::WorldAlphaMode::Additive;
  opaque.lightmapScale = 2.0f;   // a lightmap stage that doubles
  q3::WorldScene scene = sceneWithMaterials({opaque, mask, blend, additive});
  std::vector<std::byte> glb = pa::converter::exportGlb(scene);
  auto [doc, bin] = splitGlb(glb);
  const json& mats = doc["materials"];
  ASSERT_EQ(mats.size(), 4u);
  EXPECT_FALSE(mats[0].contains("alphaMode"));
  EXPECT_FLOAT_EQ(mats[0]["extras"]["quake"]["lightmapStageScale"].get<float>(), 2.0f);
  EXPECT_FALSE(mats[1]["extras"]["quake"].contains("lightmapStageScale"));
  EXPECT_EQ(mats[1]["alphaMode"], "MASK");
  EXPECT_FLOAT_EQ(mats[1]["alphaCutoff"].get<float>(), 0.5f);
  EXPECT_EQ(mats[2]["alphaMode"], "BLEND");
  EXPECT_FLOAT_EQ(mats[2]["pbrMetallicRoughness"]["baseColorFactor"][3].get<float>(), 0.5f);
  EXPECT_EQ(mats[3]["alphaMode"], "BLEND");
  EXPECT_TRUE(mats[3].contains("emissiveTexture"));
  EXPECT_EQ(mats[3]["extras"]["quake"]["blend"], "add");
  EXPECT_EQ(mats[3]["pbrMetallicRoughness"]["baseColorFactor"], json::array({0.0, 0.0, 0.0, 1.0}));

  // Alpha variants: as-is (40), inverted (215), from brightness (200).
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                          static_cast<unsigned>(glb.size())));
  auto alphaOfMaterial = [&](int m) {
    int tex = model.materials[m].pbrMetallicRoughness.baseColorTexture.index;
    return int(model.images[model.textures[tex].source].image[3]);
  };
  EXPECT_EQ(alphaOfMaterial(0), 40);
  EXPECT_EQ(alphaOfMaterial(1), 215);
  EXPECT_EQ(alphaOfMaterial(2), 40);
  EXPECT_EQ(alphaOfMaterial(3), 200);
  EXPECT_EQ(model.images.size(), 3u);   // variants shared, not duplicated
}

TEST(GltfExport, EnvironmentMappedBaseBecomesAReflectiveTint) {
  // The scene's texture 0 is sRGB (200, 100, 50): linear (0.578, 0.127, 0.0319). A chrome base
  // stage (tcGen environment) with rgbGen const (0.5, 1, 1) is exported as that mean colour x
  // the stage colour on a smooth metal, without the image on the mesh UVs.
  q3::WorldMaterial chrome = texturedMaterial("chrome");
  chrome.baseReflects = true;
  chrome.specular = 0.5f;
  chrome.baseColor = glm::vec4(0.5f, 1.0f, 1.0f, 1.0f);
  q3::WorldMaterial plain = texturedMaterial("plain");
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(sceneWithMaterials({chrome, plain})));
  const json& pbr = doc["materials"][0]["pbrMetallicRoughness"];
  EXPECT_FALSE(pbr.contains("baseColorTexture"));
  ASSERT_EQ(pbr["baseColorFactor"].size(), 4u);
  EXPECT_NEAR(pbr["baseColorFactor"][0].get<float>(), 0.5f * 0.5776f, 1e-3f);
  EXPECT_NEAR(pbr["baseColorFactor"][1].get<float>(), 0.1274f, 1e-3f);
  EXPECT_NEAR(pbr["baseColorFactor"][2].get<float>(), 0.0319f, 1e-3f);
  EXPECT_FLOAT_EQ(pbr["baseColorFactor"][3].get<float>(), 1.0f);
  EXPECT_FLOAT_EQ(pbr["metallicFactor"].get<float>(), 1.0f);
  EXPECT_FLOAT_EQ(pbr["roughnessFactor"].get<float>(), 0.25f);
  EXPECT_EQ(doc["materials"][0]["extras"]["quake"]["environmentMap"], "textures/test/a.tga");
  EXPECT_FALSE(doc["materials"][0]["extras"]["quake"].contains("texture"));
  // An ordinary material keeps its texture; the image is written once, for it alone.
  EXPECT_TRUE(doc["materials"][1]["pbrMetallicRoughness"].contains("baseColorTexture"));
  EXPECT_FLOAT_EQ(doc["materials"][1]["pbrMetallicRoughness"]["metallicFactor"].get<float>(), 0.0f);
  EXPECT_EQ(doc["images"].size(), 1u);
}

TEST(GltfExport, TextureAddedOverTheReflectionIsTheBase) {
  // Shiny floor (texture, chrome, the texture added, $lightmap filter): the added texture is
  // the base of a smooth dielectric; the chrome image is not written.
  q3::WorldMaterial floor = texturedMaterial("hfloor3");
  floor.baseReflects = true;
  floor.reflectionOverlayTexture = 1;
  q3::WorldScene scene = sceneWithMaterials({floor});
  scene.textures.push_back({"textures/test/floor", "textures/test/floor.tga", solidImage(2, 2, 9, 9, 9, 255), false, false});
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(scene));
  const json& m = doc["materials"][0];
  EXPECT_EQ(m["pbrMetallicRoughness"]["baseColorFactor"], json::array({1.0, 1.0, 1.0, 1.0}));
  EXPECT_FLOAT_EQ(m["pbrMetallicRoughness"]["metallicFactor"].get<float>(), 0.0f);
  EXPECT_FLOAT_EQ(m["pbrMetallicRoughness"]["roughnessFactor"].get<float>(), 0.25f);
  ASSERT_TRUE(m["pbrMetallicRoughness"].contains("baseColorTexture"));
  EXPECT_EQ(m["extras"]["quake"]["texture"], "textures/test/floor.tga");
  EXPECT_EQ(m["extras"]["quake"]["environmentMap"], "textures/test/a.tga");
  ASSERT_EQ(doc["images"].size(), 1u);
  EXPECT_EQ(doc["images"][0]["name"], "textures/test/floor.tga");
}

TEST(GltfExport, EnvironmentMapWithAMissingImageIsAPlainMetal) {
  q3::WorldMaterial chrome = texturedMaterial("chrome");
  chrome.baseReflects = true;
  q3::WorldScene scene = sceneWithMaterials({chrome});
  scene.textures[0].isFallback = true;   // the checker stands in for a missing file: no tint from it
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(scene));
  const json& pbr = doc["materials"][0]["pbrMetallicRoughness"];
  EXPECT_EQ(pbr["baseColorFactor"], json::array({1.0, 1.0, 1.0, 1.0}));
  EXPECT_FALSE(doc.contains("images"));
}

TEST(GltfExport, SurfaceLightBecomesEmissiveStrength) {
  q3::WorldMaterial glow = texturedMaterial("glow");
  glow.surfaceLight = 1000.0f;
  glow.emission = glm::vec3(0.5f, 0.25f, 0.0f);
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(sceneWithMaterials({glow})));
  const json& m = doc["materials"][0];
  EXPECT_EQ(m["emissiveFactor"], json::array({1.0, 0.5, 0.0}));   // normalised colour
  EXPECT_FLOAT_EQ(m["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"].get<float>(),
                  1000.0f * 3.0f * 0.25f / 64.0f);   // q3map2: value * formFactorValueScale * areaScale / full bright
  EXPECT_NE(std::find(doc["extensionsUsed"].begin(), doc["extensionsUsed"].end(), "KHR_materials_emissive_strength"),
            doc["extensionsUsed"].end());
}

TEST(GltfExport, SkipsInvisibleSkyAndFogSurfaces) {
  q3::WorldMaterial nodraw = texturedMaterial("nodraw");
  nodraw.visible = false;
  q3::WorldMaterial sky = texturedMaterial("sky");
  sky.sky = true;
  q3::WorldMaterial fog = texturedMaterial("fog");
  fog.fog = true;
  fog.visible = false;   // a fog-only shader (the world builder hides it)
  q3::WorldMaterial wall = texturedMaterial("wall");
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(sceneWithMaterials({nodraw, sky, fog, wall})));
  ASSERT_EQ(doc["meshes"][0]["primitives"].size(), 1u);
  EXPECT_EQ(doc["materials"].size(), 1u);
  EXPECT_EQ(doc["materials"][0]["name"], "wall");
}

TEST(GltfExport, FogVolumesGoToTheSceneExtrasInQuakeUnits) {
  q3::WorldScene scene = sceneWithMaterials({texturedMaterial("a")});
  q3::WorldFog fog;
  fog.shaderName = "textures/test/fog";
  fog.planes = {{1, 0, 0, 64}, {-1, 0, 0, 0}, {0, 0, 1, 16}};
  fog.color = {0.5f, 0.25f, 0.0f};
  fog.depthForOpaque = 256.0f;
  scene.fogs.push_back(fog);
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(scene));
  json fogs;
  for (const json& node : doc["nodes"])
    if (node.contains("extras") && node["extras"].contains("quake") && node["extras"]["quake"].contains("fogs"))
      fogs = node["extras"]["quake"]["fogs"];
  ASSERT_EQ(fogs.size(), 1u);
  EXPECT_EQ(fogs[0]["shader"], "textures/test/fog");
  ASSERT_EQ(fogs[0]["planes"].size(), 3u);
  EXPECT_EQ(fogs[0]["planes"][2], json::array({0.0, 0.0, 1.0, 16.0}));
  EXPECT_FLOAT_EQ(fogs[0]["depthForOpaque"].get<float>(), 256.0f);
}

TEST(GltfExport, WorldspawnAmbientGoesToTheSceneExtrasAsLightValues) {
  q3::WorldScene scene = sceneWithMaterials({texturedMaterial("a")});
  scene.ambientLight = {46.0f, 28.0f, 28.0f};
  scene.minimumLight = glm::vec3(32.0f);
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(scene));
  json quake;
  for (const json& node : doc["nodes"])
    if (node.contains("extras") && node["extras"].contains("quake") && node["extras"]["quake"].contains("ambientLight"))
      quake = node["extras"]["quake"];
  ASSERT_FALSE(quake.is_null());
  EXPECT_EQ(quake["ambientLight"], json::array({46.0, 28.0, 28.0}));
  EXPECT_EQ(quake["minimumLight"], json::array({32.0, 32.0, 32.0}));
}

glm::vec3 localMinusZ(const json& node) {
  glm::quat q(node["rotation"][3].get<float>(), node["rotation"][0].get<float>(), node["rotation"][1].get<float>(),
              node["rotation"][2].get<float>());
  return q * glm::vec3(0, 0, -1);
}

TEST(GltfExport, LightsUsePunctualExtensionInMetres) {
  q3::WorldScene scene = sceneWithMaterials({texturedMaterial("a")});
  q3::WorldLight point;
  point.position = {64, 0, 32};
  point.intensity = q3::pointLightIntensity(300.0f);
  point.source = "entity 1 (light)";
  q3::WorldLight spot = point;
  spot.type = q3::WorldLightType::Spot;
  spot.direction = {0, 0, -1};   // straight down
  spot.cosOuterAngle = std::cos(0.5f);
  q3::WorldLight sun;
  sun.type = q3::WorldLightType::Sun;
  sun.direction = glm::normalize(glm::vec3(0, 1, -1));   // travelling +Y (quake) and down
  sun.intensity = q3::sunIrradiance(100.0f);
  scene.lights = {point, spot, sun};
  pa::converter::ExportOptions options;
  options.metresPerUnit = 0.5f;
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(scene, options));
  const json& lights = doc["extensions"]["KHR_lights_punctual"]["lights"];
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_EQ(lights[0]["type"], "point");
  EXPECT_FLOAT_EQ(lights[0]["intensity"].get<float>(), q3::pointLightIntensity(300.0f) * 0.25f);
  EXPECT_EQ(lights[1]["type"], "spot");
  EXPECT_NEAR(lights[1]["spot"]["outerConeAngle"].get<float>(), 0.5f, 1e-5f);
  EXPECT_EQ(lights[2]["type"], "directional");
  EXPECT_FLOAT_EQ(lights[2]["intensity"].get<float>(), q3::sunIrradiance(100.0f));

  // Find the light nodes and check position and aim in glTF axes.
  std::vector<json> lightNodes;
  for (const auto& node : doc["nodes"])
    if (node.contains("extensions")) lightNodes.push_back(node);
  ASSERT_EQ(lightNodes.size(), 3u);
  EXPECT_EQ(lightNodes[0]["translation"], json::array({32.0, 16.0, -0.0}));
  glm::vec3 spotAim = localMinusZ(lightNodes[1]);
  EXPECT_NEAR(spotAim.y, -1.0f, 1e-5f);
  glm::vec3 sunAim = localMinusZ(lightNodes[2]);   // quake (0, 1, -1)/sqrt2 -> gltf (0, -1, -1)/sqrt2
  EXPECT_NEAR(sunAim.x, 0.0f, 1e-5f);
  EXPECT_NEAR(sunAim.y, -std::sqrt(0.5f), 1e-5f);
  EXPECT_NEAR(sunAim.z, -std::sqrt(0.5f), 1e-5f);
}

TEST(GltfExport, CamerasLookAlongTheSpawnDirection) {
  q3::WorldScene scene = sceneWithMaterials({texturedMaterial("a")});
  q3::WorldCamera cam;
  cam.name = "info_player_deathmatch 0";
  cam.eye = {0, 0, 64};
  cam.forward = {0, 1, 0};   // yaw 90: facing quake +Y -> glTF -Z
  cam.left = {-1, 0, 0};
  scene.cameras = {cam};
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(scene));
  ASSERT_EQ(doc["cameras"].size(), 1u);
  EXPECT_NEAR(doc["cameras"][0]["perspective"]["yfov"].get<float>(), glm::radians(73.74f), 1e-5f);
  json node;
  for (const auto& n : doc["nodes"])
    if (n.contains("camera")) node = n;
  ASSERT_FALSE(node.is_null());
  EXPECT_EQ(node["translation"], json::array({0.0, 2.0, -0.0}));
  glm::vec3 aim = localMinusZ(node);
  EXPECT_NEAR(aim.z, -1.0f, 1e-5f);
  glm::quat q(node["rotation"][3].get<float>(), node["rotation"][0].get<float>(), node["rotation"][1].get<float>(),
              node["rotation"][2].get<float>());
  EXPECT_NEAR((q * glm::vec3(0, 1, 0)).y, 1.0f, 1e-5f);   // camera up stays world up
}

}  // namespace

namespace {

q3::TcMod tcMod(q3::TcModKind kind, std::array<float, 4> matrix = {1, 0, 0, 1}, std::array<float, 2> values = {0, 0}) {
  q3::TcMod m;
  m.kind = kind;
  m.matrix = matrix;
  m.scroll = values;
  return m;
}

TEST(GltfExport, StaticTcModsBecomeTextureTransformsAnimatedOnesExtras) {
  q3::WorldMaterial scaled = texturedMaterial("scaled");
  scaled.tcMods = {tcMod(q3::TcModKind::Scale, {1, 0, 0, 1}, {2, 3})};
  q3::WorldMaterial turned = texturedMaterial("turned");   // s' = -t, t' = s: a quarter turn
  turned.tcMods = {tcMod(q3::TcModKind::Transform, {0, 1, -1, 0})};
  q3::WorldMaterial sheared = texturedMaterial("sheared");  // s' = s + t: no rotation x scale gives it
  sheared.tcMods = {tcMod(q3::TcModKind::Transform, {1, 0, 1, 1})};
  q3::WorldMaterial scrolling = texturedMaterial("scrolling");
  scrolling.tcMods = {tcMod(q3::TcModKind::Scale, {1, 0, 0, 1}, {2, 2}), tcMod(q3::TcModKind::Scroll, {1, 0, 0, 1}, {0.5f, 0})};
  auto [doc, bin] = splitGlb(pa::converter::exportGlb(sceneWithMaterials({scaled, turned, sheared, scrolling})));
  const json& mats = doc["materials"];
  ASSERT_EQ(mats.size(), 4u);
  auto transformOf = [&](size_t m) { return mats[m]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"]; };
  EXPECT_EQ(transformOf(0)["scale"], json::array({2.0, 3.0}));
  EXPECT_FALSE(transformOf(0).contains("rotation"));
  EXPECT_FALSE(mats[0]["extras"]["quake"].contains("tcMods"));
  EXPECT_NEAR(transformOf(1)["rotation"].get<float>(), -std::numbers::pi_v<float> / 2, 1e-6);
  EXPECT_FALSE(transformOf(1).contains("scale"));
  EXPECT_FALSE(mats[2]["pbrMetallicRoughness"]["baseColorTexture"].contains("extensions"));
  // Animated: the time-0 look (scale 2) as a transform, the whole list in extras.
  EXPECT_EQ(transformOf(3)["scale"], json::array({2.0, 2.0}));
  const json& mods = mats[3]["extras"]["quake"]["tcMods"];
  ASSERT_EQ(mods.size(), 2u);
  EXPECT_EQ(mods[0]["tcMod"], "scale");
  EXPECT_EQ(mods[1]["tcMod"], "scroll");
  EXPECT_EQ(mods[1]["speed"], json::array({0.5, 0.0}));
  EXPECT_NE(std::find(doc["extensionsUsed"].begin(), doc["extensionsUsed"].end(), "KHR_texture_transform"),
            doc["extensionsUsed"].end());
}

}  // namespace

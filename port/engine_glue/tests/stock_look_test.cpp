// Known answers for the lightmap preset's stock-look helpers: entity lighting from the light
// grid (entity_lighting.h) and the baked stock sky (sky_cube.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "port/engine_glue/entity_materials.h"
#include "port/engine_glue/entity_lighting.h"
#include "port/engine_glue/scene.h"
#include "port/engine_glue/sky_cube.h"
#include "port/engine_glue/stock_look.h"
#include "port/engine_glue/world_sprites.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/shader/shader_parser.h"
#include "renderer/core/srgb.h"

namespace glue {
namespace {

constexpr float kPi = 3.14159265358979f;

TEST(StockLook, ByteToLinearIsTheClampedCurveToTheBit) {
  // Whole bytes come from a table: the same bits as the curve, and so do 0, -0 and fractions.
  const auto same = [](float byte) {
    const float expected = pa::srgbToLinearClamped(byte / 255.0f), got = byteToLinear(byte);
    return std::memcmp(&expected, &got, sizeof(float)) == 0;
  };
  for (int b = 0; b < 256; ++b) EXPECT_TRUE(same(static_cast<float>(b))) << b;
  for (const float byte : {-0.0f, -3.0f, 0.5f, 1.25f, 127.5f, 254.999f, 255.0f, 256.0f, 300.0f, 1e9f})
    EXPECT_TRUE(same(byte)) << byte;
}

TEST(EntityLighting, ColorShiftKeepsHueWhenSaturating) {
  EXPECT_EQ(colorShiftLight({10, 20, 30}, 2), glm::vec3(40, 80, 120));
  // 256, 128, 64 passes 255: scaled by 255/256 with integer truncation, as the engine does.
  EXPECT_EQ(colorShiftLight({64, 32, 16}, 2), glm::vec3(255, 127, 63));
  EXPECT_EQ(colorShiftLight({0, 0, 0}, 2), glm::vec3(0));
}

q3::WorldLightGrid twoPointGrid() {
  q3::WorldLightGrid grid;
  grid.origin = {0, 0, 0};
  grid.cellSize = {64, 64, 128};
  grid.counts = {2, 1, 1};
  // Longitude 0 -> direction (0, 0, 1) whatever the latitude.
  grid.samples = {{10, 10, 10, 20, 20, 20, 0, 0}, {30, 30, 30, 40, 40, 40, 0, 0}};
  return grid;
}

TEST(EntityLighting, GridIsShiftedInterpolatedAndScaled) {
  EntityLight light;
  ASSERT_TRUE(lightGridAt(twoPointGrid(), {16, 0, 0}, light));
  // x = 16 of 64: weights 0.75 / 0.25 of the shifted samples (40, 120 ambient; 80, 160 directed).
  EXPECT_NEAR(light.ambient.r, (0.75f * 40 + 0.25f * 120) * 0.6f, 1e-3f);
  EXPECT_NEAR(light.directed.g, 0.75f * 80 + 0.25f * 160, 1e-3f);
  EXPECT_NEAR(light.direction.z, 1.0f, 1e-5f);
}

TEST(EntityLighting, SamplesInWallsAreSkippedAndWeightsRenormalised) {
  q3::WorldLightGrid grid = twoPointGrid();
  grid.samples[1] = {0, 0, 0, 90, 90, 90, 0, 0};   // no ambient: inside a wall
  EntityLight light;
  ASSERT_TRUE(lightGridAt(grid, {32, 0, 0}, light));
  EXPECT_NEAR(light.ambient.r, 40 * 0.6f, 1e-3f);
  EXPECT_NEAR(light.directed.r, 80, 1e-3f);
}

TEST(EntityLighting, EmptyGridIsRefused) {
  EntityLight light;
  EXPECT_FALSE(lightGridAt(q3::WorldLightGrid{}, {0, 0, 0}, light));
  q3::WorldLightGrid truncated = twoPointGrid();
  truncated.samples.pop_back();
  EXPECT_FALSE(lightGridAt(truncated, {0, 0, 0}, light));
}

TEST(EntityLighting, MinimumLightDynamicLightsAndClamp) {
  EntityLight light;
  light.ambient = {100, 240, 0};
  light.directed = {50, 50, 50};
  light.direction = {0, 0, 1};
  DynamicLight red;
  red.origin = {32, 0, 0};
  red.radius = 100;
  red.color = {1, 0, 0};
  const DynamicLight lights[] = {red};
  const EntityLight lit = finishEntityLight(light, {0, 0, 0}, lights);
  EXPECT_EQ(lit.ambient, glm::vec3(132, 255, 32));
  const float power = 16.0f * 100 * 100 / (32 * 32);
  EXPECT_NEAR(lit.directed.r, 50 + power, 1e-2f);
  EXPECT_NEAR(lit.directed.g, 50, 1e-4f);
  // The direction turns towards the light: (power, 0, |directed|) normalised.
  const glm::vec3 expected = glm::normalize(glm::vec3(power, 0, std::sqrt(3.0f) * 50));
  EXPECT_NEAR(lit.direction.x, expected.x, 1e-4f);
  EXPECT_NEAR(lit.direction.z, expected.z, 1e-4f);
}

TEST(EntityLighting, VertexLightIsAmbientPlusLambertClampedPerChannel) {
  EntityLight light;
  light.ambient = {40, 100, 200};
  light.directed = {100, 100, 100};
  light.direction = {0, 0, 1};
  EXPECT_EQ(diffuseVertexLight(light, {0, 0, -1}), glm::vec3(40, 100, 200));
  EXPECT_EQ(diffuseVertexLight(light, {0, 0, 1}), glm::vec3(140, 200, 255));
  EXPECT_EQ(diffuseVertexLight(light, glm::normalize(glm::vec3(1, 0, 1))), glm::vec3(110, 170, 255));
  const EntityLight none = noWorldLight();
  EXPECT_EQ(none.ambient, glm::vec3(150));
  EXPECT_NEAR(glm::length(none.direction), 1.0f, 1e-6f);
}

TEST(SkyCube, TracedSkyLooksStockAndLightsAsCompiled) {
  // Faces of sRGB byte 128 (linear 0.2158605) on three sides and black on three: mean 0.1079.
  SkyCube cube;
  cube.size = 2;
  for (size_t f = 0; f < 6; ++f) cube.faces[f].assign(16, f < 3 ? 128 : 0);
  const glm::vec3 mean = skyCubeMeanLinear(cube);
  EXPECT_NEAR(mean.g, 0.5f * pa::srgbToLinear(128.0f / 255.0f), 1e-5f);
  pa::SkyDesc stock;
  stock.color = glm::vec3(1.0f);
  stock.faces[0] = 7;
  pa::SkyDesc bridge;
  bridge.ambientRadiance = glm::vec3(0.1f);
  bridge.minimumRadiance = glm::vec3(0.2f);
  // The compiler lit the map with a uniform sky of radiance 0.234 (q3map_surfacelight 20): the
  // stock look, seen as drawn, lights with its mean's brightest channel brought to 0.234.
  const pa::SkyDesc sky = litStockSky(stock, mean, bridge, glm::vec3(0.234f));
  EXPECT_EQ(sky.faces[0], 7);
  EXPECT_EQ(sky.color, glm::vec3(1.0f));
  EXPECT_NEAR(mean.g * sky.lightingScale, 0.234f, 1e-5f);
  EXPECT_EQ(sky.ambientRadiance, glm::vec3(0.1f));
  EXPECT_EQ(sky.minimumRadiance, glm::vec3(0.2f));
  // A deep blue night sky over a white compiled sky light (czest1dm: nitesky, q3map_surfacelight
  // 20 from its grey star image): its brightest channel lights as the compiled light's, so no
  // channel lights more than the compiler lit (brought to the compiled luminance, its blue lit
  // at 3.4x the compiled light: the sunlit courtyard turned blue, 0.65x the bake's brightness).
  const glm::vec3 blue(0.0033f, 0.0030f, 0.0130f);
  const pa::SkyDesc night = litStockSky(stock, blue, bridge, glm::vec3(0.234f));
  EXPECT_NEAR(blue.b * night.lightingScale, 0.234f, 1e-5f);
  EXPECT_LT(blue.r * night.lightingScale, 0.234f);
  // A map lit by its sun alone: the sky lights nothing; a black stock sky leaves the bridge's.
  EXPECT_EQ(litStockSky(stock, mean, bridge, glm::vec3(0.0f)).lightingScale, 0.0f);
  bridge.lightingScale = 3.0f;
  EXPECT_EQ(litStockSky(stock, glm::vec3(0.0f), bridge, glm::vec3(0.234f)).lightingScale, 3.0f);
  EXPECT_EQ(litStockSky(stock, glm::vec3(0.0f), bridge, glm::vec3(0.234f)).faces[0], pa::kNoId);
}

TEST(SkyCube, CloudCoordinatesOfTheZenithAndTheHorizon) {
  const glm::vec2 up = cloudTexCoords({0, 0, 1}, 1024);
  EXPECT_NEAR(up.x, kPi / 2, 1e-5f);
  EXPECT_NEAR(up.y, kPi / 2, 1e-5f);
  // Horizontal ray: meets the dome at distance sqrt(2Rh + h^2), height R above its centre.
  const float r = 4096, h = 1024;
  const float p = std::sqrt(2 * r * h + h * h);
  const glm::vec2 east = cloudTexCoords({1, 0, 0}, h);
  EXPECT_NEAR(east.x, std::acos(p / (r + h)), 1e-4f);
  EXPECT_NEAR(east.y, kPi / 2, 1e-5f);
  // The length of the direction does not matter; cloud height 0 means 512.
  EXPECT_NEAR(cloudTexCoords({3, 0, 0}, h).x, east.x, 1e-5f);
  EXPECT_NEAR(cloudTexCoords({1, 0, 0}, 0).x, cloudTexCoords({1, 0, 0}, 512).x, 1e-6f);
}

TEST(SkyCube, FaceDirectionsFollowTheTracerConvention) {
  const glm::vec3 centre = skyCubeDirection(0, 1, 1, 3);
  EXPECT_EQ(centre, glm::vec3(1, 0, 0));
  // Face +X: image right is -Y, image top is +Z.
  EXPECT_LT(skyCubeDirection(0, 2, 1, 3).y, 0.0f);
  EXPECT_GT(skyCubeDirection(0, 1, 0, 3).z, 0.0f);
  EXPECT_EQ(skyCubeDirection(4, 1, 1, 3), glm::vec3(0, 0, 1));
}

std::shared_ptr<const Image> solid(uint8_t r, uint8_t g, uint8_t b) {
  auto image = std::make_shared<Image>();
  image->width = image->height = 4;
  for (int i = 0; i < 16; ++i) image->rgba.insert(image->rgba.end(), {r, g, b, 255});
  return image;
}

glm::ivec3 texel(const SkyCube& cube, int face, int x, int y) {
  const uint8_t* p = &cube.faces[size_t(face)][(size_t(y) * cube.size + x) * 4];
  return {p[0], p[1], p[2]};
}

TEST(SkyCube, FarBoxImagesLandOnTheStockSides) {
  // Stock draws rt on +X, lf on -X, bk on +Y, ft on -Y, up on +Z, dn on -Z.
  std::map<std::string, std::shared_ptr<const Image>> files = {
      {"env/box_rt", solid(10, 0, 0)}, {"env/box_bk", solid(20, 0, 0)}, {"env/box_lf", solid(30, 0, 0)},
      {"env/box_ft", solid(40, 0, 0)}, {"env/box_up", solid(50, 0, 0)}, {"env/box_dn", solid(60, 0, 0)}};
  q3::ShaderDef shader;
  shader.sky = q3::SkyParms{"env/box", 512, ""};
  SkyBaker baker;
  ASSERT_TRUE(baker.prepare(shader, [&](const std::string& path) { return files[path]; }, 8));
  EXPECT_FALSE(baker.animated());
  SkyCube cube;
  baker.bake(0.0, cube);
  ASSERT_EQ(cube.size, 8);
  const int expected[6] = {10, 30, 20, 40, 50, 60};
  for (int face = 0; face < 6; ++face) EXPECT_EQ(texel(cube, face, 4, 4).x, expected[face]) << "face " << face;
}

TEST(SkyCube, TheUpImageIsTurnedAsTheStockBoxShowsIt) {
  // tr_sky.c side +Z: x = -t, y = -s; texture (s, t) -> ((s + 1) / 2, (1 - t) / 2). A direction
  // toward +X and -Y of straight up has s = 0.625, t = -0.625: the right, bottom texel.
  auto up = std::make_shared<Image>();
  up->width = up->height = 2;
  up->rgba = {10, 0, 0, 255, 20, 0, 0, 255, 30, 0, 0, 255, 40, 0, 0, 255};   // TL TR BL BR
  q3::ShaderDef shader;
  shader.sky = q3::SkyParms{"env/box", 512, ""};
  SkyBaker baker;
  ASSERT_TRUE(baker.prepare(shader, [&](const std::string& path) { return path == "env/box_up" ? up : nullptr; }, 8));
  SkyCube cube;
  baker.bake(0.0, cube);
  const glm::vec3 d = skyCubeDirection(4, 1, 1, 8);
  ASSERT_NEAR(d.x, 0.625f, 1e-6f);
  ASSERT_NEAR(d.y, -0.625f, 1e-6f);
  EXPECT_EQ(texel(cube, 4, 1, 1).x, 40);
  EXPECT_EQ(texel(cube, 4, 6, 6).x, 10);   // toward -X, +Y: the left, top texel
}

TEST(SkyCube, CloudStagesBlendOverTheBoxExceptBelow) {
  q3::ShaderDef shader;
  shader.sky = q3::SkyParms{"", 512, ""};
  q3::ShaderStage add;
  add.textures = {"clouds_add"};
  add.hasBlend = true;
  add.srcBlend = add.dstBlend = q3::BlendFactor::One;
  q3::ShaderStage filter = add;
  filter.textures = {"clouds_filter"};
  filter.srcBlend = q3::BlendFactor::DstColor;
  filter.dstBlend = q3::BlendFactor::Zero;
  filter.tcMods.push_back(q3::TcMod{});   // scroll 0 0: animated, same picture
  shader.stages = {add, filter};
  std::map<std::string, std::shared_ptr<const Image>> files = {{"clouds_add", solid(200, 100, 50)},
                                                               {"clouds_filter", solid(128, 255, 0)}};
  SkyBaker baker;
  ASSERT_TRUE(baker.prepare(shader, [&](const std::string& path) { return files[path]; }, 4));
  EXPECT_TRUE(baker.animated());
  SkyCube cube;
  baker.bake(3.0, cube);
  // (0 + add) * filter: 200 * 128 / 255 = 100.4, 100 * 1, 50 * 0.
  EXPECT_EQ(texel(cube, 4, 1, 1), glm::ivec3(100, 100, 0));
  EXPECT_EQ(texel(cube, 0, 2, 3), glm::ivec3(100, 100, 0));
  EXPECT_EQ(texel(cube, 5, 1, 1), glm::ivec3(0, 0, 0));   // no clouds on the bottom face
}

TEST(SkyCube, ThePictureShowsWhatTheBakeWritesAtTexelCentres) {
  // A far box under a scrolling cloud layer: the per-direction picture at a shader time, encoded
  // back to display bytes, equals the bake at that time at every texel centre (the bake rounds to
  // bytes), and the clouds move between two times. The bottom is the far box alone.
  std::map<std::string, std::shared_ptr<const Image>> files = {{"env/box_dn", solid(60, 70, 80)},
                                                               {"env/box_rt", solid(90, 20, 200)}};
  auto clouds = std::make_shared<Image>();
  clouds->width = clouds->height = 4;
  for (int i = 0; i < 16; ++i) clouds->rgba.insert(clouds->rgba.end(), {uint8_t(16 * i), uint8_t(255 - 9 * i), 40, 255});
  files["clouds"] = clouds;
  q3::ShaderDef shader;
  shader.sky = q3::SkyParms{"env/box", 512, ""};
  q3::ShaderStage stage;
  stage.textures = {"clouds"};
  stage.hasBlend = true;
  stage.srcBlend = stage.dstBlend = q3::BlendFactor::One;
  q3::TcMod scroll;
  scroll.kind = q3::TcModKind::Scroll;
  scroll.scroll = {0.1f, 0.05f};
  stage.tcMods = {scroll};
  shader.stages = {stage};
  auto baker = std::make_shared<SkyBaker>();
  ASSERT_TRUE(baker->prepare(shader, [&](const std::string& path) { return files[path]; }, 8));
  ASSERT_TRUE(baker->animated());
  for (const double seconds : {0.0, 2.5}) {
    SkyCube cube;
    baker->bake(seconds, cube);
    const auto picture = stockSkyPictureAt(baker, seconds);
    ASSERT_NE(picture, nullptr);
    for (int face = 0; face < 6; ++face)
      for (int y = 0; y < cube.size; ++y)
        for (int x = 0; x < cube.size; ++x) {
          const glm::vec3 linear = picture->radiance(skyCubeDirection(face, x, y, cube.size));
          const glm::ivec3 baked = texel(cube, face, x, y);
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(pa::linearToSrgb(linear[c]) * 255.0f, float(baked[c]), 0.51f)
                << "face " << face << " texel " << x << "," << y << " channel " << c << " at " << seconds << " s";
        }
  }
  SkyCube first, later;
  baker->bake(0.0, first);
  baker->bake(2.5, later);
  EXPECT_NE(first.faces[4], later.faces[4]);   // the clouds moved
  EXPECT_EQ(texel(later, 5, 3, 3), glm::ivec3(60, 70, 80));
  EXPECT_EQ(stockSkyPictureAt(nullptr, 1.0), nullptr);
}

TEST(SkyCube, NothingToBakeWithoutBoxOrStages) {
  q3::ShaderDef shader;
  shader.sky = q3::SkyParms{"env/missing", 512, ""};
  SkyBaker baker;
  EXPECT_FALSE(baker.prepare(shader, [](const std::string&) { return nullptr; }, 8));
}

q3::WorldScene floorScene() {
  q3::WorldScene scene;
  q3::WorldMaterial material;
  material.shaderName = "textures/test/floor";
  scene.materials.push_back(material);
  q3::WorldImage lightmap{2, 2, std::vector<uint8_t>(16, 32)};   // stored 32 -> 128 after the shift
  scene.lightmaps.push_back(lightmap);
  q3::WorldMesh mesh;
  mesh.lightmap = 0;
  mesh.positions = {{-32, -32, 0}, {32, -32, 0}, {32, 32, 0}, {-32, 32, 0}};
  mesh.normals.assign(4, {0, 0, 1});
  mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.lightmapUvs = mesh.uvs;
  mesh.colors.assign(4, glm::vec4(1.0f));
  mesh.indices = {0, 1, 2, 0, 2, 3};
  scene.models.resize(1);
  scene.models[0].meshes.push_back(mesh);
  return scene;
}

TEST(StageLayers, BlendFactorsOfTheLayersOwnColourAndAlpha) {
  const auto explosion = layerFactors({1, 0x0302});   // gl_one gl_src_alpha
  ASSERT_TRUE(explosion.has_value());
  EXPECT_EQ(explosion->first, pa::BlendFactor::One);
  EXPECT_EQ(explosion->second, pa::BlendFactor::SrcAlpha);
  const auto inverse = layerFactors({0x0303, 0x0301});
  ASSERT_TRUE(inverse.has_value());
  EXPECT_EQ(inverse->first, pa::BlendFactor::OneMinusSrcAlpha);
  EXPECT_EQ(inverse->second, pa::BlendFactor::OneMinusSrcColor);
  EXPECT_FALSE(layerFactors({0x0306, 0}).has_value());       // gl_dst_color: reads the framebuffer
  EXPECT_FALSE(layerFactors({1, 0x0304}).has_value());       // gl_dst_alpha
}

TEST(StageLayers, ExplosionStagesAreAllLayers) {
  // OpenArena's rocketExplosion: two gl_one gl_src_alpha animMaps, then two additive flames.
  const q3::ShaderScript script = q3::parseShaderScript(
      "boom\n{\n { animmap 8 a1.tga a2.tga\n blendfunc gl_one gl_src_alpha\n rgbGen wave inversesawtooth 0 1 0 8 }\n"
      " { animmap 8 a2.tga a3.tga\n blendfunc gl_one gl_src_alpha }\n"
      " { clampmap f.tga\n blendfunc add }\n { map g.tga\n blendfunc gl_dst_color gl_zero }\n}\n",
      "fx.shader");
  ASSERT_EQ(script.shaders.size(), 1u);
  const ShaderLook look = lookOfShader(script.shaders[0]);
  EXPECT_EQ(look.blend.src, 1u);
  EXPECT_EQ(look.blend.dst, 0x0302u);
  ASSERT_EQ(look.layers.size(), 3u);   // every later blended image stage, in stage order
  EXPECT_EQ(look.layers[0].images[0], "a2.tga");
  EXPECT_EQ(look.layers[1].blend.dst, 1u);
  EXPECT_EQ(look.layers[2].blend.src, 0x0306u);
  // An alpha-blended first stage keeps its later stages out (its vertex colours are premultiplied).
  const q3::ShaderScript smoke = q3::parseShaderScript(
      "puff\n{\n { map s.tga\n blendfunc blend }\n { map t.tga\n blendfunc add }\n}\n", "fx.shader");
  EXPECT_TRUE(lookOfShader(smoke.shaders.at(0)).layers.empty());
}

TEST(WorldSprites, AutospriteQuadsFaceTheViewerAndMoveWithTheirWaves) {
  q3::ShaderLibrary library;
  ASSERT_TRUE(library.addScript(
      "textures/fx/puff\n{\n deformVertexes autosprite\n deformVertexes move 0 0 100 sawtooth 0 1 0 0.5\n"
      " {\n  clampmap puff.tga\n  blendfunc blend\n  alphaGen wave sawtooth 1 -1 0 0.5\n }\n}\n",
      "fx.shader"));
  q3::WorldScene scene = floorScene();
  scene.materials[0].shaderName = "textures/fx/puff";
  scene.materials[0].fromScript = true;
  WorldSprites sprites;
  const std::vector<uint32_t> materials = sprites.prepare(scene, library);
  ASSERT_EQ(materials, std::vector<uint32_t>{0});
  ASSERT_EQ(sprites.size(), 1u);
  const Viewer viewer{{-500, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  GeometryBatch batch;
  // t = 1 s: sawtooth at phase 0.5 -> moved up 50 units; the alpha wave is the material's.
  sprites.append(1.0, viewer, [](const std::string& name) { return name == "textures/fx/puff" ? 5 : 0; }, {}, batch);
  ASSERT_EQ(batch.positions.size(), 4u);
  EXPECT_EQ(batch.triangleShaders[0], 5);
  const float radius = 32.0f * std::sqrt(2.0f) * 0.707f;
  EXPECT_NEAR(batch.positions[0].x, 0.0f, 1e-4f);
  EXPECT_NEAR(batch.positions[0].y, radius, 1e-3f);
  EXPECT_NEAR(batch.positions[0].z, 50.0f + radius, 1e-3f);
  for (const glm::vec4& c : batch.colors) EXPECT_EQ(c, glm::vec4(1.0f));
  GeometryBatch none;
  sprites.append(1.0, viewer, [](const std::string&) { return 0; }, {}, none);
  EXPECT_TRUE(none.positions.empty());   // no shader handle: nothing drawn
}

TEST(WorldSprites, BrushModelSpritesFollowTheirEntity) {
  q3::ShaderLibrary library;
  ASSERT_TRUE(library.addScript("textures/fx/ball\n{\n deformVertexes autosprite\n {\n  map ball.tga\n  blendfunc add\n }\n}\n",
                                "fx.shader"));
  q3::WorldScene scene = floorScene();
  scene.materials[0].shaderName = "textures/fx/ball";
  scene.materials[0].fromScript = true;
  scene.models.push_back(scene.models[0]);   // "*1": the same card on a mover
  scene.models[0].meshes.clear();
  WorldSprites sprites;
  sprites.prepare(scene, library);
  ASSERT_EQ(sprites.size(), 1u);
  const Viewer viewer{{-500, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  glm::mat4x3 moved(1.0f);
  moved[3] = glm::vec3(0, 0, 300);
  GeometryBatch batch;
  sprites.append(0.0, viewer, [](const std::string&) { return 2; },
                 [&](uint32_t model) { return model == 1 ? &moved : nullptr; }, batch);
  ASSERT_EQ(batch.positions.size(), 4u);
  EXPECT_NEAR(0.25f * (batch.positions[0].z + batch.positions[1].z + batch.positions[2].z + batch.positions[3].z), 300.0f, 1e-3f);
  GeometryBatch hidden;
  sprites.append(0.0, viewer, [](const std::string&) { return 2; }, [](uint32_t) { return nullptr; }, hidden);
  EXPECT_TRUE(hidden.positions.empty());   // the mover is not in this view
}

TEST(StockWorldLook, UnlitShadersAreWhitenedAndVertexLightIsShifted) {
  q3::ShaderLibrary library;
  ASSERT_TRUE(library.addScript(
      "textures/test/unlit\n{\n {\n  map a.tga\n }\n {\n  map glow.tga\n  blendfunc add\n  rgbGen const ( 1 0 0 )\n }\n}\n",
      "test.shader"));
  q3::WorldScene scene = floorScene();
  scene.materials[0].shaderName = "textures/test/unlit";
  scene.materials[0].fromScript = true;
  scene.materials.push_back(q3::WorldMaterial{});   // implicit, vertex lit
  scene.models[0].meshes.push_back(scene.models[0].meshes[0]);
  scene.models[0].meshes[1].material = 1;
  scene.models[0].meshes[1].lightmap = -1;
  for (glm::vec4& c : scene.models[0].meshes[0].colors) c = glm::vec4(0.2f, 0.2f, 0.2f, 0.5f);
  for (glm::vec4& c : scene.models[0].meshes[1].colors) c = glm::vec4(32 / 255.0f, 16 / 255.0f, 8 / 255.0f, 1.0f);
  std::unordered_map<uint32_t, glm::vec3> glow;
  stockWorldLook(scene, library, glow);
  EXPECT_EQ(scene.models[0].meshes[0].colors[0], glm::vec4(1, 1, 1, 0.5f));   // unlit: full bright
  const glm::vec4 shifted = scene.models[0].meshes[1].colors[0];             // x4
  EXPECT_NEAR(shifted.r * 255.0f, 128.0f, 1e-3f);
  EXPECT_NEAR(shifted.g * 255.0f, 64.0f, 1e-3f);
  ASSERT_EQ(glow.count(0), 1u);
  EXPECT_EQ(glow[0], glm::vec3(1, 0, 0));
  EXPECT_EQ(glow.count(1), 0u);
}

TEST(StockSpecular, AlphaIsTheMirroredFixedLightToTheFourthPower) {
  // Straight below the fixed light (-960, 1980, 96), facing up: the light mirrors straight up.
  const glm::vec3 p(-960, 1980, -4), n(0, 0, 1);
  EXPECT_EQ(stockSpecularAlpha(p, n, p + glm::vec3(0, 0, 50)), 255);
  // 60 degrees off the mirror direction: 0.5^4 x 255 = 15.94, truncated.
  EXPECT_EQ(stockSpecularAlpha(p, n, p + 80.0f * glm::vec3(std::sin(kPi / 3), 0, std::cos(kPi / 3))), 15);
  // 45 degrees: 0.25 x 255 = 63.75.
  EXPECT_EQ(stockSpecularAlpha(p, n, p + glm::vec3(0, 30, 30)), 63);
  EXPECT_EQ(stockSpecularAlpha(p, n, p + glm::vec3(0, 0, -10)), 0);   // behind: negative dot
  EXPECT_EQ(stockSpecularAlpha(p, 3.0f * n, p + glm::vec3(0, 0, 50)), 255);   // normal length ignored
}

TEST(StockSpecular, SpecularLayersGetVertexCopiesWithTheirAlpha) {
  GeometryBatch batch;
  const glm::vec3 p(-960, 1980, -4);
  batch.positions = {p, p + glm::vec3(1, 0, 0), p + glm::vec3(0, 1, 0)};
  batch.normals.assign(3, glm::vec3(0, 0, 1));
  batch.uvs = {{0, 0}, {1, 0}, {0, 1}};
  batch.colors.assign(3, glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
  batch.indices = {0, 1, 2, 0, 1, 2};
  batch.triangleShaders = {7, 7};
  batch.triangleLayers = {0, 1};
  const glm::vec3 viewer = p + glm::vec3(0, 0, 50);
  specularAlphaLikeStock([](q3abi::qhandle_t shader, uint32_t layer) { return shader == 7 && layer == 1; }, viewer, batch);
  ASSERT_EQ(batch.positions.size(), 6u);
  EXPECT_EQ(batch.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));   // layer 0 keeps its vertices
  for (uint32_t v = 0; v < 3; ++v) EXPECT_EQ(batch.colors[v].a, 1.0f);
  for (uint32_t v = 3; v < 6; ++v) {
    EXPECT_EQ(batch.positions[v], batch.positions[v - 3]);
    EXPECT_EQ(batch.uvs[v], batch.uvs[v - 3]);
    EXPECT_EQ(glm::vec3(batch.colors[v]), glm::vec3(0.5f));
    EXPECT_EQ(batch.colors[v].a, stockSpecularAlpha(batch.positions[v], glm::vec3(0, 0, 1), viewer) / 255.0f);
  }
  EXPECT_EQ(batch.colors[3].a, 1.0f);   // the vertex right under the light, seen from above
}

TEST(StageLayers, ModelStagesBlendedByTheirOwnAlphaAreFactorLayersInTheLightmapPreset) {
  // OpenArena's health sphere: gl_src_alpha gl_one with a pulsing alpha, then a specular stage.
  const q3::ShaderScript script = q3::parseShaderScript(
      "smallcrossEnv\n{\n cull disable\n { map h.tga\n blendfunc gl_src_alpha gl_one\n tcGen environment\n"
      " alphaGen wave sin 0.3 0.2 0.5 0 }\n { map s.tga\n blendfunc gl_src_alpha gl_one\n tcGen environment\n"
      " alphaGen lightingSpecular }\n}\n",
      "shells.shader");
  ShaderEntry entry;
  entry.name = "smallcrossEnv";
  entry.look = lookOfShader(script.shaders.at(0));
  ASSERT_EQ(entry.look.layers.size(), 1u);
  const ImageTextures textures = [](const std::shared_ptr<const Image>&, bool, bool) { return pa::TextureId(3); };
  const pa::MaterialDesc base = describeStage(entry, entry.look, nullptr, MaterialUse::StockModel, 0, textures);
  EXPECT_EQ(base.alphaMode, pa::AlphaMode::Additive);
  EXPECT_EQ(base.stock.layerBlend, pa::LayerBlend::Factors);
  EXPECT_EQ(base.stock.layerSrcFactor, pa::BlendFactor::SrcAlpha);
  EXPECT_EQ(base.stock.layerDstFactor, pa::BlendFactor::One);
  EXPECT_FALSE(base.vertexAlphaTints);
  EXPECT_TRUE(base.stock.useVertexLight);
  const pa::MaterialDesc spec = describeStage(entry, entry.look.layers[0], nullptr, MaterialUse::StockModel, 1, textures);
  EXPECT_EQ(spec.stock.layerBlend, pa::LayerBlend::Factors);
  EXPECT_TRUE(spec.vertexAlphaTints);   // the specular alpha rides on the vertex copies
  // An alpha-blended model stage is a premultiplied-over layer tinted by its vertex light.
  const q3::ShaderScript blended = q3::parseShaderScript("m\n{\n { map m.tga\n blendfunc blend\n rgbGen lightingDiffuse }\n}\n",
                                                        "m.shader");
  ShaderEntry glass;
  glass.name = "m";
  glass.look = lookOfShader(blended.shaders.at(0));
  const pa::MaterialDesc over = describeStage(glass, glass.look, nullptr, MaterialUse::StockModel, 0, textures);
  EXPECT_EQ(over.alphaMode, pa::AlphaMode::Additive);
  EXPECT_EQ(over.stock.layerBlend, pa::LayerBlend::Over);
  EXPECT_FALSE(over.stock.useVertexLight);
  EXPECT_TRUE(over.vertexColorTints);
  EXPECT_EQ(describeStage(glass, glass.look, nullptr, MaterialUse::Model, 0, textures).alphaMode, pa::AlphaMode::Blend);
  // The traced presets weigh the additive family by its source factor too (the sphere's pulsing
  // alpha and its specular alpha), and keep plain additive stages plain.
  const pa::MaterialDesc traced = describeStage(entry, entry.look, nullptr, MaterialUse::Model, 0, textures);
  EXPECT_EQ(traced.alphaMode, pa::AlphaMode::Additive);
  EXPECT_EQ(traced.stock.layerBlend, pa::LayerBlend::Factors);
  EXPECT_EQ(traced.stock.layerSrcFactor, pa::BlendFactor::SrcAlpha);
  EXPECT_EQ(traced.stock.layerDstFactor, pa::BlendFactor::One);
  EXPECT_FALSE(traced.castsShadows);
  EXPECT_TRUE(describeStage(entry, entry.look.layers[0], nullptr, MaterialUse::Model, 1, textures).vertexAlphaTints);
  const q3::ShaderScript glows = q3::parseShaderScript(
      "g\n{\n { map g.tga\n blendfunc add }\n}\nx\n{\n { map x.tga\n blendfunc gl_one gl_src_alpha }\n}\n", "g.shader");
  ShaderEntry glow, explosion;
  glow.look = lookOfShader(glows.shaders.at(0));
  explosion.look = lookOfShader(glows.shaders.at(1));
  const pa::MaterialDesc plain = describeStage(glow, glow.look, nullptr, MaterialUse::Effect, 0, textures);
  EXPECT_EQ(plain.alphaMode, pa::AlphaMode::Additive);
  EXPECT_EQ(plain.stock.layerBlend, pa::LayerBlend::Add);
  // Effects are unlit in every preset: what keeps part of the framebuffer (dst not GL_ONE) is
  // composed over what is behind it in the traced presets too, as stock composes it.
  for (const MaterialUse use : {MaterialUse::Effect, MaterialUse::StockEffect}) {
    const pa::MaterialDesc fire = describeStage(explosion, explosion.look, nullptr, use, 0, textures);
    EXPECT_TRUE(fire.visible);
    EXPECT_EQ(fire.alphaMode, pa::AlphaMode::Additive);
    EXPECT_EQ(fire.stock.layerBlend, pa::LayerBlend::Factors);
    EXPECT_EQ(fire.stock.layerSrcFactor, pa::BlendFactor::One);
    EXPECT_EQ(fire.stock.layerDstFactor, pa::BlendFactor::SrcAlpha);
  }
}

TEST(StageLayers, EffectsAreComposedLayersInTheTracedPresetsNotStochasticCoverage) {
  // Smoke puffs (blendfunc blend) and impact marks (gl_zero gl_one_minus_src_color) speckled as
  // stochastic coverage at one sample a pixel; as effects they are the stock look's layers.
  const q3::ShaderScript script = q3::parseShaderScript(
      "smoke\n{\n { map s.tga\n blendfunc blend\n rgbGen vertex\n alphaGen vertex }\n}\n"
      "mark\n{\n { map m.tga\n blendfunc gl_zero gl_one_minus_src_color }\n}\n",
      "fx.shader");
  const ImageTextures textures = [](const std::shared_ptr<const Image>&, bool, bool) { return pa::TextureId(3); };
  ShaderEntry smoke, mark;
  smoke.look = lookOfShader(script.shaders.at(0));
  mark.look = lookOfShader(script.shaders.at(1));
  for (const MaterialUse use : {MaterialUse::Effect, MaterialUse::StockEffect}) {
    const pa::MaterialDesc puff = describeStage(smoke, smoke.look, nullptr, use, 0, textures);
    EXPECT_EQ(puff.alphaMode, pa::AlphaMode::Additive);
    EXPECT_EQ(puff.stock.layerBlend, pa::LayerBlend::Over);
    EXPECT_FALSE(puff.castsShadows);
    const pa::MaterialDesc hole = describeStage(mark, mark.look, nullptr, use, 0, textures);
    EXPECT_EQ(hole.alphaMode, pa::AlphaMode::Additive);
    EXPECT_EQ(hole.stock.layerBlend, pa::LayerBlend::MultiplyInverse);
  }
  // A lit model's alpha-blended stage stays stochastic coverage in the traced presets.
  EXPECT_EQ(describeStage(smoke, smoke.look, nullptr, MaterialUse::Model, 0, textures).alphaMode, pa::AlphaMode::Blend);
}

TEST(StageLayers, AModelStageOfItsOwnColourBlendedByItIsALayerInTheTracedPresets) {
  // OpenArena's lightning gun muzzle flash (LightnnFlash: gl_one gl_src_alpha, rgbGen wave) was
  // not drawn by direct/path; a stage coloured by the light keeps the traced handling.
  const q3::ShaderScript script = q3::parseShaderScript(
      "flash\n{\n { map f.tga\n blendfunc gl_one gl_src_alpha\n rgbGen wave inversesawtooth 0 1 0 20 }\n}\n"
      "litFlash\n{\n { map f.tga\n blendfunc gl_one gl_src_alpha\n rgbGen lightingDiffuse }\n}\n",
      "fx.shader");
  const ImageTextures textures = [](const std::shared_ptr<const Image>&, bool, bool) { return pa::TextureId(5); };
  ShaderEntry flash, lit;
  flash.look = lookOfShader(script.shaders.at(0));
  lit.look = lookOfShader(script.shaders.at(1));
  EXPECT_FALSE(lightColouredStage(flash.look));
  EXPECT_TRUE(lightColouredStage(lit.look));
  EXPECT_TRUE(lightColouredStage(ShaderLook{}));   // an implicit shader: lit by the light grid
  const pa::MaterialDesc traced = describeStage(flash, flash.look, nullptr, MaterialUse::Model, 0, textures);
  EXPECT_TRUE(traced.visible);
  EXPECT_EQ(traced.alphaMode, pa::AlphaMode::Additive);
  EXPECT_EQ(traced.stock.layerBlend, pa::LayerBlend::Factors);
  EXPECT_EQ(traced.stock.layerSrcFactor, pa::BlendFactor::One);
  EXPECT_EQ(traced.stock.layerDstFactor, pa::BlendFactor::SrcAlpha);
  EXPECT_FALSE(traced.castsShadows);
  EXPECT_FALSE(describeStage(lit, lit.look, nullptr, MaterialUse::Model, 0, textures).visible);
}

TEST(StageLayers, UnlitModelStagesShowTheirTextureInTheTracedPresets) {
  // OpenArena's medium health cross: an environment-mapped stage with no rgbGen, which the stock
  // renderer draws at the texture's colour; a lightingDiffuse stage stays lit.
  const q3::ShaderScript script = q3::parseShaderScript(
      "mediumCross\n{\n { map c.tga\n tcGen environment }\n { map y.tga\n blendfunc add\n tcGen environment }\n}\n"
      "lit\n{\n { map l.tga\n rgbGen lightingDiffuse }\n}\n"
      "tinted\n{\n { map t.tga\n rgbGen const ( 0.5 0.25 1 ) }\n}\n",
      "fx.shader");
  const ImageTextures textures = [](const std::shared_ptr<const Image>&, bool, bool) { return pa::TextureId(7); };
  ShaderEntry cross, lit, tinted;
  cross.look = lookOfShader(script.shaders.at(0));
  lit.look = lookOfShader(script.shaders.at(1));
  tinted.look = lookOfShader(script.shaders.at(2));
  EXPECT_TRUE(unlitModelStage(cross.look));
  EXPECT_FALSE(unlitModelStage(lit.look));
  ShaderLook implicit;   // a model's texture with no script: lit by the light grid
  EXPECT_FALSE(unlitModelStage(implicit));
  const pa::MaterialDesc shown = describeStage(cross, cross.look, nullptr, MaterialUse::Model, 0, textures);
  EXPECT_EQ(shown.emissiveTexture, pa::TextureId(7));
  EXPECT_EQ(shown.seenEmission, glm::vec3(1.0f));
  EXPECT_EQ(shown.emission, glm::vec3(0.0f));   // lights nothing: no emitter to sample
  EXPECT_EQ(shown.baseColor, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));   // reflects nothing
  EXPECT_EQ(shown.specular, 0.0f);
  EXPECT_EQ(shown.baseTexCoords, pa::TexCoordSource::ReflectionSphere);   // the emission is read there too
  EXPECT_FALSE(shown.emissiveOwnUv);
  const pa::MaterialDesc constant = describeStage(tinted, tinted.look, nullptr, MaterialUse::Model, 0, textures);
  EXPECT_GT(constant.seenEmission.z, constant.seenEmission.x);   // the const colour, linear
  EXPECT_EQ(describeStage(lit, lit.look, nullptr, MaterialUse::Model, 0, textures).seenEmission, glm::vec3(-1.0f));
  // The lightmap preset and effects keep their own looks.
  EXPECT_EQ(describeStage(cross, cross.look, nullptr, MaterialUse::StockModel, 0, textures).seenEmission, glm::vec3(-1.0f));
  EXPECT_EQ(describeStage(cross, cross.look, nullptr, MaterialUse::Effect, 0, textures).seenEmission, glm::vec3(-1.0f));
}

}  // namespace
}  // namespace glue

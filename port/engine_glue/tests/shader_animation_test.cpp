// Shader animation in traced views (shader_animation.h): material fields at a shader time, and a
// small world whose scrolling shader moves its rendered picture as the script says.
#include "port/engine_glue/shader_animation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "port/engine_glue/stock_look.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/world/world_scene.h"
#include "port/scene_bridge/scene_bridge.h"
#include "renderer/scene/renderer.h"

namespace glue {
namespace {

q3::TcMod tcMod(q3::TcModKind kind, float a = 0, float b = 0) {
  q3::TcMod m;
  m.kind = kind;
  m.scroll = {a, b};
  m.degreesPerSecond = a;
  return m;
}

TEST(ShaderAnimation, TcModsBecomeTheUvTransform) {
  pa::MaterialDesc desc;
  // scale 2 1 then rotate 90/s at 1 s: (s, t) -> (2s, t) -> (t, 1 - 2s).
  applyTcMods({tcMod(q3::TcModKind::Scale, 2, 1), tcMod(q3::TcModKind::Rotate, 90)}, 1.0, desc);
  const glm::vec2 uv = desc.uvTransform * glm::vec3(0.25f, 0.75f, 1.0f);
  EXPECT_NEAR(uv.x, 0.75f, 1e-5);   // the stock sin table's entries 768 and 0: -0.9999894, 0
  EXPECT_NEAR(uv.y, 0.5f, 1e-5);
  EXPECT_EQ(desc.uvWobble.amplitude, 0.0f);
}

TEST(ShaderAnimation, TurbBecomesTheStockWobble) {
  q3::TcMod turb;
  turb.kind = q3::TcModKind::Turb;
  turb.wave = {q3::WaveFunc::Sin, 0, 0.1f, 0.25f, 0.5f};   // at 3 s: 1.75 cycles
  pa::MaterialDesc desc;
  applyTcMods({turb, tcMod(q3::TcModKind::Scale, 2, 2)}, 3.0, desc);
  EXPECT_NEAR(desc.uvWobble.amplitude, 0.1f, 1e-7);
  EXPECT_NEAR(desc.uvWobble.phase, 0.75f, 1e-6);
  // Vertex (256, 512, 256): s and t read 1.25 cycles -> offset 0.1 each, doubled by the scale.
  const glm::vec2 offset = desc.uvWobble.offsetAt({256, 512, 256});
  EXPECT_NEAR(offset.x, 0.2f, 1e-5);
  EXPECT_NEAR(offset.y, 0.2f, 1e-5);
}

TEST(ShaderAnimation, RgbWaveScalesTheColourByItsGreyByte) {
  StageMotion motion;
  motion.rgbGen = q3::RgbGen::Wave;
  motion.rgbWave = {q3::WaveFunc::Sin, 0.5f, 0.5f, 0, 1};
  pa::MaterialDesc still;
  still.baseColor = glm::vec4(1.0f, 0.5f, 0.25f, 0.75f);
  EXPECT_TRUE(motion.timeDependent());
  // Level 0.5 + 0.5 x 0.9999988 (sin table entry 256) -> byte trunc(254.9998) = 254, as stock.
  const pa::MaterialDesc peak = materialAt(motion, 0.25, still);
  EXPECT_NEAR(peak.baseColor.r, byteToLinear(254.0f), 1e-6);
  EXPECT_NEAR(peak.baseColor.g, 0.5f * byteToLinear(254.0f), 1e-6);
  EXPECT_FLOAT_EQ(peak.baseColor.a, 0.75f);
  const pa::MaterialDesc middle = materialAt(motion, 0.0, still);  // level 0.5 -> byte 127
  EXPECT_NEAR(middle.baseColor.r, byteToLinear(127.0f), 1e-6);
  EXPECT_NEAR(middle.baseColor.b, 0.25f * byteToLinear(127.0f), 1e-6);
  EXPECT_NEAR(materialAt(motion, 0.75, still).baseColor.r, 0.0f, 1e-6);
}

TEST(ShaderAnimation, AlphaWaveSetsCoverageAndPremultipliedColour) {
  StageMotion motion;
  motion.alphaGen = q3::AlphaGen::Wave;
  motion.alphaWave = {q3::WaveFunc::Sawtooth, 0, 1, 0, 1};
  pa::MaterialDesc blended;
  blended.alphaMode = pa::AlphaMode::Blend;
  const float level = 512.0f / 1024.0f;   // sawtooth at 0.5 s
  EXPECT_NEAR(materialAt(motion, 0.5, blended).baseColor.a, level, 1e-6);
  EXPECT_NEAR(materialAt(motion, 0.5, blended).baseColor.r, 1.0f, 1e-6);
  pa::MaterialDesc premultiplied;
  premultiplied.alphaMode = pa::AlphaMode::Additive;
  premultiplied.stock.layerBlend = pa::LayerBlend::Over;
  // The layer is composed in display values: the colour takes the linearised alpha, so that its
  // display value is about c x alpha; the coverage takes the alpha itself.
  EXPECT_NEAR(materialAt(motion, 0.5, premultiplied).baseColor.r, byteToLinear(level * 255.0f), 1e-6);
  EXPECT_NEAR(materialAt(motion, 0.5, premultiplied).baseColor.a, level, 1e-6);
}

TEST(ShaderAnimation, GlowWaveScalesEmission) {
  StageMotion motion;
  motion.glowWaves = true;
  motion.glowWave = {q3::WaveFunc::Square, 0.5f, 0.5f, 0, 1};
  pa::MaterialDesc still;
  still.emission = glm::vec3(2.0f);
  EXPECT_NEAR(materialAt(motion, 0.25, still).emission.x, 2.0f, 1e-6);   // level 1
  EXPECT_NEAR(materialAt(motion, 0.75, still).emission.x, 0.0f, 1e-6);   // level 0
}

TEST(ShaderAnimation, GlowTcModsMoveTheEmissiveTextureOnItsOwn) {
  StageMotion motion;
  motion.glowTcMods = {tcMod(q3::TcModKind::Scroll, 0.25f, 0.5f)};
  motion.glowOwnUv = true;
  EXPECT_TRUE(motion.timeDependent());
  pa::MaterialDesc still;
  still.baseTexture = 0;
  still.emissiveTexture = 0;   // the base's image on uvs of its own (lava at two scales)
  const pa::MaterialDesc moved = materialAt(motion, 3.0, still);   // scroll (0.75, 0.5)
  EXPECT_TRUE(moved.emissiveOwnUv);
  const glm::vec2 uv = moved.emissiveUvTransform * glm::vec3(0.1f, 0.2f, 1.0f);
  EXPECT_NEAR(uv.x, 0.85f, 1e-6);
  EXPECT_NEAR(uv.y, 0.7f, 1e-6);
  EXPECT_EQ(moved.uvTransform, still.uvTransform);   // the base stays
  motion.glowOwnUv = false;   // the glow reads the base's uvs (same tcMods): nothing to move apart
  EXPECT_FALSE(materialAt(motion, 3.0, still).emissiveOwnUv);
}

TEST(ShaderAnimation, StaticTransformsDoNotAnimate) {
  StageMotion motion;
  motion.tcMods = {tcMod(q3::TcModKind::Scale, 2, 2)};
  EXPECT_FALSE(motion.timeDependent());
  EXPECT_TRUE(motion.any());
  motion.tcMods.push_back(tcMod(q3::TcModKind::Scroll, 0.1f, 0));
  EXPECT_TRUE(motion.timeDependent());
}

TEST(ShaderAnimation, MaterialPoolKeepsOneMaterialPerShaderTimeInAView) {
  pa::Renderer renderer{pa::RendererConfig{1}};
  StageMotion motion;
  motion.tcMods = {tcMod(q3::TcModKind::Scroll, 0.25f, 0)};
  MovingMaterialPool pool;
  size_t updates = 0;
  const pa::MaterialDesc still;
  const pa::MaterialId a = pool.get(motion, still, 1.0, {0, 0}, 1, renderer, updates);
  EXPECT_EQ(pool.get(motion, still, 1.0, {0, 0}, 1, renderer, updates), a);   // same time, same view
  const pa::MaterialId b = pool.get(motion, still, 2.0, {0, 0}, 1, renderer, updates);
  EXPECT_NE(a, b);                                                            // another entity's time
  EXPECT_EQ(updates, 0u);
  // The next view reuses both, replacing them only when their time changed.
  const pa::MaterialId c = pool.get(motion, still, 3.0, {0, 0}, 2, renderer, updates);
  EXPECT_EQ(c, a);
  EXPECT_EQ(updates, 1u);
  EXPECT_EQ(pool.get(motion, still, 2.0, {0, 0}, 2, renderer, updates), b);
  EXPECT_EQ(updates, 1u);
  EXPECT_NE(pool.get(motion, still, 2.0, {0.5f, 0}, 2, renderer, updates), b);   // another scroll speed
}

/// A world of one 20 x 20 quad facing +X whose material is the script `shader`, textured with a
/// 20 x 1 map (texels 0-9 red, 10-19 green), seen head-on from 2 units (u 0.4 .. 0.6 in view).
struct ScriptedWorld {
  pa::Renderer renderer{pa::RendererConfig{2}};
  q3::WorldScene scene;
  q3::ShaderLibrary library;
  pa::bridge::WorldHandles handles;
  WorldAnimation animation;
  std::vector<uint8_t> pixels;

  /// `glowOfBaseImage`: the material glows with its base image (a glow stage of the same map).
  explicit ScriptedWorld(const std::string& shader, bool glowOfBaseImage = false) {
    library.addScript(shader, "test.shader");
    q3::WorldMaterial material;
    material.shaderName = "textures/test/belt";
    material.fromScript = true;
    material.baseTexture = 0;
    if (glowOfBaseImage) material.emissiveTexture = 0;
    material.vertexLit = true;
    scene.materials.push_back(material);
    for (int x = 0; x < 20; ++x) pixels.insert(pixels.end(), {uint8_t(x < 10 ? 255 : 0), uint8_t(x < 10 ? 0 : 255), 0, 255});
    pa::TextureDesc texture;
    texture.width = 20;
    texture.height = 1;
    texture.rgba8 = pixels;
    texture.mipmaps = false;
    handles.textures.push_back(renderer.addTexture(texture));
    const pa::MaterialId id = renderer.addMaterial(pa::bridge::materialDesc(scene, handles, 0, -1));
    handles.materials[{0u, -1}] = id;
    pa::MeshDesc mesh;
    const std::vector<glm::vec3> positions = {{0, -10, -10}, {0, 10, -10}, {0, 10, 10}, {0, -10, 10}};
    const std::vector<glm::vec2> uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const std::vector<glm::vec4> colors(4, glm::vec4(1.0f));
    const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
    const std::vector<pa::MaterialId> materials(2, id);
    mesh.positions = positions;
    mesh.uvs = uvs;
    mesh.colors = colors;
    mesh.indices = indices;
    mesh.materials = materials;
    renderer.addInstance(pa::InstanceDesc{renderer.addMesh(mesh)});
    animation.prepare(scene, library, handles, renderer, [](const std::string&, bool) { return pa::kNoId; });
  }
  /// The left and right columns of the picture at shader time `seconds`.
  std::pair<glm::vec3, glm::vec3> at(double seconds) {
    animation.update(seconds, renderer);
    renderer.commit();
    pa::Camera camera;
    camera.origin = {2, 0, 0};
    camera.forward = {-1, 0, 0};
    camera.left = {0, -1, 0};
    camera.up = {0, 0, 1};
    pa::RenderSettings settings;
    settings.width = settings.height = 8;
    settings.integrator = pa::Integrator::Lightmap;
    settings.samplesPerPixel = 1;
    const pa::FrameView frame = renderer.render(camera, settings);
    glm::vec3 left(0.0f), right(0.0f);
    for (uint32_t y = 0; y < 8; ++y) {
      left += frame.radiance[y * 8] / 8.0f;
      right += frame.radiance[y * 8 + 7] / 8.0f;
    }
    return {left, right};
  }
};

bool isRed(glm::vec3 c) { return c.r > 0.9f && c.g < 0.1f; }
bool isGreen(glm::vec3 c) { return c.g > 0.9f && c.r < 0.1f; }

TEST(ShaderAnimation, ScrollingWorldShaderMovesThePicture) {
  ScriptedWorld world("textures/test/belt\n{\n{\nmap belt.tga\ntcMod scroll 0.25 0\n}\n}\n");
  EXPECT_EQ(world.animation.animatedCount(), 1u);
  auto [left, right] = world.at(0.0);
  EXPECT_TRUE(isRed(left)) << left.r << " " << left.g;
  EXPECT_TRUE(isGreen(right)) << right.r << " " << right.g;
  // 2 s: u + 0.5 -> left reads 0.91 (green), right 0.09 after the wrap (red).
  std::tie(left, right) = world.at(2.0);
  EXPECT_EQ(world.animation.lastUpdates(), 1u);
  EXPECT_TRUE(isGreen(left)) << left.r << " " << left.g;
  EXPECT_TRUE(isRed(right)) << right.r << " " << right.g;
  // 4 s: a whole texture width -> as at 0 s.
  std::tie(left, right) = world.at(4.0);
  EXPECT_TRUE(isRed(left));
  EXPECT_TRUE(isGreen(right));
  // The same time again changes nothing.
  world.at(4.0);
  EXPECT_EQ(world.animation.lastUpdates(), 0u);
}

TEST(ShaderAnimation, StillWorldShadersCostNothingPerFrame) {
  ScriptedWorld world("textures/test/belt\n{\n{\nmap belt.tga\ntcMod scale 2 1\n}\n}\n");
  EXPECT_EQ(world.animation.animatedCount(), 0u);
  // The static scale is applied once: u 0.8 .. 1.2 -> left 0.82 green, right 1.18 = 0.18 red.
  const auto [left, right] = world.at(1.0);
  EXPECT_EQ(world.animation.lastUpdates(), 0u);
  EXPECT_TRUE(isGreen(left));
  EXPECT_TRUE(isRed(right));
}

TEST(ShaderAnimation, AGlowStageOfTheBaseImageReadsItsOwnUvs) {
  // Lava: one image drawn twice, the glow stage scrolling (half a width at 1 s). Left column:
  // base red (u 0.4) plus the glow at u 0.9 (green) = yellow; with the base's uvs it would stay red.
  ScriptedWorld world("textures/test/belt\n{\n{\nmap belt.tga\n}\n{\nmap belt.tga\nblendfunc add\ntcMod scroll 0.5 0\n}\n}\n",
                      true);
  const auto [left, right] = world.at(1.0);
  EXPECT_GT(left.r, 0.9f);
  EXPECT_GT(left.g, 0.9f);
  EXPECT_GT(right.r, 0.9f);
  EXPECT_GT(right.g, 0.9f);
  // The same glow on the base's uvs (same tcMods as the base) adds the same colour.
  ScriptedWorld same("textures/test/belt\n{\n{\nmap belt.tga\n}\n{\nmap belt.tga\nblendfunc add\n}\n}\n", true);
  const auto [sameLeft, sameRight] = same.at(0.0);
  EXPECT_TRUE(isRed(sameLeft)) << sameLeft.r << " " << sameLeft.g;
  EXPECT_TRUE(isGreen(sameRight));
}

}  // namespace
}  // namespace glue

// Scene assembly on a synthetic map: materials from scripts and implicit shaders, fallbacks,
// mesh grouping and winding, sub-models, sky + sun, surface lights, hostile surfaces.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/world/world_lights.h"
#include "port/q3formats/world/world_source.h"

namespace q3 {
namespace {

std::vector<std::byte> pngOf(int w, int h, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
  std::vector<uint8_t> pixels;
  for (int i = 0; i < w * h; ++i) {
    pixels.push_back(r);
    pixels.push_back(g);
    pixels.push_back(b);
    pixels.push_back(a);
  }
  std::vector<std::byte> png;
  stbi_write_png_to_func(
      [](void* ctx, void* data, int size) {
        auto* out = static_cast<std::vector<std::byte>*>(ctx);
        out->insert(out->end(), static_cast<std::byte*>(data), static_cast<std::byte*>(data) + size);
      },
      &png, w, h, 4, pixels.data(), w * 4);
  return png;
}

constexpr const char* kScript = R"(
textures/test/wall
{
  { map $lightmap rgbGen identity }
  { map textures/test/wall.tga blendFunc filter }
}
textures/test/glass
{
  surfaceparm trans
  cull none
  { map textures/test/wall.tga blendFunc blend }
}
textures/test/lamp
{
  q3map_surfacelight 1000
  q3map_lightRGB 1 0.5 0.25
  { map $lightmap }
  { map textures/test/wall.tga blendFunc filter }
}
textures/skies/test
{
  surfaceparm sky
  surfaceparm noimpact
  q3map_sun 1 1 0.5 100 90 60
  skyparms env/test - -
}
textures/test/lampimage
{
  q3map_surfacelight 500
  q3map_lightimage textures/test/implicit.tga
  { map textures/test/wall.tga }
}
textures/test/lampmissing
{
  q3map_surfacelight 500
  q3map_lightimage textures/test/absent.tga
  qer_editorimage textures/test/absent_too.tga
  { map textures/test/wall.tga }
}
textures/test/shine
{
  { map textures/test/wall.tga rgbGen identity }
  { map textures/test/wall.tga blendfunc filter }
  { map $lightmap blendfunc filter }
}
textures/test/terrain
{
  { map textures/test/wall.tga rgbGen identity }
  { map textures/test/shadow.tga blendfunc filter tcMod scale .2 .2 tcMod scroll -0.15 0.15 }
  { map $lightmap blendfunc filter }
}
textures/test/pad
{
  { map textures/test/wall.tga tcMod scroll 0 1 }
  { map textures/test/shadow.tga blendFunc blend tcMod scale 2 2 }
  { map $lightmap blendfunc filter }
}
textures/test/tinted
{
  surfaceparm trans
  { map textures/test/wall.tga blendFunc filter }
}
textures/test/padmissing
{
  { map textures/test/wall.tga }
  { map textures/test/absent.tga blendFunc blend }
  { map $lightmap blendfunc filter }
}
textures/common/nodraw
{
  surfaceparm nodraw
  surfaceparm nonsolid
}
)";

SourceSurface quad(uint32_t shader, int32_t lightmap, uint32_t model, float z) {
  SourceSurface s;
  s.shader = shader;
  s.lightmap = lightmap;
  s.model = model;
  s.positions = {{0, 0, z}, {64, 0, z}, {64, 64, z}, {0, 64, z}};
  s.normals.assign(4, glm::vec3(0, 0, 1));
  s.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  s.lightmapUvs = s.uvs;
  s.colors.assign(4, glm::vec4(1));
  s.indices = {0, 1, 2, 0, 2, 3};   // counter-clockwise seen from +Z
  return s;
}

class WorldBuilderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    library_.addScript(kScript, "scripts/test.shader");
    files_["textures/test/wall.jpg"] = pngOf(4, 4, 200, 100, 50, 255);   // stb sniffs the content
    files_["textures/test/implicit.png"] = pngOf(2, 2, 10, 20, 30, 255);
    files_["textures/test/shadow.png"] = pngOf(2, 2, 100, 100, 100, 255);
    for (const char* face : {"rt", "bk", "lf", "ft", "up", "dn"})
      files_[std::string("env/test_") + face + ".tga"] = pngOf(2, 2, 0, 0, 255, 255);
    loader_ = [this](std::string_view path) -> std::optional<std::vector<std::byte>> {
      auto it = files_.find(std::string(path));
      if (it == files_.end()) return std::nullopt;
      return it->second;
    };
    source_.mapName = "maps/test.bsp";
    source_.shaders = {{"textures/test/wall", 0, 1}, {"textures/test/missing", 0, 1}, {"textures/test/glass", 0, 1},
                       {"textures/test/lamp", 0, 1}, {"textures/skies/test", 4, 1}, {"textures/common/nodraw", 0x80, 0},
                       {"textures/test/implicit", 0, 1}, {"textures/test/lampimage", 0, 1},
                       {"textures/test/lampmissing", 0, 1}, {"textures/test/shine", 0, 1},
                       {"textures/test/terrain", 0, 1}, {"textures/test/pad", 0, 1},
                       {"textures/test/padmissing", 0, 1}, {"textures/test/tinted", 0, 1}};
    source_.modelBounds = {{{0, 0, 0}, {64, 64, 64}}, {{0, 0, 100}, {64, 64, 101}}};
    source_.lightmaps.resize(2);
    source_.lightmaps[0].fill(64);
    source_.lightmaps[1].fill(128);
  }

  WorldScene build() { return assembleWorldScene(source_, library_, loader_); }

  const WorldMaterial* materialNamed(const WorldScene& scene, const std::string& name) {
    for (const auto& m : scene.materials)
      if (m.shaderName == name) return &m;
    return nullptr;
  }

  ShaderLibrary library_;
  std::map<std::string, std::vector<std::byte>> files_;
  FileLoader loader_;
  SourceWorld source_;
};

TEST_F(WorldBuilderTest, GroupsSurfacesByMaterialAndLightmapPerModel) {
  source_.surfaces = {quad(0, 0, 0, 0), quad(0, 0, 0, 8), quad(0, 1, 0, 16), quad(0, 0, 1, 100)};
  WorldScene scene = build();
  ASSERT_EQ(scene.models.size(), 2u);
  ASSERT_EQ(scene.models[0].meshes.size(), 2u);   // (wall, lm0) merged, (wall, lm1)
  const WorldMesh& merged = scene.models[0].meshes[0];
  EXPECT_EQ(merged.lightmap, 0);
  EXPECT_EQ(merged.sourceSurfaces, 2u);
  EXPECT_EQ(merged.positions.size(), 8u);
  ASSERT_EQ(merged.indices.size(), 12u);
  EXPECT_EQ(merged.indices[0], 0u);   // kept as given
  EXPECT_EQ(merged.indices[1], 1u);
  EXPECT_EQ(merged.indices[2], 2u);
  EXPECT_EQ(merged.indices[6], 4u);   // second surface offset by 4 vertices
  EXPECT_EQ(merged.bounds.maxs.z, 8.0f);
  EXPECT_EQ(scene.models[0].meshes[1].lightmap, 1);
  ASSERT_EQ(scene.models[1].meshes.size(), 1u);
  EXPECT_EQ(scene.models[1].bounds.mins.z, 100.0f);
  ASSERT_EQ(scene.lightmaps.size(), 2u);
  EXPECT_EQ(scene.lightmaps[1].rgba8[0], 128);
  EXPECT_EQ(scene.lightmaps[1].rgba8[3], 255);
}

TEST_F(WorldBuilderTest, ScriptMaterialResolvesTextureWithExtensionFallback) {
  source_.surfaces = {quad(0, 0, 0, 0), quad(2, 0, 0, 0)};
  WorldScene scene = build();
  const WorldMaterial* wall = materialNamed(scene, "textures/test/wall");
  ASSERT_NE(wall, nullptr);
  EXPECT_TRUE(wall->fromScript);
  ASSERT_GE(wall->baseTexture, 0);
  const WorldTexture& tex = scene.textures[size_t(wall->baseTexture)];
  EXPECT_EQ(tex.resolvedPath, "textures/test/wall.jpg");   // .tga asked, .jpg found
  EXPECT_FALSE(tex.isFallback);
  EXPECT_EQ(tex.image.width, 4u);
  EXPECT_EQ(wall->alphaMode, WorldAlphaMode::Opaque);
  const WorldMaterial* glass = materialNamed(scene, "textures/test/glass");
  ASSERT_NE(glass, nullptr);
  EXPECT_EQ(glass->alphaMode, WorldAlphaMode::Blend);
  EXPECT_TRUE(glass->twoSided);
  EXPECT_EQ(glass->baseTexture, wall->baseTexture);   // shared texture
  EXPECT_TRUE(scene.warnings.empty());
}

TEST_F(WorldBuilderTest, MissingShaderGetsFallbackTextureAndWarningImplicitShaderItsImage) {
  source_.surfaces = {quad(1, 0, 0, 0), quad(6, 0, 0, 0)};
  WorldScene scene = build();
  const WorldMaterial* missing = materialNamed(scene, "textures/test/missing");
  ASSERT_NE(missing, nullptr);
  ASSERT_GE(missing->baseTexture, 0);
  EXPECT_TRUE(scene.textures[size_t(missing->baseTexture)].isFallback);
  EXPECT_EQ(scene.textures[size_t(missing->baseTexture)].image.width, 64u);
  ASSERT_FALSE(scene.warnings.empty());
  EXPECT_NE(scene.warnings[0].find("textures/test/missing"), std::string::npos);
  const WorldMaterial* implicit = materialNamed(scene, "textures/test/implicit");
  ASSERT_NE(implicit, nullptr);
  EXPECT_FALSE(implicit->fromScript);
  EXPECT_EQ(scene.textures[size_t(implicit->baseTexture)].resolvedPath, "textures/test/implicit.png");
}

TEST_F(WorldBuilderTest, SurfaceLightColourComesFromTheFirstLightImageThatLoads) {
  source_.surfaces = {quad(7, 0, 0, 0), quad(8, 0, 0, 8)};
  WorldScene scene = build();
  const WorldMaterial* lamp = materialNamed(scene, "textures/test/lampimage");
  const WorldMaterial* missing = materialNamed(scene, "textures/test/lampmissing");
  ASSERT_NE(lamp, nullptr);
  ASSERT_NE(missing, nullptr);
  // q3map_lightimage (10, 20, 30): bluish, not the wall's orange.
  EXPECT_GT(lamp->emission.b, lamp->emission.g);
  EXPECT_GT(lamp->emission.g, lamp->emission.r);
  // Light image and editor image missing, no image by the shader's name: the stage image
  // (200, 100, 50), orange; never the fallback checker's colour.
  EXPECT_GT(missing->emission.r, missing->emission.g);
  EXPECT_GT(missing->emission.g, missing->emission.b);
  EXPECT_FLOAT_EQ(missing->emission.r, lamp->emission.b);   // both normalised to a maximum of 1
}

TEST_F(WorldBuilderTest, FilterStageOfTheSameImageSquaresTheBaseTexture) {
  source_.surfaces = {quad(9, 0, 0, 0), quad(0, 0, 0, 8)};
  WorldScene scene = build();
  const WorldMaterial* shine = materialNamed(scene, "textures/test/shine");
  const WorldMaterial* wall = materialNamed(scene, "textures/test/wall");
  ASSERT_NE(shine, nullptr);
  ASSERT_NE(wall, nullptr);
  ASSERT_NE(shine->baseTexture, wall->baseTexture);
  const WorldImage& squared = scene.textures.at(size_t(shine->baseTexture)).image;
  ASSERT_EQ(squared.rgba8.size(), 4u * 4u * 4u);
  // (200, 100, 50)^2 / 255 in 8-bit display values; the wall's own texture is untouched.
  EXPECT_EQ(std::vector<uint8_t>(squared.rgba8.begin(), squared.rgba8.begin() + 4), (std::vector<uint8_t>{157, 39, 10, 255}));
  EXPECT_EQ(scene.textures.at(size_t(wall->baseTexture)).image.rgba8[0], 200);
}

TEST_F(WorldBuilderTest, FilterStageOnItsOwnUvsDarkensTheBaseByItsMean) {
  source_.surfaces = {quad(10, 0, 0, 0)};
  WorldScene scene = build();
  const WorldMaterial* terrain = materialNamed(scene, "textures/test/terrain");
  ASSERT_NE(terrain, nullptr);
  const WorldImage& darkened = scene.textures.at(size_t(terrain->baseTexture)).image;
  ASSERT_EQ(darkened.rgba8.size(), 4u * 4u * 4u);
  // (200, 100, 50) x 100 / 255 for every texel, in 8-bit display values.
  for (size_t i = 0; i < darkened.rgba8.size(); i += 4)
    EXPECT_EQ(std::vector<uint8_t>(darkened.rgba8.begin() + i, darkened.rgba8.begin() + i + 4),
              (std::vector<uint8_t>{78, 39, 20, 255}));
}

TEST_F(WorldBuilderTest, AlphaBlendedStageBeforeTheLightmapIsTheCover) {
  source_.surfaces = {quad(11, 0, 0, 0), quad(12, 0, 0, 8)};
  WorldScene scene = build();
  const WorldMaterial* pad = materialNamed(scene, "textures/test/pad");
  ASSERT_NE(pad, nullptr);
  ASSERT_GE(pad->coverTexture, 0);
  EXPECT_EQ(scene.textures.at(size_t(pad->coverTexture)).image.rgba8.at(0), 100);   // shadow.png
  ASSERT_EQ(pad->coverTcMods.size(), 1u);
  EXPECT_EQ(pad->coverTcMods[0].kind, TcModKind::Scale);
  EXPECT_FALSE(pad->coverVertexAlpha);
  // A cover image that does not load is left out (not the fallback checker), with a warning.
  const WorldMaterial* missing = materialNamed(scene, "textures/test/padmissing");
  ASSERT_NE(missing, nullptr);
  EXPECT_EQ(missing->coverTexture, -1);
  EXPECT_TRUE(std::any_of(scene.warnings.begin(), scene.warnings.end(), [](const std::string& w) {
    return w.find("cover image 'textures/test/absent.tga' not found") != std::string::npos;
  }));
}

TEST_F(WorldBuilderTest, FilterGlassMultipliesWhatIsBehindAndCastsNoShadow) {
  source_.surfaces = {quad(13, 0, 0, 0)};
  WorldScene scene = build();
  const WorldMaterial* tinted = materialNamed(scene, "textures/test/tinted");
  ASSERT_NE(tinted, nullptr);
  EXPECT_EQ(tinted->alphaMode, WorldAlphaMode::Filter);
  EXPECT_EQ(tinted->filterBlend, FilterBlend::Multiply);
  EXPECT_FALSE(tinted->castsShadows);
}

TEST_F(WorldBuilderTest, SkyShaderGivesSkyBoxAndSun) {
  source_.surfaces = {quad(0, 0, 0, 0), quad(4, -1, 0, 64)};
  WorldScene scene = build();
  EXPECT_EQ(scene.sky.shaderName, "textures/skies/test");
  for (int f = 0; f < 6; ++f) ASSERT_GE(scene.sky.faces[size_t(f)], 0) << f;
  EXPECT_EQ(scene.textures[size_t(scene.sky.faces[0])].resolvedPath, "env/test_rt.tga");   // +X
  EXPECT_EQ(scene.textures[size_t(scene.sky.faces[1])].resolvedPath, "env/test_lf.tga");   // -X (stock)
  EXPECT_EQ(scene.textures[size_t(scene.sky.faces[2])].resolvedPath, "env/test_bk.tga");   // +Y (stock)
  EXPECT_EQ(scene.textures[size_t(scene.sky.faces[5])].resolvedPath, "env/test_dn.tga");   // -Z
  const WorldTexture& up = scene.textures[size_t(scene.sky.faces[4])];   // +Z: a copy turned 180 degrees
  EXPECT_EQ(up.resolvedPath, "env/test_up.tga");
  EXPECT_NE(up.requestedPath.find("turned 180"), std::string::npos);
  EXPECT_NEAR(scene.sky.color.b, 1.0f, 1e-4f);
  ASSERT_EQ(scene.lights.size(), 1u);
  const WorldLight& sun = scene.lights[0];
  EXPECT_EQ(sun.type, WorldLightType::Sun);
  EXPECT_FLOAT_EQ(sun.intensity, sunIrradiance(100.0f));
  // Azimuth 90, elevation 60: the sun is up along +Y; its light travels -(0, cos60, sin60).
  EXPECT_NEAR(sun.direction.x, 0.0f, 1e-5f);
  EXPECT_NEAR(sun.direction.y, -0.5f, 1e-5f);
  EXPECT_NEAR(sun.direction.z, -std::sqrt(3.0f) / 2.0f, 1e-5f);
  EXPECT_EQ(sun.color, glm::vec3(1.0f, 1.0f, 0.5f));
  const WorldMaterial* sky = materialNamed(scene, "textures/skies/test");
  ASSERT_NE(sky, nullptr);
  EXPECT_TRUE(sky->sky);
  EXPECT_FALSE(sky->castsShadows);
}

TEST_F(WorldBuilderTest, SurfaceLightAndNodraw) {
  source_.surfaces = {quad(3, 0, 0, 0), quad(5, -1, 0, 0)};
  WorldScene scene = build();
  const WorldMaterial* lamp = materialNamed(scene, "textures/test/lamp");
  ASSERT_NE(lamp, nullptr);
  EXPECT_FLOAT_EQ(lamp->surfaceLight, 1000.0f);
  EXPECT_EQ(lamp->emission, glm::vec3(1.0f, 0.5f, 0.25f));
  // The nodraw surface is dropped: only the lamp's mesh remains.
  ASSERT_EQ(scene.models[0].meshes.size(), 1u);
  EXPECT_EQ(scene.materials[scene.models[0].meshes[0].material].shaderName, "textures/test/lamp");
}

TEST_F(WorldBuilderTest, HostileSurfacesAreSkippedWithWarnings) {
  SourceSurface nan = quad(0, 0, 0, 0);
  nan.positions[1].x = std::nanf("");
  SourceSurface badIndex = quad(0, 0, 0, 0);
  badIndex.indices = {0, 1, 99, 0, 0, 1};   // out of range and degenerate
  SourceSurface mismatched = quad(0, 0, 0, 0);
  mismatched.normals.pop_back();
  SourceSurface externalLightmap = quad(0, 7, 0, 0);   // beyond the lump
  source_.surfaces = {nan, badIndex, mismatched, externalLightmap};
  WorldScene scene = build();
  ASSERT_EQ(scene.models[0].meshes.size(), 1u);
  EXPECT_EQ(scene.models[0].meshes[0].lightmap, -1);   // drawn vertex-lit
  EXPECT_EQ(scene.models[0].meshes[0].indices.size(), 6u);
  EXPECT_EQ(scene.warnings.size(), 3u);   // non-finite, mismatched arrays, external lightmap
}

}  // namespace
}  // namespace q3

// Known-answer tests of the module's own pure functions (shader looks, video modes, presets).
#include <gtest/gtest.h>

#include <GL/gl.h>

#include "port/engine_glue/settings.h"
#include "port/engine_glue/shader_scripts.h"
#include "port/engine_glue/window.h"

namespace glue {
namespace {

TEST(ShaderScripts, FirstDefinitionWinsAndFirstVisibleStageIsTheLook) {
  ShaderScripts scripts;
  scripts.addScript(
      "textures/base/light\n{\n surfaceparm nomarks\n q3map_surfacelight 400 // glow\n"
      " {\n  map $lightmap\n  rgbGen identity\n }\n"
      " {\n  map textures/base/light.tga\n  blendFunc GL_DST_COLOR GL_ZERO\n  alphaFunc GE128\n }\n}\n"
      "/* comment */ textures/base/light { { map other.tga } }\n"
      "gfx/2d/menu\n{\n nopicmip\n {\n  animMap 5 a.tga b.tga c.tga\n  blendFunc blend\n  rgbGen vertex\n }\n}\n"
      "textures/skies/sky\n{\n surfaceparm sky\n surfaceparm noimpact\n}\n");
  EXPECT_EQ(scripts.size(), 3u);
  const auto light = scripts.find("TEXTURES/base/light.tga");
  ASSERT_TRUE(light);
  ASSERT_EQ(light->images.size(), 1u);
  EXPECT_EQ(light->images[0], "textures/base/light.tga");
  EXPECT_EQ(light->blend.src, unsigned(GL_DST_COLOR));
  EXPECT_EQ(light->blend.dst, unsigned(GL_ZERO));
  EXPECT_EQ(light->alphaTest, AlphaTest::Ge128);
  EXPECT_FLOAT_EQ(light->surfaceLight, 400.0f);
  const auto menu = scripts.find("gfx/2d/menu");
  ASSERT_TRUE(menu);
  EXPECT_EQ(menu->images.size(), 3u);
  EXPECT_FLOAT_EQ(menu->animFrequency, 5.0f);
  EXPECT_TRUE(menu->vertexColor);
  EXPECT_EQ(menu->blend.src, unsigned(GL_SRC_ALPHA));
  const auto sky = scripts.find("textures/skies/sky");
  ASSERT_TRUE(sky);
  EXPECT_TRUE(sky->sky);
  EXPECT_FALSE(scripts.find("textures/none"));
}

TEST(ShaderScripts, AdditiveShadersKeepLaterGlowStagesAsLayersAndTheirColours) {
  ShaderScripts scripts;
  scripts.addScript(
      "cmuz_flash\n{\n deformVertexes autosprite\n"
      " {\n  map muz3.tga\n  blendfunc add\n  rgbGen const ( 1 0.5 0.25 )\n }\n"
      " {\n  map muz6.tga\n  blendfunc add\n  rgbGen const ( 0.5 0.25 0 )\n }\n"
      " {\n  map env.tga\n  blendfunc add\n  tcGen environment\n }\n}\n"
      "opaque\n{\n {\n  map a.tga\n }\n {\n  map b.tga\n  blendfunc add\n }\n}\n");
  const auto flash = scripts.find("cmuz_flash");
  ASSERT_TRUE(flash);
  EXPECT_TRUE(flash->autosprite);
  EXPECT_EQ(flash->rgbGen, q3::RgbGen::Const);
  EXPECT_FLOAT_EQ(flash->constColor[1], 0.5f);
  ASSERT_EQ(flash->layers.size(), 2u);   // the environment stage is a layer read at the reflection
  EXPECT_FALSE(flash->layers[0].reflectionUv);
  EXPECT_TRUE(flash->layers[1].reflectionUv);
  EXPECT_EQ(flash->layers[1].images[0], "env.tga");
  EXPECT_EQ(flash->layers[0].images[0], "muz6.tga");
  EXPECT_FLOAT_EQ(flash->layers[0].constColor[0], 0.5f);
  EXPECT_EQ(flash->layers[0].blend.dst, unsigned(GL_ONE));
  const auto opaque = scripts.find("opaque");
  ASSERT_TRUE(opaque);
  EXPECT_TRUE(opaque->layers.empty());   // only additive shaders get layers
  EXPECT_FALSE(opaque->autosprite);
}

TEST(ShaderScripts, MalformedScriptsAreSkippedWhole) {
  ShaderScripts scripts;
  EXPECT_FALSE(scripts.addScript("textures/a/ok { { map ok.tga } }\nbroken\n{\n { map x.tga\n"));
  EXPECT_TRUE(scripts.addScript("\"quoted name\" { { map y.tga } }"));
  scripts.addScript("/* never closed");
  EXPECT_FALSE(scripts.find("textures/a/ok"));   // the engine ignores the whole broken file
  EXPECT_TRUE(scripts.find("quoted name"));
}

TEST(VideoModes, StockTable) {
  int w = 0, h = 0;
  ASSERT_TRUE(stockVideoMode(3, w, h));
  EXPECT_EQ(w, 640);
  EXPECT_EQ(h, 480);
  ASSERT_TRUE(stockVideoMode(12, w, h));
  EXPECT_EQ(w, 1280);
  EXPECT_EQ(h, 720);
  ASSERT_TRUE(stockVideoMode(28, w, h));
  EXPECT_EQ(w, 3840);
  EXPECT_FALSE(stockVideoMode(29, w, h));
  EXPECT_FALSE(stockVideoMode(-1, w, h));
}

TEST(Presets, Names) {
  bool known = false;
  EXPECT_EQ(parsePreset("Lightmap", known), Preset::Lightmap);
  EXPECT_TRUE(known);
  EXPECT_EQ(parsePreset("reference", known), Preset::Reference);
  EXPECT_EQ(parsePreset("fast", known), Preset::Path);
  EXPECT_FALSE(known);
  EXPECT_STREQ(presetName(Preset::Direct), "direct");
}

TEST(TextureModes, StockNames) {
  bool known = false;
  using F = pa::TextureFilter;
  using M = pa::MipFilter;
  EXPECT_EQ(parseTextureMode("GL_LINEAR_MIPMAP_NEAREST", known), (F{M::Nearest, false}));
  EXPECT_TRUE(known);
  EXPECT_EQ(parseTextureMode("gl_linear_mipmap_linear", known), (F{M::Linear, false}));
  EXPECT_EQ(parseTextureMode("GL_NEAREST_MIPMAP_LINEAR", known), (F{M::Linear, true}));
  EXPECT_EQ(parseTextureMode("GL_NEAREST_MIPMAP_NEAREST", known), (F{M::Nearest, true}));
  EXPECT_EQ(parseTextureMode("GL_NEAREST", known), (F{M::None, true}));
  EXPECT_EQ(parseTextureMode("GL_LINEAR", known), (F{M::None, false}));
  EXPECT_TRUE(known);
  EXPECT_EQ(parseTextureMode("GL_ANISOTROPIC", known), (F{M::Nearest, false}));   // the stock default
  EXPECT_FALSE(known);
}

}  // namespace
}  // namespace glue

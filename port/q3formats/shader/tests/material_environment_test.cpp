// deriveMaterial on tcGen environment stages: which stage becomes the base and whether its
// texture is read as a reflection sphere map (MaterialInfo::baseReflects).
#include <gtest/gtest.h>

#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_parser.h"

namespace {

using namespace q3;

MaterialInfo material(const char* text) {
  auto script = parseShaderScript(text, "env.shader");
  EXPECT_EQ(script.shaders.size(), 1u);
  EXPECT_TRUE(script.warnings.empty());
  return deriveMaterial(script.shaders.at(0));
}

TEST(MaterialEnvironment, SingleEnvironmentStageIsAReflectingBase) {
  // models/powerups/holdable/medkit_base
  auto m = material(R"(medkit { { map textures/base_wall/chrome_env.jpg tcGen environment
    rgbGen lightingDiffuse tcMod scale .5 .5 } })");
  EXPECT_EQ(m.baseTexture, "textures/base_wall/chrome_env.jpg");
  EXPECT_TRUE(m.baseReflects);
  EXPECT_TRUE(m.environmentMapped);
  EXPECT_EQ(m.alphaMode, AlphaMode::Opaque);
  EXPECT_EQ(m.lighting, LightingMode::Diffuse);
  EXPECT_EQ(m.reflectionOverlay, "");   // nothing drawn over the chrome
  ASSERT_EQ(m.uvAnimation.size(), 1u);   // the stage's tcMods apply after the reflection lookup
  const UvAffine uv = uvTransformAt(m.uvAnimation, 0.0);
  EXPECT_FLOAT_EQ(uv.a, 0.5f);
  EXPECT_FLOAT_EQ(uv.d, 0.5f);
}

TEST(MaterialEnvironment, OpaqueEnvironmentStageOverwritesEarlierStages) {
  // textures/base_wall/bluemetalsupport2e (oa_rpg3dm2's wall panels): the second stage writes
  // without blending, so the first never shows; the third adds a texture; the lightmap filters both.
  auto m = material(R"(panel { { map panel.tga rgbGen identity }
    { map chrome_env.jpg tcGen environment rgbGen oneminusvertex tcmod scale .5 .5 }
    { map panel.tga blendFunc add rgbGen identity } { map $lightmap blendFunc filter rgbGen identity } })");
  EXPECT_EQ(m.baseTexture, "chrome_env.jpg");
  EXPECT_TRUE(m.baseReflects);
  EXPECT_EQ(m.lighting, LightingMode::Lightmap);
  // The added texture is multiplied by the lightmap after it: lit, not a glow.
  EXPECT_TRUE(m.glowTextures.empty());
  EXPECT_FALSE(m.emissive);
  EXPECT_EQ(m.reflectionOverlay, "panel.tga");   // what the panel shows under its sheen
  // textures/base_floor/hfloor3: the lightmap multiplies with DST_COLOR ONE_MINUS_SRC_ALPHA.
  auto floor = material(R"(hfloor3 { { map hfloor3.jpg rgbGen identity }
    { map tinfx.jpg tcGen environment rgbGen oneminusvertex } { map hfloor3.jpg blendfunc add }
    { map $lightmap blendfunc gl_dst_color gl_one_minus_src_alpha tcGen lightmap } })");
  EXPECT_TRUE(floor.baseReflects);
  EXPECT_EQ(floor.reflectionOverlay, "hfloor3.jpg");
  EXPECT_TRUE(floor.glowTextures.empty());   // lit by that lightmap too: not a glow
  // An unlit additive stage over chrome is a glow, not the surface's texture.
  auto glowing = material(R"(tele { { map env.tga tcGen environment } { map swirl.tga blendFunc add } })");
  EXPECT_EQ(glowing.reflectionOverlay, "");
  // An additive stage after the lightmap filter still glows.
  auto glow = material(R"(g { { map $lightmap } { map w.tga blendFunc filter } { map g.tga blendFunc add } })");
  ASSERT_EQ(glow.glowTextures.size(), 1u);
  EXPECT_EQ(glow.glowTextures[0], "g.tga");
}

TEST(MaterialEnvironment, AdditiveEnvironmentOverABaseKeepsTheBase) {
  // textures/base_floor/metfloor1: a faint chrome sheen added over the floor texture.
  auto m = material(R"(floor { { map metfloor1.tga rgbGen const ( 1 1 1 ) }
    { clampmap chrome_env2.tga blendfunc add rgbGen const ( 0.19 0.19 0.19 ) tcGen environment }
    { map $lightmap blendfunc filter tcGen lightmap } })");
  EXPECT_EQ(m.baseTexture, "metfloor1.tga");
  EXPECT_FALSE(m.baseReflects);
  EXPECT_TRUE(m.environmentMapped);
  EXPECT_TRUE(m.glowTextures.empty());   // environment stages are no glows
}

TEST(MaterialEnvironment, AlphaBlendedTextureOverChromeStaysTheBase) {
  // textures/base_light/xlight5: chrome behind a texture with holes: one base texture, the
  // texture (it covers most of the surface).
  auto m = material(R"(light { { map envmap2.tga rgbGen identity tcGen environment }
    { map xlight5.tga blendfunc gl_one gl_one_minus_src_alpha rgbGen identity }
    { map $lightmap blendfunc filter tcGen lightmap } { map xlight5.blend.tga blendfunc add } })");
  EXPECT_EQ(m.baseTexture, "xlight5.tga");
  EXPECT_FALSE(m.baseReflects);
  auto blend = material("b { { map env.tga tcGen environment } { map skin.tga blendFunc blend } }");
  EXPECT_EQ(blend.baseTexture, "skin.tga");
  EXPECT_FALSE(blend.baseReflects);
}

TEST(MaterialEnvironment, AdditiveEnvironmentOnlyShaderReflects) {
  // Teleporter / powerup glows: nothing but additive chrome.
  auto m = material("glow { { map fx.tga blendFunc add tcGen environment } { map fx2.tga blendFunc add tcGen environment } }");
  EXPECT_EQ(m.baseTexture, "fx.tga");
  EXPECT_TRUE(m.baseReflects);
  EXPECT_EQ(m.alphaMode, AlphaMode::Additive);
}

TEST(MaterialEnvironment, LaterOpaquePlainStageWins) {
  auto m = material("flag { { map env.tga tcGen environment } { map cloth.tga } }");
  EXPECT_EQ(m.baseTexture, "cloth.tga");
  EXPECT_FALSE(m.baseReflects);
  auto plain = material("w { { map $lightmap } { map w.tga blendFunc filter } }");
  EXPECT_FALSE(plain.baseReflects);
}

}  // namespace

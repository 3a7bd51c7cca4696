#include "port/q3formats/shader/shader_parser.h"

#include <gtest/gtest.h>

#include "port/q3formats/common/format_error.h"

namespace {

using namespace q3;

constexpr const char* kScript = R"(
// a lit wall with a glow
textures/base/light1
{
	qer_editorimage textures/base/light1.tga
	surfaceparm nomarks
	surfaceparm NoLightmap
	q3map_surfacelight 2500
	q3map_lightimage textures/base/light1_blend.tga
	cull disable
	{
		map $lightmap
		rgbGen identity
	}
	{
		map textures/base/light1.tga
		blendFunc GL_DST_COLOR GL_ZERO
		rgbGen identity
	}
	{
		animMap 4 textures/a1.tga textures/a2.tga textures/a3.tga
		blendFunc add
		rgbGen wave sin 0.5 0.25 0 1
		tcMod scroll 0.5 -1
		tcMod rotate 30
	}
}

/* a sky */
textures/skies/sky1
{
	surfaceparm sky
	surfaceparm noimpact
	q3map_sun 1 .9 .8 120 45 60
	skyparms env/sky1 512 -
	{
		map textures/skies/clouds.tga
		tcMod scale 3 2
		tcMod turb 0 0.1 0 0.2
	}
}
)";

TEST(ShaderParser, ParsesGeneralKeywordsAndStages) {
  ShaderScript script = parseShaderScript(kScript, "test.shader");
  ASSERT_EQ(script.shaders.size(), 2u);
  EXPECT_TRUE(script.warnings.empty()) << script.warnings[0].message;

  const ShaderDef& light = script.shaders[0];
  EXPECT_EQ(light.name, "textures/base/light1");
  EXPECT_EQ(light.line, 3);
  EXPECT_TRUE(light.has(SurfaceParm::NoMarks));
  EXPECT_TRUE(light.has(SurfaceParm::NoLightmap));
  EXPECT_FALSE(light.has(SurfaceParm::Sky));
  EXPECT_FLOAT_EQ(light.surfaceLight, 2500);
  EXPECT_EQ(light.lightImage, "textures/base/light1_blend.tga");
  EXPECT_EQ(light.editorImage, "textures/base/light1.tga");
  EXPECT_EQ(light.cull, CullMode::TwoSided);
  ASSERT_EQ(light.stages.size(), 3u);
  EXPECT_EQ(light.stages[0].source, TextureSource::Lightmap);
  EXPECT_EQ(light.stages[0].rgbGen, RgbGen::Identity);
  EXPECT_EQ(light.stages[1].textures[0], "textures/base/light1.tga");
  EXPECT_EQ(light.stages[1].srcBlend, BlendFactor::DstColor);
  EXPECT_EQ(light.stages[1].dstBlend, BlendFactor::Zero);
  const ShaderStage& glow = light.stages[2];
  ASSERT_EQ(glow.textures.size(), 3u);
  EXPECT_EQ(glow.textures[2], "textures/a3.tga");
  EXPECT_FLOAT_EQ(glow.animFrequency, 4);
  EXPECT_EQ(glow.srcBlend, BlendFactor::One);
  EXPECT_EQ(glow.dstBlend, BlendFactor::One);
  EXPECT_EQ(glow.rgbGen, RgbGen::Wave);
  EXPECT_FLOAT_EQ(glow.rgbWave.base, 0.5f);
  EXPECT_FLOAT_EQ(glow.rgbWave.amplitude, 0.25f);
  EXPECT_FLOAT_EQ(glow.rgbWave.frequency, 1);
  ASSERT_EQ(glow.tcMods.size(), 2u);
  EXPECT_EQ(glow.tcMods[0].kind, TcModKind::Scroll);
  EXPECT_FLOAT_EQ(glow.tcMods[0].scroll[1], -1);
  EXPECT_FLOAT_EQ(glow.tcMods[1].degreesPerSecond, 30);

  const ShaderDef& sky = script.shaders[1];
  EXPECT_TRUE(sky.has(SurfaceParm::Sky));
  ASSERT_TRUE(sky.sun);
  EXPECT_FLOAT_EQ(sky.sun->color[1], 0.9f);
  EXPECT_FLOAT_EQ(sky.sun->intensity, 120);
  EXPECT_FLOAT_EQ(sky.sun->degrees, 45);
  EXPECT_FLOAT_EQ(sky.sun->elevation, 60);
  ASSERT_TRUE(sky.sky);
  EXPECT_EQ(sky.sky->farBox, "env/sky1");
  EXPECT_FLOAT_EQ(sky.sky->cloudHeight, 512);
  EXPECT_EQ(sky.sky->nearBox, "");
  ASSERT_EQ(sky.stages[0].tcMods.size(), 2u);
  EXPECT_EQ(sky.stages[0].tcMods[1].kind, TcModKind::Turb);
  EXPECT_FLOAT_EQ(sky.stages[0].tcMods[1].wave.amplitude, 0.1f);
}

TEST(ShaderParser, ExplicitBlendFactorsAlphaFuncAndGens) {
  auto script = parseShaderScript(R"(s {
    { clampMap a.tga
      blendFunc GL_SRC_ALPHA GL_ONE_MINUS_SRC_ALPHA
      alphaFunc LT128
      depthFunc equal
      depthWrite
      detail
      rgbGen const ( 0.25 0.5 1 )
      alphaGen const 0.3
      tcGen vector ( 0.01 0 0 ) ( 0 0.02 0 )
      tcMod transform 1 0.5 0 1 0.25 0
      tcMod stretch sin 1 0.1 0 0.5
    }
    { map $whiteimage
      alphaGen portal 512
      tcGen environment
      rgbGen oneMinusEntity }
  })",
                                  "t.shader");
  ASSERT_EQ(script.shaders.size(), 1u);
  EXPECT_TRUE(script.warnings.empty());
  const auto& s0 = script.shaders[0].stages[0];
  EXPECT_TRUE(s0.clamp);
  EXPECT_TRUE(s0.blends());
  EXPECT_EQ(s0.srcBlend, BlendFactor::SrcAlpha);
  EXPECT_EQ(s0.dstBlend, BlendFactor::OneMinusSrcAlpha);
  EXPECT_EQ(s0.alphaTest, AlphaTest::Lt128);
  EXPECT_TRUE(s0.depthEqual);
  EXPECT_TRUE(s0.depthWrite);
  EXPECT_TRUE(s0.detail);
  EXPECT_EQ(s0.rgbGen, RgbGen::Const);
  EXPECT_FLOAT_EQ(s0.constColor[0], 0.25f);
  EXPECT_FLOAT_EQ(s0.constColor[2], 1.0f);
  EXPECT_FLOAT_EQ(s0.constAlpha, 0.3f);
  EXPECT_EQ(s0.tcGen, TcGen::Vector);
  EXPECT_FLOAT_EQ(s0.tcGenVectors[1][1], 0.02f);
  EXPECT_FLOAT_EQ(s0.tcMods[0].matrix[1], 0.5f);
  EXPECT_FLOAT_EQ(s0.tcMods[0].translate[0], 0.25f);
  EXPECT_EQ(s0.tcMods[1].wave.func, WaveFunc::Sin);
  const auto& s1 = script.shaders[0].stages[1];
  EXPECT_EQ(s1.source, TextureSource::WhiteImage);
  EXPECT_EQ(s1.alphaGen, AlphaGen::Portal);
  EXPECT_FLOAT_EQ(s1.portalRange, 512);
  EXPECT_EQ(s1.tcGen, TcGen::Environment);
  EXPECT_EQ(s1.rgbGen, RgbGen::OneMinusEntity);
}

TEST(ShaderParser, DeformsSortFogPortalCull) {
  auto script = parseShaderScript(R"(a {
    deformVertexes wave 100 sin 3 5 0.1 0.5
    deformVertexes move 0 0 4 sin 0 1 0 0.2
    deformVertexes autosprite2
    deformVertexes text3
    sort underwater
    fogparms ( .5 .2 .1 ) 300
    portal
    polygonOffset
    cull back
  }
  b { sort 12 cull twosided }
  )",
                                  "t.shader");
  ASSERT_EQ(script.shaders.size(), 2u);
  EXPECT_TRUE(script.warnings.empty());
  const auto& a = script.shaders[0];
  ASSERT_EQ(a.deforms.size(), 4u);
  EXPECT_EQ(a.deforms[0].kind, DeformKind::Wave);
  EXPECT_FLOAT_EQ(a.deforms[0].spread, 100);
  EXPECT_FLOAT_EQ(a.deforms[0].wave.frequency, 0.5f);
  EXPECT_EQ(a.deforms[1].kind, DeformKind::Move);
  EXPECT_FLOAT_EQ(a.deforms[1].params[2], 4);
  EXPECT_EQ(a.deforms[2].kind, DeformKind::AutoSprite2);
  EXPECT_EQ(a.deforms[3].textIndex, 3);
  EXPECT_FLOAT_EQ(*a.sort, sort_key::Underwater);
  ASSERT_TRUE(a.fog);
  EXPECT_FLOAT_EQ(a.fog->color[0], 0.5f);
  EXPECT_FLOAT_EQ(a.fog->depthForOpaque, 300);
  EXPECT_TRUE(a.portal);
  EXPECT_TRUE(a.polygonOffset);
  EXPECT_EQ(a.cull, CullMode::BackSided);
  EXPECT_FLOAT_EQ(*script.shaders[1].sort, 12);
  EXPECT_EQ(script.shaders[1].cull, CullMode::TwoSided);
}

TEST(ShaderParser, UnknownKeywordsAreCollectedOncePerKeyword) {
  auto script = parseShaderScript(R"(a {
    frobnicate 1 2 3
    surfaceparm wibble
    { map x.tga
      frobnicate
      tcMod wobble 1 }
  }
  b { frobnicate }
  )",
                                  "t.shader");
  ASSERT_EQ(script.shaders.size(), 2u);
  int frob = 0;
  for (const auto& w : script.warnings) {
    EXPECT_TRUE(w.unknownKeyword);
    if (w.keyword == "frobnicate") {
      ++frob;
      EXPECT_EQ(w.count, 3);
      EXPECT_EQ(w.line, 2);
    }
  }
  EXPECT_EQ(frob, 1);
  EXPECT_EQ(script.warnings[1].keyword, "surfaceparm wibble");
  EXPECT_EQ(script.warnings[2].keyword, "tcmod wobble");
  EXPECT_EQ(script.warnings.size(), 3u);  // frobnicate, wibble, tcmod wobble
  EXPECT_EQ(script.shaders[0].stages.size(), 1u);
  EXPECT_EQ(script.shaders[0].unknownKeywords, 4);
  EXPECT_EQ(script.shaders[1].unknownKeywords, 1);
}

TEST(ShaderParser, BadArgumentsWarnWithoutThrowing) {
  auto script = parseShaderScript("a { q3map_surfacelight bright\n { map\n blendFunc GL_FOO GL_ZERO } }", "t.shader");
  ASSERT_EQ(script.shaders.size(), 1u);
  EXPECT_FLOAT_EQ(script.shaders[0].surfaceLight, 0);
  ASSERT_EQ(script.warnings.size(), 3u);
  EXPECT_EQ(script.warnings[0].keyword, "q3map_surfacelight");
  EXPECT_FALSE(script.warnings[0].unknownKeyword);
  EXPECT_EQ(script.shaders[0].stages[0].srcBlend, BlendFactor::One);  // the engine's fallback
}

TEST(ShaderParser, BraceOnTheSameLineEndsTheArguments) {
  auto script = parseShaderScript("a { cull none }\nb { { map x.tga } }", "t.shader");
  ASSERT_EQ(script.shaders.size(), 2u);
  EXPECT_EQ(script.shaders[0].cull, CullMode::TwoSided);
  EXPECT_EQ(script.shaders[1].stages.at(0).textures.at(0), "x.tga");
}

TEST(ShaderParser, StructuralErrorsThrowWithFileAndLine) {
  try {
    parseShaderScript("good { }\n\nbad {\n { map x.tga }\n", "broken.shader");
    FAIL() << "expected FormatError";
  } catch (const FormatError& e) {
    EXPECT_EQ(e.file(), "broken.shader");
    EXPECT_NE(std::string(e.what()).find("'bad' (line 3)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseShaderScript("name without brace", "x.shader"), FormatError);
  EXPECT_THROW(parseShaderScript("a { { map x.tga", "x.shader"), FormatError);
  EXPECT_NO_THROW(parseShaderScript("", "empty.shader"));
  EXPECT_NO_THROW(parseShaderScript("// only a comment", "c.shader"));
}

TEST(ShaderParser, AnimMapKeepsAtMostEightFrames) {
  auto script = parseShaderScript("a { { animMap 10 1 2 3 4 5 6 7 8 9 10 } }", "t.shader");
  EXPECT_EQ(script.shaders[0].stages[0].textures.size(), 8u);
  EXPECT_EQ(script.warnings.size(), 2u);
}

TEST(ShaderParser, WaveEvaluation) {
  WaveForm w{WaveFunc::Sin, 1, 2, 0, 1};
  EXPECT_NEAR(w.evaluate(0.25), 3.0, 1e-5);
  w.func = WaveFunc::Square;
  EXPECT_FLOAT_EQ(w.evaluate(0.75), -1);
  w.func = WaveFunc::Triangle;
  EXPECT_NEAR(w.evaluate(0.5), 1.0, 1e-5);
  w.func = WaveFunc::Sawtooth;
  EXPECT_NEAR(w.evaluate(0.25), 1.5, 1e-5);
  w.func = WaveFunc::InverseSawtooth;
  EXPECT_NEAR(w.evaluate(0.25), 2.5, 1e-5);
}

}  // namespace

// Known-answer tests of the 2D stage colours and texture transforms (overlay_stages.h), on
// stages parsed from script text the way the module reads them.
#include <gtest/gtest.h>

#include <cmath>

#include "port/engine_glue/overlay_stages.h"
#include "port/engine_glue/shader_scripts.h"

namespace glue {
namespace {

/// The stages of a one-shader script.
std::vector<q3::ShaderStage> stagesOf(const std::string& body) {
  ShaderScripts scripts;
  EXPECT_TRUE(scripts.addScript("gfx/test\n{\n" + body + "}\n"));
  const auto look = scripts.find("gfx/test");
  EXPECT_TRUE(look);
  return look ? look->stages : std::vector<q3::ShaderStage>{};
}

const Rgba kSetColor{0.2f, 0.4f, 0.6f, 0.5f};

TEST(OverlayStages, EveryStageIsKeptInOrderAndLightmapStagesAreNotDrawn) {
  const auto stages = stagesOf(
      " { map $lightmap }\n {\n  map a.tga\n  blendFunc GL_DST_COLOR GL_SRC_COLOR\n }\n { videoMap intro.roq }\n");
  ASSERT_EQ(stages.size(), 3u);
  EXPECT_FALSE(stageDraws2D(stages[0]));
  EXPECT_TRUE(stageDraws2D(stages[1]));
  EXPECT_EQ(glBlendFactor(stages[1].srcBlend), 0x0306u);   // GL_DST_COLOR
  EXPECT_EQ(glBlendFactor(stages[1].dstBlend), 0x0300u);   // GL_SRC_COLOR
  EXPECT_FALSE(stageDraws2D(stages[2]));
}

TEST(OverlayStages, IdentityAndConstIgnoreSetColorAndAreOpaque) {
  const auto stages = stagesOf(" { map a.tga }\n {\n  map a.tga\n  rgbGen const ( 0.25 0.5 0.75 )\n }\n");
  ASSERT_EQ(stages.size(), 2u);
  EXPECT_EQ(stageColor2D(stages[0], kSetColor, 0.0), (Rgba{1, 1, 1, 1}));
  EXPECT_EQ(stageColor2D(stages[1], kSetColor, 0.0), (Rgba{0.25f, 0.5f, 0.75f, 1}));
}

TEST(OverlayStages, VertexKeepsSetColorAlphaButExactVertexDoesNot) {
  // Stock: alphaGen identity keeps the colour source's alpha only for rgbGen vertex.
  const auto stages = stagesOf(" {\n  map a.tga\n  rgbGen vertex\n }\n {\n  map a.tga\n  rgbGen exactVertex\n }\n"
                               " {\n  map a.tga\n  rgbGen oneMinusVertex\n  alphaGen vertex\n }\n");
  ASSERT_EQ(stages.size(), 3u);
  EXPECT_EQ(stageColor2D(stages[0], kSetColor, 0.0), kSetColor);
  EXPECT_EQ(stageColor2D(stages[1], kSetColor, 0.0), (Rgba{0.2f, 0.4f, 0.6f, 1}));
  const Rgba inverse = stageColor2D(stages[2], kSetColor, 0.0);
  EXPECT_FLOAT_EQ(inverse[0], 0.8f);
  EXPECT_FLOAT_EQ(inverse[1], 0.6f);
  EXPECT_FLOAT_EQ(inverse[2], 0.4f);
  EXPECT_FLOAT_EQ(inverse[3], 0.5f);
}

TEST(OverlayStages, WavesAreEvaluatedAtTheTimeAndClamped) {
  // sin base 0.5 amplitude 1 at 1 Hz: 0.5 + sin(2 pi t) -> 1.5 at t = 0.25 (clamped to 1),
  // 0.5 at t = 0.5, -0.5 at t = 0.75 (clamped to 0).
  const auto stages = stagesOf(" {\n  map a.tga\n  rgbGen wave sin 0.5 1 0 1\n  alphaGen wave sin 0.5 0.25 0 1\n }\n");
  ASSERT_EQ(stages.size(), 1u);
  EXPECT_FLOAT_EQ(stageColor2D(stages[0], kSetColor, 0.25)[0], 1.0f);
  EXPECT_NEAR(stageColor2D(stages[0], kSetColor, 0.5)[1], 0.5f, 1e-2f);
  EXPECT_FLOAT_EQ(stageColor2D(stages[0], kSetColor, 0.75)[2], 0.0f);
  EXPECT_NEAR(stageColor2D(stages[0], kSetColor, 0.25)[3], 0.75f, 1e-2f);
  const auto constAlpha = stagesOf(" {\n  map a.tga\n  blendFunc blend\n  alphaGen const 0.3\n }\n");
  ASSERT_EQ(constAlpha.size(), 1u);
  EXPECT_FLOAT_EQ(stageColor2D(constAlpha[0], kSetColor, 0.0)[3], 0.3f);
}

TEST(OverlayStages, TcModsScrollAndScaleTheTextureCoordinates) {
  // menuback's second stage: scroll, then scale (stock applies tcMods in order).
  const auto stages = stagesOf(" {\n  map a.tga\n  tcMod scroll -0.04 0.1\n  tcMod scale -1.1 0.8\n }\n");
  ASSERT_EQ(stages.size(), 1u);
  const q3::UvAffine uv = stageUvTransform2D(stages[0], 2.5);
  // scroll at 2.5 s: (-0.1, 0.25) -> fractions (0.9, 0.25); then scale: (-0.99, 0.2) at s = t = 0.
  const auto origin = uv.apply(0.0f, 0.0f);
  EXPECT_NEAR(origin[0], 0.9f * -1.1f, 1e-5f);
  EXPECT_NEAR(origin[1], 0.25f * 0.8f, 1e-5f);
  const auto corner = uv.apply(1.0f, 1.0f);
  EXPECT_NEAR(corner[0], (1.0f + 0.9f) * -1.1f, 1e-5f);
  EXPECT_NEAR(corner[1], (1.0f + 0.25f) * 0.8f, 1e-5f);
}

}  // namespace
}  // namespace glue

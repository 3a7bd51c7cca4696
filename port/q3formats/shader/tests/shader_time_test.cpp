// Known answers for shader time as the stock renderer evaluates it: values worked out by hand
// from the 1024-entry tables (entry trunc(cycles x 1024) mod 1024; the sin table holds
// sin(i x 360 / 1023 degrees), so entry 256 is 0.9999988, not 1).
#include "port/q3formats/shader/shader_time.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "port/q3formats/shader/shader_parser.h"

namespace q3 {
namespace {

TcMod scrollMod(float s, float t) {
  TcMod m;
  m.kind = TcModKind::Scroll;
  m.scroll = {s, t};
  return m;
}

TcMod scaleMod(float s, float t) {
  TcMod m;
  m.kind = TcModKind::Scale;
  m.scroll = {s, t};
  return m;
}

TcMod rotateMod(float degreesPerSecond) {
  TcMod m;
  m.kind = TcModKind::Rotate;
  m.degreesPerSecond = degreesPerSecond;
  return m;
}

std::array<float, 2> at(const TcModsAt& mods, float s, float t, float x = 0, float y = 0, float z = 0) {
  const auto uv = mods.affine.apply(s, t);
  const auto wobble = mods.wobble.offsetAt(x, y, z);
  return {uv[0] + wobble[0], uv[1] + wobble[1]};
}

TEST(ShaderTime, WaveTablesAreReadAtTruncatedEntries) {
  EXPECT_NEAR(waveTableValue(WaveFunc::Sin, 0.25), 0.9999988f, 1e-7);   // entry 256: sin(90.088 degrees)
  EXPECT_NEAR(waveTableValue(WaveFunc::Sin, 0.1), 0.5862936f, 1e-6);     // entry 102: sin(35.894 degrees)
  EXPECT_NEAR(waveTableValue(WaveFunc::Sin, -0.25), -0.9999894f, 1e-6);  // -256 & 1023 = 768
  EXPECT_NEAR(waveTableValue(WaveFunc::Sin, 3.25), 0.9999988f, 1e-7);    // periodic
  EXPECT_EQ(waveTableValue(WaveFunc::Sin, 0.0), 0.0f);
  EXPECT_FLOAT_EQ(waveTableValue(WaveFunc::Square, 0.49), 1.0f);
  EXPECT_FLOAT_EQ(waveTableValue(WaveFunc::Square, 0.5), -1.0f);
  EXPECT_FLOAT_EQ(waveTableValue(WaveFunc::Triangle, 0.125), 0.5f);      // rising: 4x
  EXPECT_NEAR(waveTableValue(WaveFunc::Triangle, 0.3), 0.80078125f, 1e-6);  // entry 307: 2 - 4x
  EXPECT_FLOAT_EQ(waveTableValue(WaveFunc::Triangle, 0.625), -0.5f);     // second half negated
  EXPECT_NEAR(waveTableValue(WaveFunc::Sawtooth, 0.3), 0.2998046875f, 1e-7);   // 307 / 1024
  EXPECT_NEAR(waveTableValue(WaveFunc::InverseSawtooth, 0.3), 0.7001953125f, 1e-7);
  // trunc, not floor: just below zero reads entry 0 (a floor would read 1023).
  EXPECT_FLOAT_EQ(waveTableValue(WaveFunc::Sawtooth, -0.0001), 0.0f);
}

TEST(ShaderTime, WaveFormEvaluatesThroughTheTables) {
  const WaveForm w{WaveFunc::Sin, 1, 2, 0.05f, 0.5f};   // base + amp * sin(phase + t * freq)
  EXPECT_NEAR(w.evaluate(0.1), 1 + 2 * 0.5862936f, 1e-5);
  const WaveForm saw{WaveFunc::Sawtooth, 0, 1, 0, 1};
  EXPECT_NEAR(saw.evaluate(2.3), 0.2998046875f, 1e-6);
}

TEST(ShaderTime, NoiseIsContinuousAndBounded) {
  for (int i = -4; i < 4; ++i) {
    const float a = waveNoise(i), b = waveNoise(i + 1);
    EXPECT_GE(a, -1.0f);
    EXPECT_LE(a, 1.0f);
    EXPECT_NEAR(waveNoise(i + 0.25), a + (b - a) * 0.25f, 1e-6);   // linear between whole values
  }
  EXPECT_NE(waveNoise(0), waveNoise(1));
  EXPECT_EQ(waveNoise(7.5), waveNoise(7.5));
}

TEST(ShaderTime, ScrollKeepsTheFraction) {
  const auto uv = at(tcModsAt({scrollMod(0.25f, -0.5f)}, 3.0), 0.1f, 0.2f);
  EXPECT_NEAR(uv[0], 0.1f + 0.75f, 1e-6);   // 0.75
  EXPECT_NEAR(uv[1], 0.2f + 0.5f, 1e-6);    // -1.5 - floor(-1.5) = 0.5
}

TEST(ShaderTime, ScaleMultiplies) {
  const auto uv = at(tcModsAt({scaleMod(2, 3)}, 5.0), 0.5f, 0.25f);
  EXPECT_NEAR(uv[0], 1.0f, 1e-6);
  EXPECT_NEAR(uv[1], 0.75f, 1e-6);
}

TEST(ShaderTime, RotateReadsTheSinTable) {
  // 90 degrees/s at 1 s: -90 degrees = entry -256 -> sin(entry 768) ~ -1, cos (entry 0) 0: (s, t) -> (t, 1 - s).
  auto uv = at(tcModsAt({rotateMod(90)}, 1.0), 1.0f, 0.5f);
  EXPECT_NEAR(uv[0], 0.5f, 1e-5);
  EXPECT_NEAR(uv[1], 0.0f, 1e-5);
  // 30 degrees/s at 0.5 s: -15 degrees = entry trunc(-42.67) = -42: sin = entry 982, cos = entry 214.
  uv = at(tcModsAt({rotateMod(30)}, 0.5), 1.0f, 0.0f);
  EXPECT_NEAR(uv[0], 0.8590684f, 1e-5);
  EXPECT_NEAR(uv[1], -0.1082344f, 1e-5);
  const auto centre = at(tcModsAt({rotateMod(30)}, 0.5), 0.5f, 0.5f);
  EXPECT_NEAR(centre[0], 0.5f, 1e-6);
  EXPECT_NEAR(centre[1], 0.5f, 1e-6);
}

TEST(ShaderTime, StretchScalesAboutTheCentreByTheInverseWave) {
  TcMod m;
  m.kind = TcModKind::Stretch;
  m.wave = {WaveFunc::Sin, 1, 0.5f, 0, 1};   // 1.5 at 0.25 s -> p = 2/3
  const auto uv = at(tcModsAt({m}, 0.25), 1.0f, 0.0f);
  EXPECT_NEAR(uv[0], 2.0f / 3 + 0.5f - 1.0f / 3, 1e-6);
  EXPECT_NEAR(uv[1], 0.5f - 1.0f / 3, 1e-6);
}

TEST(ShaderTime, TransformIsTheScriptMatrix) {
  TcMod m;
  m.kind = TcModKind::Transform;
  m.matrix = {1, 2, 3, 4};   // m00 m01 m10 m11
  m.translate = {5, 6};
  const auto uv = at(tcModsAt({m}, 7.0), 1.0f, 2.0f);
  EXPECT_NEAR(uv[0], 1 * 1 + 2 * 3 + 5, 1e-5);   // s m00 + t m10 + t0
  EXPECT_NEAR(uv[1], 1 * 2 + 2 * 4 + 6, 1e-5);   // s m01 + t m11 + t1
}

TEST(ShaderTime, TurbWobblesPerVertexAndLaterModsMoveTheWobble) {
  TcMod turb;
  turb.kind = TcModKind::Turb;
  turb.wave = {WaveFunc::Sin, 0, 0.1f, 0.25f, 0.5f};   // at 1 s: phase 0.75 cycles
  // Vertex (256, 512, 256): s reads (256 + 256) / 1024 + 0.75 = 1.25 -> sin 1, t reads 512/1024 + 0.75 -> 1.
  auto uv = at(tcModsAt({turb}, 1.0), 0.5f, 0.5f, 256, 512, 256);
  EXPECT_NEAR(uv[0], 0.6f, 1e-6);
  EXPECT_NEAR(uv[1], 0.6f, 1e-6);
  // Vertex (0, 256, 0): s reads 0.75 -> entry 768 (-0.9999894), t reads 1.0 -> entry 0 (0).
  uv = at(tcModsAt({turb}, 1.0), 0.5f, 0.5f, 0, 256, 0);
  EXPECT_NEAR(uv[0], 0.5f - 0.09999894f, 1e-6);
  EXPECT_NEAR(uv[1], 0.5f, 1e-6);
  // A scale after the turb scales the wobbled uv: (0.6, 0.6) x 2.
  uv = at(tcModsAt({turb, scaleMod(2, 2)}, 1.0), 0.5f, 0.5f, 256, 512, 256);
  EXPECT_NEAR(uv[0], 1.2f, 1e-6);
  EXPECT_NEAR(uv[1], 1.2f, 1e-6);
  // A scale before it does not scale the wobble: 0.5 x 2 + 0.1.
  uv = at(tcModsAt({scaleMod(2, 2), turb}, 1.0), 0.5f, 0.5f, 256, 512, 256);
  EXPECT_NEAR(uv[0], 1.1f, 1e-6);
  EXPECT_NEAR(uv[1], 1.1f, 1e-6);
}

TEST(ShaderTime, ModsComposeInScriptOrder) {
  // scale 2 1, scroll 0.5 0, rotate 90 at 1 s: (0.25, 0.5) -> (0.5, 0.5) -> (1.0, 0.5) -> (t, 1 - s) = (0.5, 0).
  const auto uv = at(tcModsAt({scaleMod(2, 1), scrollMod(0.5f, 0), rotateMod(90)}, 1.0), 0.25f, 0.5f);
  EXPECT_NEAR(uv[0], 0.5f, 1e-5);
  EXPECT_NEAR(uv[1], 0.0f, 1e-5);
  // Reversed: rotate (0.25, 0.5) -> (0.5, 0.75), scroll -> (1.0, 0.75), scale -> (2.0, 0.75).
  const auto back = at(tcModsAt({rotateMod(90), scrollMod(0.5f, 0), scaleMod(2, 1)}, 1.0), 0.25f, 0.5f);
  EXPECT_NEAR(back[0], 2.0f, 1e-5);
  EXPECT_NEAR(back[1], 0.75f, 1e-5);
}

TEST(ShaderTime, EntityTranslateScrollsByTheEntitySpeed) {
  TcMod m;
  m.kind = TcModKind::EntityTranslate;
  const auto uv = at(tcModsAt({m}, 2.0, {0.125f, 0.75f}), 0, 0);
  EXPECT_NEAR(uv[0], 0.25f, 1e-6);
  EXPECT_NEAR(uv[1], 0.5f, 1e-6);   // fraction of 1.5
}

TEST(ShaderTime, NonFiniteModsAreLeftOut) {
  const float huge = 3.0e38f;
  TcMod rotate = rotateMod(huge);
  TcMod scroll = scrollMod(std::numeric_limits<float>::infinity(), 0);
  const auto uv = at(tcModsAt({scaleMod(2, 2), rotate, scroll}, 1.0e9), 0.25f, 0.5f);
  EXPECT_TRUE(std::isfinite(uv[0]) && std::isfinite(uv[1]));
  const auto scaledOnly = at(tcModsAt({scaleMod(2, 2), scroll}, 1.0), 0.25f, 0.5f);
  EXPECT_NEAR(scaledOnly[0], 0.5f, 1e-6);
  EXPECT_NEAR(scaledOnly[1], 1.0f, 1e-6);
  EXPECT_EQ(rgbWaveAt(WaveForm{WaveFunc::Sin, std::numeric_limits<float>::quiet_NaN(), 1, 0, 1}, 1.0), 0.0f);
  EXPECT_EQ(alphaWaveAt(WaveForm{WaveFunc::Sin, 0, std::numeric_limits<float>::infinity(), 0.25f, 0}, 1.0), 0.0f);
}

TEST(ShaderTime, WhichModsAnimate) {
  EXPECT_FALSE(tcModsAnimate({scaleMod(2, 2)}));
  EXPECT_FALSE(tcModsAnimate({scrollMod(0, 0)}));
  EXPECT_TRUE(tcModsAnimate({scaleMod(2, 2), scrollMod(0.1f, 0)}));
  EXPECT_TRUE(tcModsAnimate({rotateMod(5)}));
}

TEST(ShaderTime, AnimMapFrameChoice) {
  EXPECT_EQ(animMapFrame(4, 2, 1.6), 3u);     // trunc(1.6 x 2 x 1024) = 3276, >> 10 = 3
  EXPECT_EQ(animMapFrame(4, 2, 2.0), 0u);     // 4 mod 4
  EXPECT_EQ(animMapFrame(4, 2, 0.4999), 0u);
  EXPECT_EQ(animMapFrame(4, 2, 0.5), 1u);
  EXPECT_EQ(animMapFrame(4, 2, -1.0), 0u);    // negative shader time: the first frame
  EXPECT_EQ(animMapFrame(1, 2, 5.0), 0u);
  EXPECT_EQ(animMapFrame(3, 10, 1.05), 1u);   // frame 10 of 3 -> 1
}

TEST(ShaderTime, RgbAndAlphaWaves) {
  const WaveForm pulse{WaveFunc::Sin, 0.5f, 0.5f, 0, 1};
  EXPECT_NEAR(rgbWaveAt(pulse, 0.25), 1.0f, 1e-6);
  EXPECT_NEAR(rgbWaveAt(pulse, 0.75), 0.0f, 1e-5);
  EXPECT_NEAR(rgbWaveAt(pulse, 0.25, 0.5f), 0.5f, 1e-6);   // x identityLight
  const WaveForm loud{WaveFunc::Square, 0.5f, 1, 0, 1};
  EXPECT_FLOAT_EQ(rgbWaveAt(loud, 0.1), 1.0f);              // 1.5 clamped
  EXPECT_FLOAT_EQ(rgbWaveAt(loud, 0.6), 0.0f);              // -0.5 clamped
  const WaveForm tri{WaveFunc::Triangle, 0, 1, 0, 2};
  EXPECT_FLOAT_EQ(rgbWaveAt(tri, 0.0625), 0.5f);            // cycles 0.125
  const WaveForm inv{WaveFunc::InverseSawtooth, 0, 1, 0, 1};
  EXPECT_NEAR(rgbWaveAt(inv, 0.3), 0.7001953125f, 1e-6);
  // Noise reads (time + phase) x frequency, without identityLight.
  const WaveForm noise{WaveFunc::Noise, 0.5f, 0.25f, 1, 2};
  EXPECT_NEAR(rgbWaveAt(noise, 0.5, 0.5f), std::clamp(0.5f + waveNoise(3.0) * 0.25f, 0.0f, 1.0f), 1e-6);
  const WaveForm fade{WaveFunc::Sawtooth, 0, 1, 0, 1};
  EXPECT_NEAR(alphaWaveAt(fade, 0.3), 0.2998046875f, 1e-6);
  EXPECT_FLOAT_EQ(alphaWaveAt(WaveForm{WaveFunc::Sin, 1, 1, 0, 1}, 0.25), 1.0f);
}

TEST(ShaderTime, ParsedTcModsAnimateAsScripted) {
  const auto script = parseShaderScript(
      "textures/liquids/lava {\n{\nmap textures/lava.tga\ntcMod turb 0 .25 0 .1\ntcMod scale .5 .5\ntcMod scroll .04 .03\n}\n}",
      "t.shader");
  ASSERT_EQ(script.shaders.size(), 1u);
  const auto& mods = script.shaders[0].stages[0].tcMods;
  ASSERT_EQ(mods.size(), 3u);
  EXPECT_TRUE(tcModsAnimate(mods));
  // At 10 s: wobble phase 1.0, scroll (0.4, 0.3); uv (1, 1) at the origin vertex: sin entry 0 = 0.
  const auto uv = at(tcModsAt(mods, 10.0), 1, 1, 0, 0, 0);
  EXPECT_NEAR(uv[0], 0.5f + 0.4f, 1e-5);
  EXPECT_NEAR(uv[1], 0.5f + 0.3f, 1e-5);
  // Vertex (256, 256, 0): both read 1.25 -> sin 1; the wobble 0.25 is halved by the later scale.
  const auto moved = at(tcModsAt(mods, 10.0), 1, 1, 256, 256, 0);
  EXPECT_NEAR(moved[0], 0.5f + 0.125f + 0.4f, 1e-5);
  EXPECT_NEAR(moved[1], 0.5f + 0.125f + 0.3f, 1e-5);
}

}  // namespace
}  // namespace q3

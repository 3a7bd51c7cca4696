// Models and effects: tcGen environment stages become reflection-sphere materials.
#include <gtest/gtest.h>

#include "port/engine_glue/reflection_look.h"
#include "port/q3formats/shader/shader_parser.h"

namespace glue {
namespace {

ShaderLook lookOf(const char* text) {
  const q3::ShaderScript script = q3::parseShaderScript(text, "env.shader");
  EXPECT_EQ(script.shaders.size(), 1u);
  return lookOfShader(script.shaders.at(0));
}

TEST(ReflectionLook, ChromeStageReadsTheReflectionSphere) {
  // models/powerups/holdable/medkit_base
  const ShaderLook look = lookOf(R"(models/powerups/holdable/medkit_base { { map textures/base_wall/chrome_env.jpg
    tcGen environment rgbGen lightingDiffuse tcMod scale .5 .5 } })");
  EXPECT_TRUE(look.reflectionUv);
  ASSERT_EQ(look.images.size(), 1u);
  EXPECT_EQ(look.images[0], "textures/base_wall/chrome_env.jpg");
  EXPECT_EQ(look.rgbGen, q3::RgbGen::LightingDiffuse);
  pa::MaterialDesc desc;
  applyReflectionLook(look, desc);
  EXPECT_EQ(desc.baseTexCoords, pa::TexCoordSource::ReflectionSphere);
  EXPECT_FLOAT_EQ(desc.uvTransform[0][0], 0.5f);   // s' = 0.5 s
  EXPECT_FLOAT_EQ(desc.uvTransform[1][1], 0.5f);   // t' = 0.5 t
  EXPECT_FLOAT_EQ(desc.uvTransform[0][1], 0.0f);
  EXPECT_FLOAT_EQ(desc.uvTransform[2][0], 0.0f);
  EXPECT_FLOAT_EQ(desc.specular, kReflectionSpecular);
}

TEST(ReflectionLook, TransformTcModMapsToTheUvMatrix) {
  // tcMod transform m00 m01 m10 m11 t0 t1: s' = s m00 + t m10 + t0, t' = s m01 + t m11 + t1.
  const ShaderLook look = lookOf("e { { map env.tga tcGen environment tcMod transform 1 2 3 4 5 6 } }");
  pa::MaterialDesc desc;
  applyReflectionLook(look, desc);
  const glm::vec2 uv = desc.uvTransform * glm::vec3(0.25f, 0.5f, 1.0f);
  EXPECT_FLOAT_EQ(uv.x, 0.25f * 1 + 0.5f * 3 + 5);
  EXPECT_FLOAT_EQ(uv.y, 0.25f * 2 + 0.5f * 4 + 6);
}

TEST(ReflectionLook, AdditiveChromeKeepsItsLayersAndNoGloss) {
  // Powerup glows: additive chrome over additive chrome, both layers reflect.
  const ShaderLook look = lookOf(R"(p { { map a.tga blendFunc GL_SRC_ALPHA GL_ONE tcGen environment }
    { map b.tga blendFunc GL_SRC_ALPHA GL_ONE tcGen environment } })");
  EXPECT_TRUE(look.reflectionUv);
  ASSERT_EQ(look.layers.size(), 1u);
  EXPECT_TRUE(look.layers[0].reflectionUv);
  pa::MaterialDesc desc;
  desc.alphaMode = pa::AlphaMode::Additive;
  applyReflectionLook(look, desc);
  EXPECT_EQ(desc.baseTexCoords, pa::TexCoordSource::ReflectionSphere);
  EXPECT_FLOAT_EQ(desc.specular, 0.0f);   // additive light reflects nothing
}

TEST(ReflectionLook, PlainStagesAreLeftAlone) {
  const ShaderLook look = lookOf("w { { map skin.tga rgbGen lightingDiffuse tcMod scale 2 2 } }");
  EXPECT_FALSE(look.reflectionUv);
  pa::MaterialDesc desc;
  applyReflectionLook(look, desc);
  EXPECT_EQ(desc.baseTexCoords, pa::TexCoordSource::Mesh);
  EXPECT_FLOAT_EQ(desc.uvTransform[0][0], 1.0f);
  EXPECT_FLOAT_EQ(desc.specular, 0.0f);
}

}  // namespace
}  // namespace glue
